#include "swarm_forage/core/controllers/controller_registry.hpp"

#include <algorithm>
#include <map>
#include <mutex>
#include <sstream>

#include "swarm_forage/core/controllers/parallel_batch.hpp"

namespace swarm_forage {

namespace {
constexpr const char* kBuiltinPackage = "swarm_forage";

// Built on first use: registrars in other translation units run in an unspecified order. A map keeps
// the kinds sorted by name, so every list is the same whatever that order; its entries never move, so
// a kind's reference stays valid while plugins are added (nodelets may look kinds up from several
// threads, hence the lock; recursive: a source's load registers while a lookup holds it).
struct Registry {
  std::recursive_mutex lock;
  std::map<std::string, ControllerKind> kinds;
  std::vector<std::shared_ptr<ControllerSource>> sources;
};
Registry& registry() {
  // Never destroyed: a plugin's kind holds code of its library, which may be unloaded at exit first.
  static Registry* r = new Registry;
  return *r;
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// Names the kind in what its batch throws: a run stopped by it says which controller and why.
class NamedBatch final : public ControllerBatch {
 public:
  NamedBatch(std::string kind, std::unique_ptr<ControllerBatch> batch)
      : kind_(std::move(kind)), batch_(std::move(batch)) {}
  std::string name() const override { return batch_->name(); }
  bool checkpointable() const override { return batch_->checkpointable(); }
  void persist(StateArchive& a) override { batch_->persist(a); }
  void step(uint64_t tick, const SensorData& sensors, CommandData& commands,
            ControllerStatus& status) override {
    try {
      batch_->step(tick, sensors, commands, status);
    } catch (const std::exception& e) {
      throw ControllerFailure("controller '" + kind_ + "' failed in step at tick " + std::to_string(tick) +
                              ": " + e.what());
    }
  }

 private:
  std::string kind_;
  std::unique_ptr<ControllerBatch> batch_;
};
}  // namespace

void registerKind(ControllerKind kind) {
  const std::string name = kind.name;
  if (name.empty() || !kind.constants || !kind.make)
    throw std::logic_error("controller kind '" + name + "' lacks a name, constants or make");
  Registry& r = registry();
  std::lock_guard<std::recursive_mutex> hold(r.lock);
  if (!r.kinds.emplace(name, std::move(kind)).second)
    throw std::logic_error("controller kind '" + name + "' is registered twice");
}

ControllerRegistrar::ControllerRegistrar(ControllerKind kind) { registerKind(std::move(kind)); }

void setControllerSource(std::shared_ptr<ControllerSource> source) {
  std::lock_guard<std::recursive_mutex> hold(registry().lock);
  registry().sources.assign(1, std::move(source));
}

void addControllerSource(std::shared_ptr<ControllerSource> source) {
  std::lock_guard<std::recursive_mutex> hold(registry().lock);
  registry().sources.push_back(std::move(source));
}

std::vector<std::string> controllerNames() {
  Registry& r = registry();
  std::lock_guard<std::recursive_mutex> hold(r.lock);
  std::vector<std::string> n;
  for (const auto& [name, kind] : r.kinds) n.push_back(name);
  return n;
}

std::vector<std::string> availableControllers() {
  Registry& r = registry();
  std::lock_guard<std::recursive_mutex> hold(r.lock);
  std::vector<std::string> n = controllerNames();
  for (const auto& source : r.sources)
    for (const std::string& name : source->names())
      if (!r.kinds.count(name) && std::find(n.begin(), n.end(), name) == n.end()) n.push_back(name);
  std::sort(n.begin(), n.end());
  return n;
}

const ControllerKind& controllerKind(const std::string& name) {
  Registry& r = registry();
  std::lock_guard<std::recursive_mutex> hold(r.lock);
  if (const auto it = r.kinds.find(name); it != r.kinds.end()) return it->second;
  const std::string builtin = std::string(kBuiltinPackage) + "/";
  if (name.compare(0, builtin.size(), builtin) == 0)
    if (const auto it = r.kinds.find(name.substr(builtin.size())); it != r.kinds.end()) return it->second;
  for (const auto& source : r.sources)
    if (source->load(name))
      if (const auto it = r.kinds.find(name); it != r.kinds.end()) return it->second;
  throw ParameterError("controller '" + name + "' is unknown; valid: " + joined(availableControllers()));
}

std::string controllerPackage(const ControllerKind& kind) {
  const auto slash = kind.name.find('/');
  return slash == std::string::npos ? kBuiltinPackage : kind.name.substr(0, slash);
}

std::vector<std::string> constantSections(const std::string& name) {
  std::vector<std::string> chain;
  for (std::string k = controllerKind(name).name; !k.empty(); k = controllerKind(k).builds_on)
    chain.insert(chain.begin(), k);
  return chain;
}

bool checkpointableKind(const std::string& name) {
  try {
    return makeController(name, ControllerConfigs(), 1, 0, 1)->checkpointable();
  } catch (const std::exception&) {
    return false;  // a batch that cannot be made at the defaults cannot be saved either
  }
}

std::string describeControllerKind(const std::string& name,
                                   const std::function<std::string(const std::string&)>& package_path) {
  std::ostringstream out;
  const ControllerKind& k = controllerKind(name);
  const std::string package = controllerPackage(k);
  out << "- name: " << k.name << "\n  display_name: \"" << k.display_name << "\"\n  colour: \"" << k.colour
      << "\"\n  constants: [" << joined(constantSections(name))
      << "]\n  line_of_sight: " << (k.line_of_sight ? "true" : "false")
      << "\n  static_cache: " << (k.static_cache ? "true" : "false")
      << "\n  light_only_carrying: " << (k.light_only_carrying ? "true" : "false")
      << "\n  checkpointable: " << (checkpointableKind(name) ? "true" : "false") << "\n  package: " << package
      << "\n  plugin: " << (k.name.find('/') != std::string::npos ? "true" : "false") << "\n  defaults: \""
      << (package_path && !k.defaults.empty() ? package_path(package) + "/" : "") << k.defaults << "\"\n";
  return out.str();
}

std::string describeControllerKinds(const std::function<std::string(const std::string&)>& package_path) {
  std::string out;
  for (const std::string& name : controllerNames()) out += describeControllerKind(name, package_path);
  return out;
}

WorldConfig configuredFor(WorldConfig c, const std::string& controller) {
  const ControllerKind& kind = controllerKind(controller);
  c.line_of_sight = kind.line_of_sight;
  c.cache.enabled = kind.static_cache;
  c.light_only_carrying = kind.light_only_carrying;
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
  auto part = [&](uint32_t first, uint32_t n) {
    std::unique_ptr<ControllerBatch> batch = k.make(configs, seed, first, n);
    if (!batch) throw std::runtime_error("its make returned no batch (a null pointer)");
    return batch;
  };
  try {
    if (pool != nullptr && pool->threads() > 1 && !k.one_thread)
      return std::make_unique<NamedBatch>(
          k.name, std::make_unique<ParallelBatch>(part, first_id, count, std::move(pool)));
    return std::make_unique<NamedBatch>(k.name, part(first_id, count));
  } catch (const ParameterError&) {
    throw;  // names "<kind>/<key>" and its range already
  } catch (const std::exception& e) {
    throw ControllerFailure("controller '" + k.name + "' failed to start: " + e.what());
  }
}

}  // namespace swarm_forage
