#include "swarm_forage/ros/params/params.hpp"

#include <ros/package.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <type_traits>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/run/condition.hpp"
#include "swarm_forage/core/util/worker_pool.hpp"
#include "swarm_forage/ros/params/known_params.hpp"

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
// Reads a config from ~<section>/<name> through the core's parameter lists (defaults: the core's, which
// equal the YAML files); validate() then names the field and its range. Angles are read in degrees.
struct Reader : ConstantVisitor {
  const ParamSource& p;
  std::string prefix;
  Reader(const ParamSource& source, std::string section) : p(source), prefix(std::move(section)) {}
  void number(const char* name, double& v) override { v = param<double>(p, prefix + name, v); }
  void count(const char* name, uint32_t& v) override {
    v = static_cast<uint32_t>(paramInRange(p, prefix + name, static_cast<int>(v), 0, 2147483647));
  }
  void degrees(const char* name, double& radians) override {
    radians = deg2rad(param<double>(p, prefix + name, radians * 180.0 / kPi));
  }
  void choice(const char* name, bool& flag, const char* off, const char* on) override {
    flag = paramOneOf(p, prefix + name, flag ? on : off, {off, on}) == on;
  }
};

/// A typo in a controller YAML (`widht`, `wander_forse`) would otherwise leave a default in force unseen.
void rejectUnknownKeys(const ParamSource& p) {
  for (const std::string& section : controllerNames()) {
    XmlRpc::XmlRpcValue values;
    if (!p.get(section, values)) continue;
    const std::vector<std::string> valid = parameterNames(section);
    std::string list;
    for (const auto& n : valid) list += (list.empty() ? "" : ", ") + n;
    if (values.getType() != XmlRpc::XmlRpcValue::TypeStruct)
      throw ParameterError("~" + section + " must be a map of " + section + " constants (" + list + ")");
    for (auto it = values.begin(); it != values.end(); ++it)
      if (std::find(valid.begin(), valid.end(), it->first) == valid.end())
        throw ParameterError("~" + section + "/" + it->first + " is not a " + section +
                             " constant (a typo in " + controllerKind(section).defaults +
                             "?); valid keys: " + list);
  }
}

}  // namespace

bool NodeParams::get(const std::string& name, XmlRpc::XmlRpcValue& value) const {
  return pnh_.getParam(name, value);
}

namespace {
/// A YAML scalar as rosparam sets it: an int, a double, a bool, else the text.
XmlRpc::XmlRpcValue scalarValue(const YAML::Node& node, const std::string& text) {
  int i = 0;
  double d = 0;
  bool b = false;
  const bool plain = node.IsScalar() && node.Tag() == "?";
  if (plain && YAML::convert<int>::decode(node, i)) return XmlRpc::XmlRpcValue(i);
  if (plain && YAML::convert<double>::decode(node, d)) return XmlRpc::XmlRpcValue(d);
  if (plain && YAML::convert<bool>::decode(node, b)) return XmlRpc::XmlRpcValue(b);
  return XmlRpc::XmlRpcValue(text);
}
}  // namespace

WordParams::WordParams(const std::vector<std::string>& words) {
  root_ = XmlRpc::XmlRpcValue();
  root_.begin();  // an empty struct
  for (const std::string& w : words) {
    const auto eq = w.find(":=");
    if (eq == std::string::npos || eq == 0)
      throw ParameterError("'" + w + "' is not a parameter: give name:=value (e.g. n_robots:=64)");
    const std::string name = w.substr(0, eq), text = w.substr(eq + 2);
    // Names whose values are text however they read: an identity of eight digits is not a number.
    static const std::vector<std::string> kText{"expect_identity", "label"};
    const bool literal = std::find(kText.begin(), kText.end(), name) != kText.end();
    const XmlRpc::XmlRpcValue v =
        literal ? XmlRpc::XmlRpcValue(text) : scalarValue(YAML::Load(text.empty() ? "''" : text), text);
    XmlRpc::XmlRpcValue* at = &root_;
    std::stringstream parts(name);
    std::vector<std::string> path;
    for (std::string part; std::getline(parts, part, '/');) path.push_back(part);
    for (std::size_t k = 0; k + 1 < path.size(); ++k) {
      if (at->hasMember(path[k]) && (*at)[path[k]].getType() != XmlRpc::XmlRpcValue::TypeStruct)
        throw ParameterError(name + ":= conflicts with " + path[k] + ":=");
      at = &(*at)[path[k]];
      if (at->getType() != XmlRpc::XmlRpcValue::TypeStruct) at->begin();
    }
    (*at)[path.back()] = v;
    names_.push_back(name);
  }
}

