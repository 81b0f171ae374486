#include "swarm_forage/ros/runs/run_bag.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "swarm_forage/core/util/worker_pool.hpp"
#include "swarm_forage/ros/messages/condition_ros.hpp"
#include "swarm_forage/ros/runs/follower_messages.hpp"

namespace swarm_forage {

namespace {
namespace fs = std::filesystem;

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

RunKey runKey(const RunInfo& info, uint32_t interval) {
  RunKey key;
  key.controller = info.controller;
  key.arena = info.arena;
  key.swarm_size = info.swarm_size;
  RunSetup& s = key.setup;
  s.arena_width = info.arena_x;
  s.arena_height = info.arena_y;
  s.cube_size = info.cube_size;
  s.ramp_length = info.ramp_length;
  s.n_blocks = info.n_blocks;
  s.ticks = info.ticks;
  s.ticks_per_second = info.ticks_per_second;
  s.mode = info.mode.empty() ? "lockstep" : info.mode;
  s.world_constants = info.world_constants;
  s.controller_constants = info.controller_constants;
  s.interval = interval;
  key.environment = conditionOf(info.environment);
  return key;
}

RunRecord readRunBag(const std::string& path, uint32_t interval) {
  RunFollower follower(interval, RunFollower::Mode::kRecord);
  feedBag(follower, path);
  return follower.record(path);
}

RunBagCache::Scan RunBagCache::scan(const std::string& directory) {
  std::vector<std::string> paths;
  std::error_code ec;
  for (fs::directory_iterator it(directory, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().extension() == ".bag") paths.push_back(it->path().string());
  if (ec) throw std::runtime_error("the run library '" + directory + "' cannot be read: " + ec.message());
  std::sort(paths.begin(), paths.end());

  Scan scan;
  for (fs::directory_iterator it(directory, ec), end; !ec && it != end; it.increment(ec))
    if (const std::string name =
            it->path().filename().string();  // NAME.bag.<pid>.active (or an older NAME.bag.active)
        endsWith(name, ".active") && name.find(".bag.") != std::string::npos)
      scan.unfinished.push_back(it->path().string());
  std::sort(scan.unfinished.begin(), scan.unfinished.end());
  // Which records are new or changed: read those, on every core (a sweep's tables read thousands, and
  // bz2 decoding is most of the work), each into its own entry; then list them all in path order.
  std::vector<Entry*> to_read;
  std::vector<const std::string*> read_paths;
  for (const std::string& path : paths) {
    const uintmax_t size = fs::file_size(path, ec);
    const auto time = fs::last_write_time(path, ec).time_since_epoch().count();
    Entry& e = entries_[path];
    if ((e.ok || !e.error.empty()) && e.size == size && e.mtime == static_cast<std::time_t>(time)) continue;
    e = Entry{};
    e.size = size;
    e.mtime = static_cast<std::time_t>(time);
    to_read.push_back(&e);
    read_paths.push_back(&path);
  }
  WorkerPool(0).run(to_read.size(), [&](std::size_t i, unsigned) {
    try {
      to_read[i]->run = readRunBag(*read_paths[i], interval_);
      to_read[i]->ok = true;
    } catch (const std::exception& ex) {
      to_read[i]->error = ex.what();
    }
  });
  for (const std::string& path : paths) {
    const Entry& e = entries_[path];
    if (e.ok)
      scan.runs.push_back(&e.run);
    else
      scan.problems.push_back(path + ": " + e.error);
  }
  return scan;
}

}  // namespace swarm_forage
