#pragma once
// Recorded runs as library entries: a bag written by world_node (world/run_info, world/performance,
// swarm/status, under any namespace) read back into a run's series.
#include <swarm_forage/RunInfo.h>

#include <ctime>
#include <map>
#include <string>
#include <vector>

#include "swarm_forage/core/metrics/run_library.hpp"

namespace swarm_forage {

/// The library key (identity) of a run whose series are cut at `interval` ticks per sample.
RunKey runKey(const RunInfo& info, uint32_t interval);

/// Reads one run; throws std::runtime_error saying what is wrong (unreadable, no run_info, no
/// world/run_end or one marking the run incomplete, a tick without performance or status, a run that
/// stops before its last tick).
RunRecord readRunBag(const std::string& path, uint32_t interval);

/// Reads the *.bag files of a directory, each once (again only when its size or time changes).
class RunBagCache {
 public:
  explicit RunBagCache(uint32_t interval) : interval_(interval) {}
  struct Scan {
    std::vector<const RunRecord*> runs;
    std::vector<std::string> problems;    // "PATH: why it cannot be used"
    std::vector<std::string> unfinished;  // *.bag.<pid>.active: being written, or its writer was killed
  };
  uint32_t interval() const { return interval_; }
  /// Throws std::runtime_error when `directory` cannot be listed.
  Scan scan(const std::string& directory);

 private:
  struct Entry {
    std::time_t mtime = 0;
    uintmax_t size = 0;
    bool ok = false;
    RunRecord run;
    std::string error;
  };
  uint32_t interval_;
  std::map<std::string, Entry> entries_;
};

}  // namespace swarm_forage
