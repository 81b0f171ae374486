#include "swarm_forage/ros/runs/follower_messages.hpp"

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <swarm_forage/LegacyRunInfo.h>
#include <swarm_forage/LegacyThrottle.h>
#include <swarm_forage/Population.h>

#include <algorithm>
#include <map>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "swarm_forage/core/world/config.hpp"
#include "swarm_forage/record/bag_records.hpp"
#include "swarm_forage/ros/runs/run_bag.hpp"

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

void followPopulation(RunFollower& follower, const Population& msg) {
  follower.population(populationOf(msg));
  if (!msg.changed) return;
  follower.handChanged(msg.run, msg.tick, "a population rate",
                       "death=" + canonicalNumber(msg.death) + " birth=" + canonicalNumber(msg.birth) +
                           " malfunction=" + canonicalNumber(msg.malfunction) +
                           " repair=" + canonicalNumber(msg.repair));
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
    followPopulation(follower, instantiate<Population>(m));
  } else if (endsWith(topic, "world/provenance")) {
    follower.provenance(instantiate<Provenance>(m).model_version);
  }
}

namespace {
/// The connections that get a reader of their own: none when the chunks follow time (every chunk
/// starts where the one before it ended), as a run writes them; otherwise every connection with at
/// least 1/32 of the messages (per-tick topics) but the largest, which the main reader keeps.
std::vector<uint32_t> ownReaders(const bag_records::Layout& layout) {
  bool in_time = true;
  ros::Time latest;
  std::map<uint32_t, uint64_t> messages;
  uint64_t total = 0;
  for (const bag_records::Chunk& c : layout.chunks) {  // in file order
    in_time = in_time && c.start >= latest;
    latest = std::max(latest, c.stop);
    for (const auto& [id, n] : c.counts) messages[id] += n, total += n;
  }
  if (in_time) return {};
  std::vector<std::pair<uint64_t, uint32_t>> heavy;
  for (const auto& [id, n] : messages)
    if (n * 32 >= total) heavy.emplace_back(n, id);
  std::sort(heavy.rbegin(), heavy.rend());
  std::vector<uint32_t> out;
  for (std::size_t k = 1; k < heavy.size(); ++k) out.push_back(heavy[k].second);
  return out;
}

/// One connection's messages from a reader of its own, in the order a View of the whole bag gives them.
struct OwnReader {
  explicit OwnReader(const std::string& path, uint32_t id)
      : bag(path, rosbag::bagmode::Read),
        view(bag, [id](const rosbag::ConnectionInfo* c) { return c->id == id; }),
        at(view.begin()) {}
  rosbag::Bag bag;
  rosbag::View view;
  rosbag::View::iterator at;
};
}  // namespace

void feedBag(RunFollower& follower, const std::string& path) {
  // rosbag trusts the lengths and offsets of a bag's records (a flipped byte can make it read past its
  // buffers): it gets only a bag whose records were checked to hold together.
  const bag_records::Layout layout = checkBag(path);
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    // rosbag keeps one chunk decompressed. A bag whose chunks do not follow time (a copy made connection
    // by connection, as checkpoints did) puts a tick's status and performance in different chunks, and a
    // View in time order then reads a whole chunk per message: 17 times as slow at 100,000 ticks. There
    // each per-tick connection is read from a bag handle of its own, each in file order, while the View
    // over `bag` still gives the order, so the messages and their order are the same either way.
    rosbag::View all(bag);
    std::map<const ros::M_string*, std::unique_ptr<OwnReader>> own;  // by connection (its header)
    const std::vector<uint32_t> ids = ownReaders(layout);
    for (const rosbag::ConnectionInfo* c : all.getConnections())
      if (std::find(ids.begin(), ids.end(), c->id) != ids.end())
        own[c->header.get()] = std::make_unique<OwnReader>(path, c->id);
    for (const rosbag::MessageInstance& m : all) {
      const auto it = own.find(m.getConnectionHeader().get());
      if (it == own.end()) {
        feed(follower, m);
        continue;
      }
      OwnReader& r = *it->second;
      if (r.at == r.view.end() || r.at->getTime() != m.getTime())
        throw std::runtime_error("its connection " + m.getTopic() + " reads differently from two handles");
      feed(follower, *r.at);
      ++r.at;
    }
  } catch (const rosbag::BagException& e) {
    throw std::runtime_error(std::string("not a readable bag: ") + e.what());
  }
}

}  // namespace swarm_forage
