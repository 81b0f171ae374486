#include "swarm_forage/core/controllers/controller_registry.hpp"

#include <map>
#include <sstream>
#include <stdexcept>

#include "swarm_forage/core/controllers/parallel_batch.hpp"

namespace swarm_forage {

namespace {
// Built on first use: registrars in other translation units run in an unspecified order. A map keeps
// the kinds sorted by name, so every list is the same whatever that order.
std::map<std::string, ControllerKind>& registry() {
  static std::map<std::string, ControllerKind> kinds;
  return kinds;
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}
}  // namespace

ControllerRegistrar::ControllerRegistrar(ControllerKind kind) {
  const std::string name = kind.name;
  if (!registry().emplace(name, std::move(kind)).second)
    throw std::logic_error("controller kind '" + name + "' is registered twice");
}

const std::vector<std::string>& controllerNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& [name, kind] : registry()) n.push_back(name);
    return n;
  }();
  return names;
}

const ControllerKind& controllerKind(const std::string& name) {
  const auto it = registry().find(name);
  if (it == registry().end())
    throw ParameterError("controller '" + name + "' is unknown; valid: " + joined(controllerNames()));
  return it->second;
}

std::vector<std::string> constantSections(const std::string& name) {
  std::vector<std::string> chain;
  for (std::string k = name; !k.empty(); k = controllerKind(k).builds_on) chain.insert(chain.begin(), k);
  return chain;
}

std::string describeControllerKinds() {
  std::ostringstream out;
  for (const std::string& name : controllerNames()) {
    const ControllerKind& k = controllerKind(name);
    out << "- name: " << k.name << "\n  display_name: \"" << k.display_name << "\"\n  colour: \"" << k.colour
        << "\"\n  constants: [" << joined(constantSections(name))
        << "]\n  line_of_sight: " << (k.line_of_sight ? "true" : "false")
        << "\n  static_cache: " << (k.static_cache ? "true" : "false") << "\n";
  }
  return out.str();
}

WorldConfig configuredFor(WorldConfig c, const std::string& controller) {
  const ControllerKind& kind = controllerKind(controller);
  c.line_of_sight = kind.line_of_sight;
  c.cache.enabled = kind.static_cache;
  return c;
}

ControllerConfigs sharingWorld(ControllerConfigs c, const Vec2& nest_center, const LineOfSight& sight) {
  c.world = WorldFacts{nest_center, sight};
  return c;
}

std::unique_ptr<ControllerBatch> makeController(const std::string& kind, const ControllerConfigs& configs,
                                                uint32_t seed, uint32_t first_id, uint32_t count,
                                                std::shared_ptr<WorkerPool> pool) {
  const ControllerKind& k = controllerKind(kind);
  if (pool != nullptr && pool->threads() > 1) {
    auto part = [&](uint32_t first, uint32_t n) { return k.make(configs, seed, first, n); };
    return std::make_unique<ParallelBatch>(part, first_id, count, std::move(pool));
  }
  return k.make(configs, seed, first_id, count);
}

}  // namespace swarm_forage
