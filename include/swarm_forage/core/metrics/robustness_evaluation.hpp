#pragma once
// The robustness measures of a run (or a group's mean) against a library (docs/robustness-measures.md): what
// the live metrics/robustness topic and the robustness tables of metrics/compute and run_tables both
// evaluate.
//
// References (the group must be in the library; otherwise the status names it):
//   SAA            the same identity without the run's noise/ words (the noise-free run). paper and
//                  authors_code_2020: the group mean curves; authors_code: runs paired by seed (their
//                  per-simulation comparison), then averaged.
//   PD, paper and authors_code_2020  the same identity without the run's population/ words (no population
//                  dynamics).
//   PD, authors_code  the lowest-rate group of the run's batch: the same identity but for the four rates, the
//                  same rates non-zero and the same max_size, with the smallest sum of rates (their exp0);
//                  runs paired by seed, then averaged.
#include <cstdint>
#include <optional>
#include <string>

#include "swarm_forage/core/metrics/robustness.hpp"
#include "swarm_forage/core/metrics/run_library.hpp"

namespace swarm_forage {

struct RobustnessEvaluation {
  RobustnessWords words;
  bool saa_applies = false, pd_applies = false;  // the run has noise / population dynamics
  Evaluated saa_status, pd_status;               // reference_size: the number of reference runs used
  std::string saa_reference, pd_reference;       // identities of the reference groups ("" when none)
  SaaRobustness saa;
  PdRobustness pd;
  QueueCheck queue;  // PD: the queue's prediction and, once final, what the library's records of the run show
  double T = 0;      // ticks: the run's length when final, else the samples so far
  double P = 0;      // the run's final (or latest) cumulative performance
  double saa_P_reference = 0, P_reference = 0;  // the same of the SAA and of the PD reference
};

/// `seed`: the run's seed when `series` is one run (live, or a row of robustness_runs.csv); nullopt for a
/// group's mean. While a run is going (`final` false) references are cut to its number of samples and T is
/// the ticks sampled so far; at the end T is the run's length (its identity's ticks).
RobustnessEvaluation evaluateRobustness(const RunLibrary& library, const RunKey& key, const RunSeries& series,
                                        std::optional<uint32_t> seed, bool final, Definitions defs,
                                        std::optional<std::size_t> band = std::nullopt);

}  // namespace swarm_forage
