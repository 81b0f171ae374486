#include "swarm_forage/ros/run_feed.hpp"

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <stdexcept>

#include "swarm_forage/ros/run_bag.hpp"

namespace swarm_forage {

namespace {
bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

template <typename M>
M instantiate(const rosbag::MessageInstance& m) {
  const auto msg = m.instantiate<M>();
  if (!msg)
    throw std::runtime_error(m.getTopic() + " was recorded with another message definition (" +
                             m.getDataType() + ")");
  return *msg;
}
}  // namespace

TickPerformance fromMsg(const Performance& m) {
  TickPerformance p;
  p.run = m.run;
  p.swarm_size = m.swarm_size;
  p.tick = m.tick;
  p.delivered = m.delivered;
  p.cumulative = m.cumulative;
  p.throttle = m.throttle;
  p.last = m.last;
  p.stamp_ns = m.header.stamp.toNSec();
  return p;
}

StatusRange fromMsg(const SwarmStatus& m, const std::string& sender) {
  StatusRange s;
  s.run = m.run;
  s.swarm_size = m.swarm_size;
  s.tick = m.tick;
  s.first_id = m.first_id;
  s.count = m.count;
  s.in_avoidance = m.in_avoidance;
  s.sender = sender;
  return s;
}

RunEnding fromMsg(const RunEnd& m) {
  RunEnding e;
  e.run = m.run;
  e.ticks_done = m.ticks_done;
  e.ticks = m.ticks;
  e.complete = m.complete;
  e.reason = m.reason;
  return e;
}

AnnouncedRun describeRun(const RunInfo& info, uint32_t interval) {
  AnnouncedRun d;
  d.key = runKey(info, interval);
  d.seed = info.seed;
  return d;
}

void feed(RunFollower& follower, const rosbag::MessageInstance& m) {
  const std::string& topic = m.getTopic();
  if (endsWith(topic, "world/performance")) {
    follower.performance(fromMsg(instantiate<Performance>(m)));
  } else if (endsWith(topic, "swarm/status")) {
    follower.status(fromMsg(instantiate<SwarmStatus>(m), m.getCallerId()));
  } else if (endsWith(topic, "environment/throttle")) {
    const auto t = instantiate<Throttle>(m);
    follower.condition(t.tick, conditionOf(t));
  } else if (endsWith(topic, "world/run_info")) {
    const auto info = instantiate<RunInfo>(m);
    follower.describe(info.run, describeRun(info, follower.interval()));
  } else if (endsWith(topic, "world/run_end")) {
    follower.end(fromMsg(instantiate<RunEnd>(m)));
  }
}

void feedBag(RunFollower& follower, const std::string& path) {
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    for (const rosbag::MessageInstance& m : rosbag::View(bag)) feed(follower, m);
  } catch (const rosbag::BagException& e) {
    throw std::runtime_error(std::string("not a readable bag: ") + e.what());
  }
}

}  // namespace swarm_forage
