#include "swarm_forage/core/controllers/controller_constants.hpp"

#include <algorithm>
#include <stdexcept>

#include "swarm_forage/core/controllers/controller_registry.hpp"

namespace swarm_forage {

namespace {
struct NameCollector : ConstantVisitor {
  std::vector<std::string>& names;
  explicit NameCollector(std::vector<std::string>& n) : names(n) {}
  void number(const char* n, double&) override { names.emplace_back(n); }
  void count(const char* n, uint32_t&) override { names.emplace_back(n); }
  void degrees(const char* n, double&) override { names.emplace_back(n); }
  void choice(const char* n, bool&, const char*, const char*) override { names.emplace_back(n); }
};

struct Describer : ConstantVisitor {
  std::string prefix;
  std::string& out;
  Describer(std::string p, std::string& o) : prefix(std::move(p)), out(o) {}
  void add(const char* n, const std::string& v) { out += (out.empty() ? "" : " ") + prefix + n + "=" + v; }
  void number(const char* n, double& v) override { add(n, canonicalNumber(v)); }
  void count(const char* n, uint32_t& v) override { add(n, std::to_string(v)); }
  void degrees(const char* n, double& radians) override { add(n, canonicalNumber(radians * 180.0 / kPi)); }
  void choice(const char* n, bool& flag, const char* off, const char* on) override {
    add(n, flag ? on : off);
  }
};
}  // namespace

ControllerConfigs::ControllerConfigs() {
  for (const std::string& kind : controllerNames()) sections_[kind] = controllerKind(kind).constants();
}

ControllerConfigs& ControllerConfigs::operator=(const ControllerConfigs& other) {
  if (this == &other) return *this;
  sections_.clear();
  for (const auto& [kind, section] : other.sections_) sections_[kind] = section->clone();
  world = other.world;
  return *this;
}

void ControllerConfigs::validate() const {
  for (const auto& [kind, section] : sections_) section->validate();
}

ConstantSection& ControllerConfigs::section(const std::string& kind) const {
  const auto it = sections_.find(kind);
  if (it != sections_.end()) return *it->second;
  controllerKind(kind);  // throws, naming the valid kinds
  throw std::logic_error("controller '" + kind + "' was registered after these constants were made");
}

void ControllerConfigs::wrongType(const std::string& kind) {
  throw std::logic_error("ControllerConfigs::of: not the constants type of controller '" + kind + "'");
}

std::vector<std::string> parameterNames(const std::string& kind) {
  std::vector<std::string> names;
  const auto& all = controllerNames();
  if (std::find(all.begin(), all.end(), kind) == all.end()) return names;
  NameCollector collect(names);
  controllerKind(kind).constants()->visit(collect);
  return names;
}

std::string describeConstants(const std::string& kind, ControllerConfigs configs) {
  std::string out;
  for (const std::string& k : constantSections(kind)) {
    Describer describe(k + "/", out);
    configs.visit(k, describe);
  }
  return out;
}

}  // namespace swarm_forage
