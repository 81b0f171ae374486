#include "swarm_forage/ros/run_bag.hpp"

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <swarm_forage/Performance.h>
#include <swarm_forage/RunEnd.h>
#include <swarm_forage/SwarmStatus.h>
#include <swarm_forage/Throttle.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <stdexcept>

#include "swarm_forage/ros/condition_ros.hpp"
#include "swarm_forage/ros/run_messages.hpp"

namespace swarm_forage {

namespace {
namespace fs = std::filesystem;

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

struct Tick {
  std::optional<Performance> performance;
  std::map<uint32_t, std::pair<uint32_t, uint32_t>> status;  // first id -> (count, in avoidance)
};

template <typename M>
M instantiate(const rosbag::MessageInstance& m) {
  const auto msg = m.instantiate<M>();
  if (!msg)
    throw std::runtime_error(m.getTopic() + " was recorded with another message definition (" +
                             m.getDataType() + ")");
  return *msg;
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
  std::optional<RunInfo> info;
  std::optional<RunEnd> end;
  std::map<uint64_t, Tick> ticks;
  std::vector<Throttle> throttles;
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
      const std::string& topic = m.getTopic();
      if (endsWith(topic, "world/run_info")) {
        if (!info) info = instantiate<RunInfo>(m);
      } else if (endsWith(topic, "world/performance")) {
        const auto p = instantiate<Performance>(m);
        ticks[p.tick].performance = p;
      } else if (endsWith(topic, "world/run_end")) {
        end = instantiate<RunEnd>(m);
      } else if (endsWith(topic, "environment/throttle")) {
        throttles.push_back(instantiate<Throttle>(m));
      } else if (endsWith(topic, "swarm/status")) {
        const auto s = instantiate<SwarmStatus>(m);
        ticks[s.tick].status[s.first_id] = {s.count, s.in_avoidance};
      }
    }
  } catch (const rosbag::BagException& e) {
    throw std::runtime_error(std::string("not a readable bag: ") + e.what());
  }
  if (!info) throw std::runtime_error("no world/run_info in the bag (was it recorded by world_node?)");
  if (!end)
    throw std::runtime_error(
        "no world/run_end in the bag: its writer never closed it (killed?), so it is "
        "incomplete");
  if (!end->complete)
    throw std::runtime_error("incomplete: run " + std::to_string(end->run) + " stopped at tick " +
                             std::to_string(end->ticks_done) + " of " + std::to_string(end->ticks) + " (" +
                             end->reason + ")");

  for (const Throttle& t : throttles)
    if (!sameWaveform(t, info->environment)) throw std::runtime_error(reconfiguredLive(t));

  RunRecord run;
  run.key = runKey(*info, interval);
  run.seed = info->seed;
  run.source = path;
  RunSeriesBuilder builder(interval, info->swarm_size);
  uint64_t expected = 0;
  for (const auto& [tick, t] : ticks) {
    const std::string at = "tick " + std::to_string(tick) + ": ";
    if (!t.performance) throw std::runtime_error(at + "no world/performance");
    if (tick != expected)
      throw std::runtime_error("ticks " + std::to_string(expected) + " to " + std::to_string(tick - 1) +
                               " are missing");
    uint32_t covered = 0, in_avoidance = 0;
    for (const auto& [first, range] : t.status) {
      covered += range.first;
      in_avoidance += range.second;
    }
    if (covered != info->swarm_size)
      throw std::runtime_error(at + "swarm/status covers " + std::to_string(covered) + " of " +
                               std::to_string(info->swarm_size) + " robots");
    const Performance& p = *t.performance;
    builder.add(tick, p.delivered, p.cumulative, in_avoidance, p.last, p.throttle);
    ++expected;
    if (p.last) break;
  }
  if (!builder.finished())
    throw std::runtime_error("the run stops at tick " + std::to_string(expected) + " of " +
                             std::to_string(info->ticks) + " (incomplete)");
  run.series = builder.series();
  return run;
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
  for (const std::string& path : paths) {
    const uintmax_t size = fs::file_size(path, ec);
    const auto time = fs::last_write_time(path, ec).time_since_epoch().count();
    Entry& e = entries_[path];
    if (e.ok || !e.error.empty()) {
      if (e.size == size && e.mtime == static_cast<std::time_t>(time)) {
        if (e.ok)
          scan.runs.push_back(&e.run);
        else
          scan.problems.push_back(path + ": " + e.error);
        continue;
      }
    }
    e = Entry{};
    e.size = size;
    e.mtime = static_cast<std::time_t>(time);
    try {
      e.run = readRunBag(path, interval_);
      e.ok = true;
      scan.runs.push_back(&e.run);
    } catch (const std::exception& ex) {
      e.error = ex.what();
      scan.problems.push_back(path + ": " + e.error);
    }
  }
  return scan;
}

}  // namespace swarm_forage
