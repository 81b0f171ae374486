#include "swarm_forage/ros/params.hpp"

#include <ros/package.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace swarm_forage {

namespace {
template <typename T>
T inRange(const std::string& name, T v, T lo, T hi) {
  if (!(v >= lo && v <= hi)) {
    std::ostringstream msg;
    msg << "~" << name << " must be in [" << lo << ", " << hi << "] (got " << v << ")";
    throw ParameterError(msg.str());
  }
  return v;
}
}  // namespace

double paramInRange(const ros::NodeHandle& pnh, const std::string& name, double fallback, double lo,
                    double hi) {
  XmlRpc::XmlRpcValue raw;
  if (!pnh.getParam(name, raw)) return inRange(name, fallback, lo, hi);
  if (raw.getType() == XmlRpc::XmlRpcValue::TypeInt) return inRange(name, double(int(raw)), lo, hi);
  if (raw.getType() == XmlRpc::XmlRpcValue::TypeDouble) return inRange(name, double(raw), lo, hi);
  throw ParameterError("~" + name + " must be a number in [" + std::to_string(lo) + ", " +
                       std::to_string(hi) + "]");
}

int paramInRange(const ros::NodeHandle& pnh, const std::string& name, int fallback, int lo, int hi) {
  XmlRpc::XmlRpcValue raw;
  if (!pnh.getParam(name, raw)) return inRange(name, fallback, lo, hi);
  if (raw.getType() == XmlRpc::XmlRpcValue::TypeInt) return inRange(name, int(raw), lo, hi);
  // YAML reads 1e9 or 64.0 as a double: say what range it must be in, not just "wrong type".
  if (raw.getType() == XmlRpc::XmlRpcValue::TypeDouble) {
    const double v = raw;
    std::ostringstream msg;
    if (!(v >= lo && v <= hi))
      msg << "~" << name << " must be in [" << lo << ", " << hi << "] (got " << v << ")";
    else if (v != std::floor(v))
      msg << "~" << name << " must be a whole number in [" << lo << ", " << hi << "] (got " << v << ")";
    else
      return static_cast<int>(v);
    throw ParameterError(msg.str());
  }
  std::ostringstream msg;
  msg << "~" << name << " has the wrong type (" << pnh.resolveName(name)
      << "): it must be a whole number in [" << lo << ", " << hi << "]";
  throw ParameterError(msg.str());
}

std::string paramOneOf(const ros::NodeHandle& pnh, const std::string& name, const std::string& fallback,
                       const std::vector<std::string>& valid) {
  const std::string v = param<std::string>(pnh, name, fallback);
  if (std::find(valid.begin(), valid.end(), v) != valid.end()) return v;
  std::string list;
  for (const auto& s : valid) list += (list.empty() ? "" : ", ") + s;
  throw ParameterError("~" + name + " '" + v + "' is not valid; valid: " + list);
}

ArenaConfig loadArena(const std::string& name_or_path) {
  namespace fs = std::filesystem;
  if (name_or_path.find('/') != std::string::npos || fs::path(name_or_path).extension() == ".yaml")
    return loadArenaYaml(name_or_path);
  const fs::path dir = fs::path(ros::package::getPath("swarm_forage")) / "config" / "arenas";
  const fs::path file = dir / (name_or_path + ".yaml");
  if (!fs::exists(file)) {
    std::vector<std::string> names;
    if (fs::is_directory(dir))
      for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ".yaml") names.push_back(e.path().stem().string());
    std::sort(names.begin(), names.end());
    std::string list;
    for (const auto& s : names) list += (list.empty() ? "" : ", ") + s;
    throw ParameterError("~arena '" + name_or_path + "' is unknown; valid: " + list +
                         " (config/arenas/*.yaml) or a path to an arena YAML file");
  }
  return loadArenaYaml(file.string());
}

}  // namespace swarm_forage
