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

AnnouncedRun describeRun(const RunInfo& info, uint32_t interval) {
  AnnouncedRun d;
  d.key = runKey(info, interval);
  d.seed = info.seed;
  return d;
}

void feed(RunFollower& follower, const rosbag::MessageInstance& m) {
  const std::string& topic = m.getTopic();
  if (endsWith(topic, "world/performance")) {
    const auto p = instantiate<Performance>(m);
    follower.performance(performanceOf(p), p.header.stamp.toNSec());
  } else if (endsWith(topic, "swarm/status")) {
    follower.status(statusOf(instantiate<SwarmStatus>(m), m.getCallerId()));
  } else if (endsWith(topic, "environment/throttle")) {
    follower.condition(conditionSampleOf(instantiate<Throttle>(m)));
  } else if (endsWith(topic, "world/run_info")) {
    const auto info = instantiate<RunInfo>(m);
    follower.describe(info.run, describeRun(info, follower.interval()));
  } else if (endsWith(topic, "world/run_end")) {
    follower.end(runEndOf(instantiate<RunEnd>(m)));
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
