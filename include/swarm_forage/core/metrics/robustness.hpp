#pragma once
// The robustness measures (docs/robustness-measures.md): robustness to sensor and actuator noise (SAA) and to
// population dynamics (PD), as Harwell & Gini define them (arXiv 2012.04144) and as their later code computes
// them. ROS-free; evaluated against a library in robustness_evaluation.hpp.
//
// A run's noise and population rates are read from its world constants (RunInfo.world_constants): the
// `noise/...` and `population/...` words the world adds only when they are enabled. The reference of a
// measure is the run of the same identity without those words (docs/robustness-measures.md, References).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "swarm_forage/core/metrics/swarm_metrics.hpp"

namespace swarm_forage {

/// The four Poisson rates (per tick) and the population maximum of a run; all 0 when it has none.
struct PopulationRates {
  double death = 0, birth = 0, malfunction = 0, repair = 0;  // lambda_d, mu_b, lambda_m, mu_r
  uint32_t max_size = 0;
  bool enabled() const { return death > 0 || birth > 0 || malfunction > 0 || repair > 0; }
  double arrival() const { return death + malfunction; }  // lambda: robots leaving the swarm
  double service() const { return birth + repair; }       // mu: robots joining it
  /// The authors' "pure death" case (death without birth; malfunction and repair may be present).
  bool pureDeath() const { return death > 0 && birth == 0; }
  bool operator==(const PopulationRates& o) const {
    return death == o.death && birth == o.birth && malfunction == o.malfunction && repair == o.repair &&
           max_size == o.max_size;
  }
};

/// What a run's world constants say about noise and population dynamics.
struct RobustnessWords {
  std::string noise;       // its noise/ words, space-separated, in their order ("" = no noise)
  double noise_level = 0;  // the largest level over its devices (sigma, half-width or misread probability)
  PopulationRates population;
  std::string without_noise, without_population;  // the world constants without those words
  std::string problem;  // a noise/ or population/ word that cannot be read ("" = none)
};
/// Splits `world_constants` (space-separated name=value words) as above.
/// Noise words: `noise/<device>=<model>:<level>` or `noise/<device>=<level>` (ground).
/// Population words: population/death, birth, malfunction, repair, max_size.
RobustnessWords robustnessWords(const std::string& world_constants);

/// Why `defs` has no robustness measures ("" when it has them): authors_code_2019 (2019's code has none).
std::string robustnessUnavailable(Definitions defs);

/// sigma(x) - sigma(-x) with sigma the logistic function (= tanh(x / 2), computed so, without overflow).
double logisticSpread(double x);

// ---- SAA robustness -------------------------------------------------------------------------------

struct SaaRobustness {
  MetricValue distance;    // d = DTW(P(N,kappa,t), P_reference(N,kappa,t)); lower is better
  MetricValue normalized;  // sigma(-d) - sigma(d) in (-1, 0]; higher is better
};
/// `reference` is the noise-free run (or group mean) of the same identity. Both need the same sample interval
/// and number of samples (else invalid, as reactivity). paper: 1-D DTW on the cumulative P values;
/// authors_code: DTW over (tick, P) points with L1 cost (what their fastdtw call approximates; dtw.hpp);
/// authors_code_2019: invalid (their 2019 code has no robustness measure).
SaaRobustness saaRobustness(const RunSeries& reference, const RunSeries& run, Definitions defs,
                            std::optional<std::size_t> band = std::nullopt);

// ---- Population-dynamics robustness ---------------------------------------------------------------

/// The expected time [ticks] a robot spends out of the swarm, the robots out of it being one M/M/1 queue with
/// lambda = death + malfunction, mu = birth + repair, over a run of T ticks:
///   paper         T_bar = 1/(mu - lambda) - 1/mu; invalid "no steady state" when lambda >= mu;
///   authors_code  W = 1/(mu - lambda) (titerra's rho^2/(1 - rho)/lambda + 1/mu, equal for lambda > 0 and its
///                 limit 1/mu at lambda = 0), and T under pure death (death > 0, birth = 0) as titerra;
///                 invalid "no steady state" otherwise when lambda >= mu;
///   authors_code_2019 invalid.
/// Also invalid when no rate is > 0 or T is not > 0.
MetricValue expectedTimeOut(const PopulationRates& rates, double T, Definitions defs);

struct PdRobustness {
  MetricValue time_out;    // T_bar (paper) or W (authors_code) of the run, in ticks
  double weight = 0;       // paper (T - T_bar)/T; authors_code W_reference / W_run
  MetricValue theta;       // P(N,kappa,T) - weight * P_reference(N,kappa,T)
  MetricValue normalized;  // sigma(theta) - sigma(-theta) in (-1, 1); higher is better
};
/// `P`, `P_reference`: final cumulative performance of the run and of its reference, after T ticks.
/// paper: the reference is the same run without population dynamics (`reference_rates` unused);
/// authors_code: the lowest-rate run of the same batch, whose rates give W_reference.
PdRobustness pdRobustness(double P, double P_reference, double T, const PopulationRates& rates,
                          const PopulationRates& reference_rates, Definitions defs);

}  // namespace swarm_forage
