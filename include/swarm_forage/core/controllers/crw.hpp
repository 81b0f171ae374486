#pragma once
// CRW foraging: explore by correlated random walk, take the first block found to the nest by
// phototaxis, wander in the nest, drop, leave the nest, explore again (docs/design-model.md, Controllers).
#include <cstdint>
#include <string>
#include <vector>

#include "swarm_forage/core/controllers/controller_constants.hpp"
#include "swarm_forage/core/controllers/forager_batch.hpp"  // CrwConfig and the shared motion primitives

namespace swarm_forage {

enum class CrwState : uint8_t { kExplore, kPickup, kTransport, kNestWander, kDrop, kLeaveNest, kCount };
const char* crwStateName(CrwState s);

/// CRW's constants under their YAML names (config/controllers/crw.yaml).
void visitCrwParameters(CrwConfig& c, ConstantVisitor& v);

class CrwBatch : public ForagerBatch {
 public:
  CrwBatch(const CrwConfig& config, uint32_t seed, uint32_t first_id, uint32_t count);
  std::string name() const override { return "crw"; }
  void step(uint64_t tick, const SensorData& sensors, CommandData& commands,
            ControllerStatus& status) override;

  bool checkpointable() const override;

  CrwState state(uint32_t local) const { return static_cast<CrwState>(state_[local]); }

 private:
  void chooseDrives(uint32_t first, uint32_t end, uint64_t tick, const SensorData& s,
                    CommandData& out) override;

  CrwConfig config_;
};

}  // namespace swarm_forage
