#pragma once
// The model's version: a record made by another version may differ for the same parameters and seed.
#include <cstdint>

namespace swarm_forage {

/// Bump with any change of what a run computes (world, sensing, controllers, metrics inputs): the
/// reference bags (rosbags/) are then regenerated and the change measured in docs/FIDELITY.md.
/// Version 1: the model as of issue 19 (2026-12-01).
constexpr uint32_t kModelVersion = 1;

}  // namespace swarm_forage
