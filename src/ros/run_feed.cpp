#include "swarm_forage/ros/run_feed.hpp"

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <swarm_forage/LegacyRunInfo.h>
#include <swarm_forage/LegacyThrottle.h>
#include <swarm_forage/Population.h>

#include <stdexcept>
#include <type_traits>
#include <vector>

#include "swarm_forage/ros/run_bag.hpp"

namespace swarm_forage {

namespace {
bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// `old` as the current message: Throttle added three strings at its end (target, series,
/// series_digest), and RunInfo ends with a Throttle, so an old message's bytes followed by three empty
/// strings (a zero length each) are the current message with those fields empty (docs/runs-and-bags.md).
template <typename M, typename Old>
M upgraded(const Old& old) {
  namespace ser = ros::serialization;
  std::vector<uint8_t> bytes(ser::serializationLength(old) + 3 * sizeof(uint32_t), 0);
  ser::OStream out(bytes.data(), static_cast<uint32_t>(bytes.size()));
  ser::serialize(out, old);
  M msg;
  ser::IStream in(bytes.data(), static_cast<uint32_t>(bytes.size()));
  ser::deserialize(in, msg);
  return msg;
}

/// Legacy<M>: the definition of M that bags recorded before (void: M never changed).
template <typename M>
struct Legacy {
  using type = void;
};
template <>
struct Legacy<Throttle> {
  using type = LegacyThrottle;
};
template <>
struct Legacy<RunInfo> {
  using type = LegacyRunInfo;
};

template <typename M>
M instantiate(const rosbag::MessageInstance& m) {
  auto msg = m.instantiate<M>();
  if constexpr (!std::is_void_v<typename Legacy<M>::type>)
    if (!msg)
      if (const auto old = m.instantiate<typename Legacy<M>::type>()) return upgraded<M>(*old);
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

void noiseChanged(RunFollower& follower, const NoiseChange& msg) {
  follower.handChanged(msg.run, msg.tick, "the noise", msg.noise.empty() ? "none" : msg.noise);
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
  } else if (endsWith(topic, "world/noise")) {
    noiseChanged(follower, instantiate<NoiseChange>(m));
  } else if (endsWith(topic, "world/run_end")) {
    follower.end(runEndOf(instantiate<RunEnd>(m)));
  } else if (endsWith(topic, "world/population")) {
    if (const auto p = m.instantiate<Population>(); p && p->changed)
      follower.populationChanged(p->run, p->tick);
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
