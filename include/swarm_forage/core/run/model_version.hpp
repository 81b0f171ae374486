#pragma once
// The model's version: a record made by another version may differ for the same parameters and seed.
#include <cstdint>

namespace swarm_forage {

/// Bump with any change of what a run computes (world, sensing, controllers, metrics inputs): the
/// reference bags (rosbags/) are then regenerated and the change measured in docs/FIDELITY.md.
/// Version 1: the first versioned model. Version 2: fordyca_2019 the default model (rosbags/ as committed
/// with it); the same bits per model as version 1.
constexpr uint32_t kModelVersion = 2;

}  // namespace swarm_forage
