#pragma once
// The bootstrap over seeds (docs/metrics.md, Bootstrap): each group's runs resampled with replacement, every
// metric recomputed from the resampled means against the resampled references of the same draw, so that any
// function of several groups' metrics (a claim's margin) has a bootstrap distribution of its own.
#include <cstdint>
#include <optional>
#include <string>

#include "swarm_forage/core/metrics/run_library.hpp"

namespace swarm_forage {

struct BootstrapOptions {
  uint32_t draws = 0;  // B; 0: no bootstrap
  uint64_t seed = 1;   // draws are a pure function of (seed, group identity, draw)
};

/// bootstrap.csv: one row per draw (0 = the groups as measured, 1 ... B resampled) and valid group:
/// draw,controller,arena,waveform,beta,environment,N,runs,P,e,Z,R,A,sample_interval,identity
/// P is the group's mean final P, e is e(N1, N) against the next smaller N, Z is Z_mean; a cell is empty
/// where the metric is undefined (e and Z at the smallest N or invalid, R and A in ideal groups).
std::string bootstrapCsv(const RunLibrary& library, Definitions defs, std::optional<std::size_t> band,
                         const BootstrapOptions& options);

}  // namespace swarm_forage
