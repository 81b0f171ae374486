#pragma once
// The robots out of the swarm as a run's population record shows them (world/population, every tick of a run
// with population dynamics): what the queue behind the population-dynamics robustness predicts, measured
// (docs/robustness-measures.md, The queue, measured). ROS-free.
#include <cstdint>
#include <optional>
#include <vector>

namespace swarm_forage {

struct PopulationRecord;  // core/run/run_records.hpp, which needs the run library (this header's includer)

/// Totals over one run's ticks, or over a group's runs (add).
struct OutOfSwarm {
  uint64_t ticks = 0;       // ticks recorded
  double robot_ticks = 0;   // sum over those ticks of the robots out of the swarm (max_size - active)
  uint64_t returns = 0;     // outages that ended within the run: a robot's id born again, or repaired
  double return_ticks = 0;  // their lengths summed [ticks]: from the tick it left to the tick it came back
  uint64_t open = 0;        // outages still going at the end of the run (not among the returns)
  void add(const OutOfSwarm& o);
  /// Mean robots out of the swarm per tick; nullopt without ticks.
  std::optional<double> meanOut() const;
  /// Mean length of the outages that ended [ticks]; nullopt when none did (death only, say).
  std::optional<double> meanTimeOut() const;
  bool operator==(const OutOfSwarm& o) const;
};

/// Counts one run's population records, tick by tick from tick 0. Within a tick the events are taken in the
/// world's order (deaths, births, malfunctions, repairs), so a robot that dies and is born again in the same
/// tick was out for 0 ticks. A robot awaiting repair that dies stays out until its id is born again.
class OutOfSwarmCounter {
 public:
  void add(const PopulationRecord& p);
  /// The totals when the records covered ticks 0 to `ticks` - 1, each once and in order; nullopt otherwise
  /// (a run followed from a later tick, a tick missing).
  std::optional<OutOfSwarm> totals(uint64_t ticks) const;

 private:
  OutOfSwarm totals_;
  std::vector<int64_t> left_;  // per robot id: the tick it left the swarm, -1 while in it
  uint64_t next_tick_ = 0;
  bool broken_ = false;
};

}  // namespace swarm_forage
