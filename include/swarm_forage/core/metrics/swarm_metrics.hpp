#pragma once
// The paper's swarm metrics (docs/design-model.md, Metrics): Karp-Flatt scalability e, self-organization Z,
// reactivity R and adaptability A, plus aggregation of runs across seeds. ROS-free.
//
// Results never hold NaN or infinity. Every value sits in a MetricValue / MetricSeries whose `valid`
// says whether it could be computed; when it could not, the value is 0 and `reason` names what is
// missing (e.g. "P(N1) is 0 at every sample", "reference run has 3 samples, run has 5"). Any input
// value that is not finite makes the results depending on it invalid ("... is not finite at sample 2").
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace swarm_forage {

/// `definitions: paper | authors_code_2019 | authors_code_2020 | authors_code` (docs/design-model.md,
/// Metrics; docs/robustness-measures.md). authors_code: each measure as the authors' code computes it: e, Z,
/// R, A as their 2019 scripts (the same as authors_code_2019), the robustness measures as their later code
/// (titerra), which 2019's lacks. authors_code_2020: e, Z, R, A as authors_code, the robustness measures as
/// sierra computed them for the 2020 paper (its population-dynamics edge cases).
enum class Definitions { kPaper, kAuthorsCode2019, kAuthorsCode, kAuthorsCode2020 };
/// The valid names, for parameter checks and messages: "paper, authors_code_2019, authors_code_2020,
/// authors_code".
const std::vector<std::string>& definitionsNames();
/// One of definitionsNames(); anything else throws ParameterError listing them.
Definitions parseDefinitions(const std::string& name);
const char* definitionsName(Definitions d);
/// e, Z, R and A follow the authors' 2019 scripts (authors_code_2019 and authors_code).
inline bool authors2019Rules(Definitions d) { return d != Definitions::kPaper; }

/// One run (or the sample-by-sample mean of several), one entry per sample interval.
struct RunSeries {
  uint32_t swarm_size = 0;   // N
  uint32_t interval = 0;     // sample interval [ticks]; sample i ends at tick (i + 1) * interval
  std::vector<double> P;     // P(N,t): blocks delivered by the end of the sample (cumulative)
  std::vector<double> p;     // p(N,t): blocks delivered within the sample
  std::vector<double> n_ca;  // n_ca(N,t): mean robots in collision avoidance per tick of the sample
  std::vector<double> s;     // s(t) = 1 - mean V over the sample's ticks (speed condition; > 1 = boost)
};

struct MetricValue {
  double value = 0.0;
  bool valid = false;
  std::string reason;  // empty when valid
};

struct MetricSeries {
  std::vector<double> value;  // 0 where a sample is invalid
  std::vector<bool> sample_valid;
  bool valid = false;  // true iff there is at least one sample and every sample is valid
  std::string reason;  // what made samples invalid, e.g. "P(N1) is 0 at 2 of 5 samples"
};

// ---- Aggregation across runs (seeds) --------------------------------------------------------------

/// Two-sided 95 % Student t critical value t(0.975, dof); dof >= 1 (0 returns 0).
double studentT95(uint32_t dof);

struct SeriesStats {
  std::vector<double> mean;
  std::vector<double> ci95;  // half-width: t(0.975, R - 1) * sample sd / sqrt(R); 0 when R = 1
  std::size_t runs = 0;      // R
  bool truncated = false;    // the series differed in length; only the common prefix is used
  std::size_t longest = 0;   // longest input series
};
/// Sample-by-sample mean and 95 % CI half-width over the common prefix of `series`.
/// No series -> empty result (runs = 0).
SeriesStats aggregateSeries(const std::vector<std::vector<double>>& series);

struct AggregatedRuns {
  RunSeries mean;  // swarm_size and interval of the runs; each of P, p, n_ca, s averaged
  RunSeries ci95;  // the same fields holding CI half-widths
  std::size_t runs = 0;
  bool valid = false;  // false: no runs, or runs of different swarm sizes or sample intervals
  std::string reason;
  bool truncated = false;  // some field had runs of unequal length; it was cut to the common prefix
  std::string note;        // e.g. "P: runs have 4 to 5 samples, using the common 4"
};
AggregatedRuns aggregateRuns(const std::vector<RunSeries>& runs);
/// The same over `count` runs held elsewhere (no copies: the bootstrap aggregates a draw per group).
AggregatedRuns aggregateRuns(const RunSeries* const* runs, std::size_t count);

// ---- Scalability (paper Eqs 1-2) ------------------------------------------------------------------

/// phi = P2 / ((N2 / N1) P1). Invalid when P1 = 0 ("P(N1) is 0"), N1 = 0 or N2 <= N1.
MetricValue karpFlattPhi(double P1, double P2, uint32_t n1, uint32_t n2);
/// e = (1/phi - 1/n) / (1 - 1/n). Invalid when n < 2 (0/0 form) or phi = 0 (e unbounded).
MetricValue karpFlattE(double phi, uint32_t n);

struct Scalability {
  uint32_t n1 = 0, n2 = 0;
  /// The N in e's formula: N1 in paper mode with N1 > 1; N2 when N1 = 1 (the paper's formula is 0/0
  /// there; the authors' implementation uses N2) and always in authors_code_2019 mode.
  uint32_t n_used = 0;
  MetricValue phi, e;       // from the final samples P(N1,T), P(N2,T)
  MetricSeries phi_t, e_t;  // per sample: phi(t) = P(N2,t) / ((N2/N1) P(N1,t)), e(t) from phi(t)
  std::string note;         // says when N2 replaced N1
};
/// Both runs must have the same number of samples (else every field is invalid:
/// "N1 run has 3 samples, N2 run has 5"); no samples -> invalid "no samples".
/// phi is the ratio of cumulative counts, so the paper's sum over t in T is the count at T; the final
/// value is therefore identical in both modes, which differ only in n_used.
Scalability scalability(const RunSeries& run_n1, const RunSeries& run_n2,
                        Definitions defs = Definitions::kPaper);

// ---- Self-organization (paper Eqs 3-5) ------------------------------------------------------------

/// t_lost^N(t) = n_ca(N,t) / N. Invalid when N = 0 or there are no samples.
MetricSeries tLost(const RunSeries& run);
/// P_lost(1,t) = p(1,t) t_lost^1(t) when run.swarm_size = 1, else
/// P_lost(N,t) = p(N,t) t_lost^N(t) - N P_lost(1,t) (0 for N robots that do not interact).
/// `single` must be a 1-robot run with as many samples as `run`. Zero performance gives 0.
MetricSeries pLost(const RunSeries& single, const RunSeries& run);

struct SelfOrganization {
  uint32_t m_prev = 0, m_cur = 0;  // m_(i-1), m_i
  /// paper: P_lost per sample; authors_code_2019: one value, the whole-run fractional loss
  /// PL(N) = (n_ca(N) - N n_ca(1)) / N with n_ca the mean over all samples (PL(1) = 0).
  MetricSeries p_lost_prev, p_lost_cur;
  /// theta_Z(m_i,t) = P_lost(m_i,t) - (m_i/m_(i-1)) P_lost(m_(i-1),t) (authors: one value from PL).
  MetricSeries theta;
  /// paper: z_sum = sum_t [1 - 1/(1 + e^-theta)] (the paper's Z), z_mean = z_sum / samples, in (0,1)
  /// mathematically ([0,1] in floating point for |theta| > ~37); zero performance gives 0.5 per sample.
  /// authors_code_2019: z_sum = z_mean = 1 - e^theta on the final values (<= 1, can be negative;
  /// invalid if e^theta overflows).
  MetricValue z_sum, z_mean;
};
/// Needs 1 <= m_(i-1) < m_i, `single` of 1 robot (it may be `prev` itself) and the same number of
/// samples in all three runs; otherwise everything is invalid with the reason.
SelfOrganization selfOrganization(const RunSeries& single, const RunSeries& prev, const RunSeries& cur,
                                  Definitions defs = Definitions::kPaper);

// ---- Reactivity and adaptability (paper Eqs 6-10) -------------------------------------------------

/// Q(X, a, b) = (b - a)(X - min X)/(max X - min X) + a; a constant X maps every sample to (a + b)/2.
/// Empty X -> empty result. Inputs are assumed finite.
std::vector<double> minMaxMap(const std::vector<double>& x, double a, double b);
/// P_R*(t) = Q(s(t), min P_ideal, max P_ideal); empty when either input is empty.
std::vector<double> reactivityIdeal(const std::vector<double>& s, const std::vector<double>& p_ideal);
/// P_A*(t) = P_ideal(t) s(t) where s(t) > 1, else P_ideal(t), over the common prefix of both inputs.
std::vector<double> adaptabilityIdeal(const std::vector<double>& s, const std::vector<double>& p_ideal);

struct Flexibility {
  MetricValue distance;       // R or A: DTW(ideal curve, p(N,t)); lower is better
  std::vector<double> ideal;  // P_R* or P_A* (empty when invalid)
};
/// `ideal` is the same swarm under ideal conditions (V = 0): its p is P_ideal. `run` supplies p and s.
/// Invalid (distance 0, ideal empty) when: a run has no samples ("run has no samples"); the runs
/// differ in swarm size, sample interval or number of samples ("reference run has 3 samples, run has
/// 5"); run.s and run.p differ in length; a value is not finite. Zero performance is valid.
/// paper: 1-D DTW on values. authors_code_2019: DTW over (tick, value) points with L1 cost, the tick of
/// sample i being (i + 1) * interval for both curves (see dtwTimeValue). The ideal curves are the same
/// in both modes. `band`: optional Sakoe-Chiba band in samples (see dtw.hpp).
Flexibility reactivity(const RunSeries& ideal, const RunSeries& run, Definitions defs = Definitions::kPaper,
                       std::optional<std::size_t> band = std::nullopt);
Flexibility adaptability(const RunSeries& ideal, const RunSeries& run, Definitions defs = Definitions::kPaper,
                         std::optional<std::size_t> band = std::nullopt);

}  // namespace swarm_forage
