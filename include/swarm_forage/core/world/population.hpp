#pragma once
// Population dynamics (docs/robustness-population.md): four Poisson processes with exponential waiting
// times -- death, birth, malfunction (into a FIFO repair queue) and repair (the queue's head rejoins) --
// as in the authors' code. The process rules live here; World carries out the events on bodies and blocks.
#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <vector>

namespace swarm_forage {

class StateArchive;

/// Rates per tick (>= 0, finite) and the most robots present at once (births are refused there).
struct PopulationConfig {
  double death = 0, birth = 0, malfunction = 0, repair = 0;
  uint32_t max_size = 0;  // 0: the swarm size

  bool enabled() const { return death > 0 || birth > 0 || malfunction > 0 || repair > 0; }
  /// Throws ParameterError naming the parameter and its valid range (`n_robots`: the swarm size).
  void validate(uint32_t n_robots) const;
  /// "population/death=... population/max_size=..." (all five) when enabled, else "".
  std::string describe(uint32_t n_robots) const;
  /// A short name for record names ("pd-d0.005-r0.004", "-max<N>" when max_size is set); "" when off.
  std::string tag() const;
};

/// Where each robot is.
enum class Presence : uint8_t { kActive = 0, kRepair = 1, kDead = 2 };

/// One tick's events (robot ids) and the counts after them.
struct PopulationEvents {
  std::vector<uint32_t> deaths, births, malfunctions, repairs;
  uint32_t active = 0, present = 0, queue = 0;
  bool any() const { return !deaths.empty() || !births.empty() || !malfunctions.empty() || !repairs.empty(); }
};

/// One Poisson process as jharwell/rcppsw include/rcppsw/ds/poisson_queue.hpp runs it: with no operation
/// scheduled, the next is drawn at last + floor(Exp(rate)) ticks; it is due while tick >= next; doing it
/// (or, for repair, passing the check) sets last = tick and unschedules. At most one operation per tick.
class PoissonClock {
 public:
  PoissonClock() = default;
  PoissonClock(double rate, uint64_t seed, uint64_t process) : rate_(rate), seed_(seed), process_(process) {}
  bool due(uint64_t tick);
  /// A live change: the next operation is drawn afresh at the new rate from the last one.
  void setRate(double rate) {
    rate_ = rate;
    scheduled_ = false;
  }
  void done(uint64_t tick) {
    last_ = tick;
    scheduled_ = false;
  }
  uint64_t next() const { return next_; }
  void persist(StateArchive& a);  // world_checkpoint.cpp

 private:
  double rate_ = 0;
  uint64_t seed_ = 0, process_ = 0;
  uint64_t last_ = 0, next_ = 0;
  bool scheduled_ = false;
};

/// The four processes over robots 0..n-1 (all active at tick 0). update() decides one tick's events in
/// the authors' order (death, birth, malfunction, repair); the caller carries them out. Victims are drawn
/// from the counter-based RNG (seed, population stream, process, tick): bit-identical for any thread count.
class PopulationDynamics {
 public:
  void reset(const PopulationConfig& config, uint32_t seed, uint32_t n_robots);
  /// Whether the run has population dynamics: fixed at reset (a live change of the rates keeps it).
  bool enabled() const { return enabled_; }
  /// A live change of the four rates (realtime mode); `rates.max_size` is ignored.
  void setRates(const PopulationConfig& rates);
  /// The rates were changed by hand (setRates) during this run.
  bool changed() const { return changed_; }
  /// `place(id, rejoin)`: puts a newly born (rejoin false) or repaired robot in the arena; false when no
  /// free spot was found: a birth then stays due (as the authors' refused operations do), a repaired robot
  /// stays at the queue's head.
  const PopulationEvents& update(uint64_t tick, const std::function<bool(uint32_t, bool)>& place);

  Presence presence(uint32_t i) const { return static_cast<Presence>(presence_[i]); }
  const std::vector<uint8_t>& activeMask() const { return active_; }  // 1: active
  const std::deque<uint32_t>& repairQueue() const { return queue_; }
  const PopulationEvents& events() const { return events_; }
  const PopulationConfig& config() const { return config_; }
  void persist(StateArchive& a);  // world_checkpoint.cpp

 private:
  /// A robot drawn uniformly (in id order) among those `among` (kActive; kRepair: the alive ones); -1 when
  /// there is none.
  int64_t victim(uint64_t tick, uint64_t process, Presence among) const;
  void setPresence(uint32_t i, Presence p);
  void count();

  PopulationConfig config_;
  uint32_t seed_ = 0, max_size_ = 0;
  bool enabled_ = false, changed_ = false;
  PoissonClock death_, birth_, malfunction_, repair_;
  std::vector<uint8_t> presence_, active_;
  std::deque<uint32_t> queue_;
  PopulationEvents events_;
};

}  // namespace swarm_forage
