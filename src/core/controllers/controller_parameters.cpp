#include "swarm_forage/core/controllers/controller_parameters.hpp"

namespace swarm_forage {

namespace {
struct NameCollector {
  std::vector<std::string>& names;
  template <typename T>
  void number(const char* n, T&) {
    names.emplace_back(n);
  }
  template <typename T>
  void count(const char* n, T&) {
    names.emplace_back(n);
  }
  void degrees(const char* n, double&) { names.emplace_back(n); }
  void choice(const char* n, bool&, const char*, const char*) { names.emplace_back(n); }
};

struct Describer {
  std::string prefix;
  std::string& out;
  void add(const char* n, const std::string& v) { out += (out.empty() ? "" : " ") + prefix + n + "=" + v; }
  void number(const char* n, double& v) { add(n, canonicalNumber(v)); }
  void count(const char* n, uint32_t& v) { add(n, std::to_string(v)); }
  void degrees(const char* n, double& radians) { add(n, canonicalNumber(radians * 180.0 / kPi)); }
  void choice(const char* n, bool& flag, const char* off, const char* on) { add(n, flag ? on : off); }
};
}  // namespace

const std::vector<std::string>& parameterSections() {
  static const std::vector<std::string> sections{"crw", "dpo", "gp_dpo"};
  return sections;
}

std::vector<std::string> parameterNames(const std::string& section) {
  std::vector<std::string> names;
  ControllerConfigs c;
  if (section == "crw") visitCrwParameters(c.crw, NameCollector{names});
  if (section == "dpo") visitDpoParameters(c.dpo, NameCollector{names});
  if (section == "gp_dpo") visitGpDpoParameters(c.gp_dpo, NameCollector{names});
  return names;
}

std::string describeConstants(const std::string& kind, ControllerConfigs c) {
  // DPO explores with crw's constants and GP-DPO's tasks are DPO's: the ROS layer keeps the copies equal.
  std::string out;
  visitCrwParameters(c.crw, Describer{"crw/", out});
  if (kind == "dpo" || kind == "gp_dpo") visitDpoParameters(c.dpo, Describer{"dpo/", out});
  if (kind == "gp_dpo") visitGpDpoParameters(c.gp_dpo, Describer{"gp_dpo/", out});
  return out;
}

}  // namespace swarm_forage
