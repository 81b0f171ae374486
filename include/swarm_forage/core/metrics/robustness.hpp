#pragma once
// The robustness measures (docs/robustness-measures.md): robustness to sensor and actuator noise (SAA) and to
// population dynamics (PD), as Harwell & Gini define them (arXiv 2012.04144), as their code computed them for
// that paper (authors_code_2020) and as their later code computes them (authors_code). ROS-free; evaluated
// against a library in robustness_evaluation.hpp.
//
// A run's noise and population rates are read from its world constants (RunInfo.world_constants): the
// `noise/...` and `population/...` words the world adds only when they are enabled. The reference of a
// measure is the run of the same identity without those words (docs/robustness-measures.md, References).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "swarm_forage/core/metrics/out_of_swarm.hpp"
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

/// The authors' performance curve (cosm's cum_avg_transported, the column their experiments compared): the
/// blocks delivered so far per tick, P at the end of sample k over the ticks so far, (k + 1) * interval.
std::vector<double> cumulativeAverage(const RunSeries& r);

// ---- SAA robustness -------------------------------------------------------------------------------

struct SaaRobustness {
  MetricValue distance;    // d = DTW(run's curve, reference's curve); lower is better
  MetricValue normalized;  // sigma(-d) - sigma(d) in (-1, 0]; higher is better
};
/// `reference` is the noise-free run (or group mean) of the same identity. Both need the same sample interval
/// and number of samples (else invalid, as reactivity). DTW with the L1 cost over points (x_k, y_k) of sample
/// k (what the authors' fastdtw call approximates; dtw.hpp):
///   paper              1-D DTW on the cumulative P values;
///   authors_code       x = k (the sample's row, as their collated tables index it), y = cumulativeAverage;
///   authors_code_2020  x = (k + 1) * interval (the tick of their "clock" column), y = cumulativeAverage;
///   authors_code_2019  invalid (their 2019 code has no robustness measure).
SaaRobustness saaRobustness(const RunSeries& reference, const RunSeries& run, Definitions defs,
                            std::optional<std::size_t> band = std::nullopt);

// ---- Population-dynamics robustness ---------------------------------------------------------------

/// The expected time [ticks] a robot spends out of the swarm as the measure takes it, the robots out of it
/// being one M/M/1 queue with lambda = death + malfunction, mu = birth + repair, over a run of T ticks:
///   paper              T_bar = 1/(mu - lambda) - 1/mu (the wait before service); invalid "no steady state"
///                      when lambda >= mu;
///   authors_code_2020  T_bar as sierra's calc_tasked_swarm_time (T - T_S): T under pure death (death > 0,
///                      birth = 0); 0 when mu - lambda or mu is 0 (their ZeroDivisionError); otherwise the
///                      paper's formula, negative when lambda > mu;
///   authors_code       W = 1/(mu - lambda) (titerra's rho^2/(1 - rho)/lambda + 1/mu, equal for lambda > 0
///   and
///                      its limit 1/mu at lambda = 0), and T under pure death as titerra; invalid "no steady
///                      state" otherwise when lambda >= mu;
///   authors_code_2019  invalid.
/// Also invalid when no rate is > 0 or T is not > 0.
MetricValue expectedTimeOut(const PopulationRates& rates, double T, Definitions defs);

struct PdRobustness {
  MetricValue time_out;    // T_bar (paper, authors_code_2020) or W (authors_code) of the run, in ticks
  double weight = 0;       // paper, authors_code_2020 (T - T_bar)/T; authors_code W_reference / W_run
  MetricValue theta;       // P(N,kappa,T) - weight * P_reference(N,kappa,T) (authors_code: both over T)
  MetricValue normalized;  // sigma(theta) - sigma(-theta) in (-1, 1); higher is better
};
/// `P`, `P_reference`: final cumulative performance of the run and of its reference, after T ticks.
/// paper, authors_code_2020: the reference is the same run without population dynamics (`reference_rates`
/// unused); authors_code: the lowest-rate run of the same batch, whose rates give W_reference, and theta on
/// the last value of the authors' curve (cumulativeAverage: P / T).
PdRobustness pdRobustness(double P, double P_reference, double T, const PopulationRates& rates,
                          const PopulationRates& reference_rates, Definitions defs);

// ---- The queue, measured --------------------------------------------------------------------------

/// How far a measured value may be off the queue's before the tables flag it: 20 %.
constexpr double kQueueTolerance = 0.2;

/// The M/M/1 queue the PD measure assumes against what the runs' population records show.
struct QueueCheck {
  // The queue's prediction (nullopt when lambda >= mu: no steady state): the time a robot is out of the
  // swarm, W = 1/(mu - lambda) (in the queue and in service), and the robots out, L = lambda/(mu - lambda).
  std::optional<double> time_out_queue, out_queue;
  // Measured (nullopt without records): the mean length of the outages that ended, the mean robots out per
  // tick, and the number of outages that ended (over the runs).
  std::optional<double> time_out_measured, out_measured;
  uint64_t outages = 0;
  /// A measured value more than kQueueTolerance off the queue's; nullopt when no pair can be compared.
  std::optional<bool> differs;
};
/// `measured`: the runs' totals (nullopt when none has a whole population record).
QueueCheck queueCheck(const PopulationRates& rates, const std::optional<OutOfSwarm>& measured);

}  // namespace swarm_forage
