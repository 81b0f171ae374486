#include "swarm_forage/core/controllers/controller_constants.hpp"

#include <yaml-cpp/yaml.h>

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

// A section's values from its YAML map (keys as the visitor names them, angles in degrees).
struct YamlReader : ConstantVisitor {
  const YAML::Node& section;
  explicit YamlReader(const YAML::Node& s) : section(s) {}
  void number(const char* n, double& v) override { v = section[n].as<double>(); }
  void count(const char* n, uint32_t& v) override { v = section[n].as<uint32_t>(); }
  void degrees(const char* n, double& radians) override { radians = deg2rad(section[n].as<double>()); }
  void choice(const char* n, bool& flag, const char*, const char* on) override {
    flag = section[n].as<std::string>() == on;
  }
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
std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}
}  // namespace

ControllerConfigs::ControllerConfigs() {
  for (const std::string& kind : controllerNames()) sections_[kind] = controllerKind(kind).constants();
}

ControllerConfigs& ControllerConfigs::operator=(const ControllerConfigs& other) {
  if (this == &other) return *this;
  sections_.clear();
  for (const auto& [kind, section] : other.sections_) sections_[kind] = section->clone();
  world = other.world;
  quirks = other.quirks;
  return *this;
}

void ControllerConfigs::validate() const {
  for (const auto& [kind, section] : sections_) section->validate();
}

ConstantSection& ControllerConfigs::section(const std::string& kind) const {
  if (const auto it = sections_.find(kind); it != sections_.end()) return *it->second;
  // A plugin loaded after these constants were made starts at its defaults; throws for an unknown kind.
  const ControllerKind& k = controllerKind(kind);
  auto& s = sections_[k.name];
  if (!s) s = k.constants();
  return *s;
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

void checkDefaultsFile(const ControllerKind& kind, const std::string& path) {
  const std::string& name = kind.name;
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const std::exception& e) {
    throw ParameterError("controller '" + name + "': its defaults " + path + " cannot be read: " + e.what());
  }
  std::vector<std::string> names;
  NameCollector collect(names);
  kind.constants()->visit(collect);
  const YAML::Node section = root.IsMap() ? root[name] : YAML::Node();
  if (!section.IsMap())
    throw ParameterError(path + " must hold the map '" + name + ":' of its constants (" + joined(names) +
                         ")");
  std::vector<std::string> in_file;
  for (const auto& entry : section) in_file.push_back(entry.first.as<std::string>());
  if (in_file != names)
    throw ParameterError(path + ": '" + name + "' lists the keys [" + joined(in_file) +
                         "]; they must be exactly the code's constants, in order: " + joined(names));
  const auto file = kind.constants(), code = kind.constants();
  YamlReader read(section);
  file->visit(read);
  std::string said, defaults;
  Describer describe_file(name + "/", said), describe_code(name + "/", defaults);
  file->visit(describe_file);
  code->visit(describe_code);
  if (said != defaults)
    throw ParameterError(path + " must hold the code defaults of '" + name + "': the file says\n  " + said +
                         "\nthe code says\n  " + defaults);
}

std::string describeConstants(const std::string& kind, ControllerConfigs configs) {
  std::string out;
  for (const std::string& k : constantSections(kind)) {
    Describer describe(k + "/", out);
    configs.visit(k, describe);
  }
  const std::string quirks = configs.quirks.controllerSide().describe();
  if (!quirks.empty()) out += (out.empty() ? "" : " ") + quirks;
  return out;
}

}  // namespace swarm_forage