bool WordParams::get(const std::string& name, XmlRpc::XmlRpcValue& value) const {
  XmlRpc::XmlRpcValue at = root_;
  std::stringstream parts(name);
  for (std::string part; std::getline(parts, part, '/');) {
    if (at.getType() != XmlRpc::XmlRpcValue::TypeStruct || !at.hasMember(part)) return false;
    XmlRpc::XmlRpcValue next = at[part];
    at = next;
  }
  value = at;
  return true;
}

std::vector<std::string> WordParams::unknown(const std::vector<std::string>& valid) const {
  return unknownNames(names_, valid);
}

void WordParams::accepts(const ParamUsage& u) const {
  for (const ParamUsage& seen : usage_)
    if (seen.name == u.name) return;
  usage_.push_back(u);
}

std::string usageTable(const std::vector<ParamUsage>& usage) {
  std::size_t name_width = 4, fallback_width = 7;
  for (const ParamUsage& u : usage) {
    name_width = std::max(name_width, u.name.size());
    fallback_width = std::max(fallback_width, u.fallback.size());
  }
  const auto row = [&](const std::string& name, const std::string& fallback, const std::string& valid) {
    return "  " + name + std::string(name_width + 2 - name.size(), ' ') + fallback +
           std::string(fallback_width + 2 - fallback.size(), ' ') + valid + "\n";
  };
  std::string out = row("NAME", "DEFAULT", "VALID");
  for (const ParamUsage& u : usage) {
    out += row(u.name, u.fallback, u.valid);
    if (!u.doc.empty()) out += std::string(name_width + 6, ' ') + u.doc + "\n";
  }
  return out;
}

double valueInRange(const std::string& name, double value, double lo, double hi) {
  return inRange(name, value, lo, hi);
}

namespace {
template <typename T>
std::string text(const T& v) {
  std::ostringstream out;
  if constexpr (std::is_same_v<T, bool>)
    out << (v ? "true" : "false");
  else if constexpr (std::is_same_v<T, std::string>)
    out << (v.empty() ? "''" : v);
  else
    out << v;
  return out.str();
}

template <typename T>
std::string range(T lo, T hi) {
  return "[" + text(lo) + ", " + text(hi) + "]";
}

/// A wrong-typed value as given, with its kind: "the text 'abc'", "the list [...]".
std::string given(const XmlRpc::XmlRpcValue& raw) {
  using X = XmlRpc::XmlRpcValue;
  XmlRpc::XmlRpcValue copy = raw;
  switch (raw.getType()) {
    case X::TypeString:
      return "the text '" + std::string(copy) + "'";
    case X::TypeBoolean:
      return std::string("the truth value ") + (bool(copy) ? "true" : "false");
    case X::TypeInt:
      return "the whole number " + std::to_string(int(copy));
    case X::TypeDouble:
      return "the number " + text(double(copy));
    case X::TypeArray:
      return "a list of " + std::to_string(copy.size());
    case X::TypeStruct:
      return "a map";
    default:
      return "a value of another type";
  }
}

ParameterError wrongType(const ParamSource& p, const std::string& name, const XmlRpc::XmlRpcValue& raw,
                         const std::string& valid) {
  return ParameterError("~" + name + " has the wrong type: got " + given(raw) + " (" + p.resolve(name) +
                        "); valid: " + valid);
}

template <typename T>
const char* kind() {
  if constexpr (std::is_same_v<T, bool>) return "true or false";
  if constexpr (std::is_same_v<T, int>) return "a whole number";
  if constexpr (std::is_same_v<T, double>) return "a number";
  return "text";
}
}  // namespace

template <typename T>
T param(const ParamSource& p, const std::string& name, const T& fallback) {
  p.accepts({name, text(fallback), kind<T>(), ""});
  XmlRpc::XmlRpcValue raw;
  if (!p.get(name, raw)) return fallback;
  using X = XmlRpc::XmlRpcValue;
  if constexpr (std::is_same_v<T, bool>) {
    if (raw.getType() == X::TypeBoolean) return bool(raw);
  } else if constexpr (std::is_same_v<T, int>) {
    if (raw.getType() == X::TypeInt) return int(raw);
  } else if constexpr (std::is_same_v<T, double>) {
    if (raw.getType() == X::TypeDouble) return double(raw);
    if (raw.getType() == X::TypeInt) return double(int(raw));
  } else {
    static_assert(std::is_same_v<T, std::string>);
    if (raw.getType() == X::TypeString) return std::string(raw);
  }
  throw wrongType(p, name, raw, kind<T>());
}
template bool param<bool>(const ParamSource&, const std::string&, const bool&);
template int param<int>(const ParamSource&, const std::string&, const int&);
template double param<double>(const ParamSource&, const std::string&, const double&);
template std::string param<std::string>(const ParamSource&, const std::string&, const std::string&);

double paramInRange(const ParamSource& p, const std::string& name, double fallback, double lo, double hi) {
  const std::string valid = "a number in " + range(lo, hi);
  p.accepts({name, text(fallback), valid, ""});
  XmlRpc::XmlRpcValue raw;
  if (!p.get(name, raw)) return inRange(name, fallback, lo, hi);
  if (raw.getType() == XmlRpc::XmlRpcValue::TypeInt) return inRange(name, double(int(raw)), lo, hi);
  if (raw.getType() == XmlRpc::XmlRpcValue::TypeDouble) return inRange(name, double(raw), lo, hi);
  throw wrongType(p, name, raw, valid);
}

int paramInRange(const ParamSource& p, const std::string& name, int fallback, int lo, int hi) {
  const std::string valid = "a whole number in " + range(lo, hi);
  p.accepts({name, text(fallback), valid, ""});
  XmlRpc::XmlRpcValue raw;
  if (!p.get(name, raw)) return inRange(name, fallback, lo, hi);
  if (raw.getType() == XmlRpc::XmlRpcValue::TypeInt) return inRange(name, int(raw), lo, hi);
  // YAML reads 1e9 or 64.0 as a double: say what range it must be in, not just "wrong type".
  if (raw.getType() == XmlRpc::XmlRpcValue::TypeDouble) {
    const double v = raw;
    std::ostringstream msg;
    if (!(v >= lo && v <= hi))
      msg << "~" << name << " must be in " << range(lo, hi) << " (got " << v << ")";
    else if (v != std::floor(v))
      msg << "~" << name << " must be " << valid << " (got " << v << ")";
    else
      return static_cast<int>(v);
    throw ParameterError(msg.str());
  }
  throw wrongType(p, name, raw, valid);
}

std::string paramOneOf(const ParamSource& p, const std::string& name, const std::string& fallback,
                       const std::vector<std::string>& valid) {
  const std::string list = joinNames(valid);
  p.accepts({name, text(fallback), "one of " + list, ""});
  XmlRpc::XmlRpcValue raw;
  if (!p.get(name, raw)) return fallback;
  if (raw.getType() != XmlRpc::XmlRpcValue::TypeString) throw wrongType(p, name, raw, "one of " + list);
  const std::string v = raw;
  if (std::find(valid.begin(), valid.end(), v) != valid.end()) return v;
  throw ParameterError("~" + name + " '" + v + "' is not valid; valid: " + list);
}

FordycaQuirks readQuirks(const ParamSource& p) {
  const std::string model = readParam<std::string>(p, "model");
  const std::string valid = quirkNames();
  const ParamSpec& quirks = paramSpec("quirks");
  p.accepts({"quirks", fallbackText(quirks), validText(quirks), quirks.doc});
  XmlRpc::XmlRpcValue raw;
  std::string extra;
  if (p.get("quirks", raw)) {
    if (raw.getType() == XmlRpc::XmlRpcValue::TypeString) {
      extra = static_cast<std::string>(raw);
    } else if (raw.getType() == XmlRpc::XmlRpcValue::TypeArray) {  // a YAML list works too
      for (int i = 0; i < raw.size(); ++i) {
        if (raw[i].getType() != XmlRpc::XmlRpcValue::TypeString)
          throw ParameterError("~quirks must be quirk names (comma-separated or a list); valid: " + valid);
        extra += (extra.empty() ? "" : ",") + static_cast<std::string>(raw[i]);
      }
    } else {
      throw ParameterError("~quirks must be quirk names (comma-separated or a list); valid: " + valid);
    }
  }
  return FordycaQuirks::parse(model, extra);
}

WorldConfig readWorldConfig(const ParamSource& p) {
  WorldConfig c;  // defaults and ranges: the parameter table's (param_table.cpp), equal to the core's
  c.arena = loadArena(readParam<std::string>(p, "arena"));
  c.n_robots = static_cast<uint32_t>(readParam<int>(p, "n_robots"));
  c.seed = static_cast<uint32_t>(readParam<int>(p, "seed"));
  c.ticks_per_second = readParam<double>(p, "ticks_per_second");
  c.cache.size_fraction = readParam<double>(p, "cache/size_fraction");
  c.cache.block_fraction = readParam<double>(p, "cache/block_fraction");
  c.cache.min_blocks = static_cast<uint32_t>(readParam<int>(p, "cache/min_blocks"));
  c.cache.recreation_rate = readParam<double>(p, "cache/recreation_rate");
  c.sight.cell = readParam<double>(p, "los_cell");
  c.sight.radius = readParam<int>(p, "los_radius");
  c.serialize_block_ops = readParam<bool>(p, "serialize_block_ops");
  // Population dynamics: rates per tick (docs/robustness-population.md); WorldConfig::validate checks
  // max_size against the swarm size.
  c.population.death = readParam<double>(p, "population/death");
  c.population.birth = readParam<double>(p, "population/birth");
  c.population.malfunction = readParam<double>(p, "population/malfunction");
  c.population.repair = readParam<double>(p, "population/repair");
  c.population.max_size = static_cast<uint32_t>(readParam<int>(p, "population/max_size"));
  c.noise = readNoise(p);
  c.quirks = readQuirks(p);
  return c;
}

unsigned readThreads(const ParamSource& p) {
  const int threads = readParam<int>(p, "threads");
  return threads == 0 ? WorkerPool::cores() : static_cast<unsigned>(threads);
}

std::string paramController(const ParamSource& p, const std::string& external) {
  const ParamSpec& s = paramSpec("controller");
  const std::string valid = validText(s);
  p.accepts({"controller", fallbackText(s), valid, s.doc});
  XmlRpc::XmlRpcValue raw;
  if (!p.get("controller", raw)) return s.fallback;
  if (raw.getType() != XmlRpc::XmlRpcValue::TypeString) throw wrongType(p, "controller", raw, valid);
  if (!external.empty() && static_cast<std::string>(raw) == external)
    return external;  // served by other nodes
  try {
    return controllerKind(static_cast<std::string>(raw)).name;
  } catch (const ParameterError& e) {
    throw ParameterError("~controller: " + std::string(e.what()));
  }
}

void putControllerDefaults(const ros::NodeHandle& pnh, const std::string& kind) {
  for (const std::string& section : constantSections(kind)) {
    const ControllerKind& k = controllerKind(section);
    const std::string file = ros::package::getPath(controllerPackage(k)) + "/" + k.defaults;
    for (const auto& entry : YAML::LoadFile(file)[section]) {
      const std::string name = section + "/" + entry.first.as<std::string>();
      if (!pnh.hasParam(name)) pnh.setParam(name, scalarValue(entry.second, entry.second.Scalar()));
    }
  }
}

ControllerConfigs readControllerConfigs(const ParamSource& p) {
  rejectUnknownKeys(p);
  ControllerConfigs c;
  for (const std::string& kind : controllerNames()) {
    Reader read(p, kind + "/");
    c.visit(kind, read);
  }
  c.quirks = readQuirks(p);
  try {
    c.validate();
  } catch (const ParameterError& e) {
    throw ParameterError("~" + std::string(e.what()));  // core messages name the YAML key
  }
  return c;
}

}  // namespace swarm_forage
