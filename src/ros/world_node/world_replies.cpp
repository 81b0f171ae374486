// world_node's ports: world/sensors out, swarm/commands, swarm/status and environment/throttle back. In
// lockstep a tick waits for every reply (the barrier); in realtime it steps with the latest ones. Says what
// is wrong when they do not come or do not fit together.
#include <rosgraph_msgs/Clock.h>

#include <algorithm>
#include <cstdio>

#include "swarm_forage/ros/messages/batch_messages.hpp"
#include "swarm_forage/ros/messages/run_messages.hpp"
#include "swarm_forage/ros/messages/world_messages.hpp"
#include "swarm_forage/ros/world_node/world_ros.hpp"

namespace swarm_forage {

std::string WorldRos::waitForPeers() {
  const ros::WallTime start = ros::WallTime::now(), deadline = start + ros::WallDuration(startup_timeout_);
  std::string waiting;
  while (!stop_ && ros::ok()) {
    waiting.clear();
    if (sensors_pub_.getNumSubscribers() == 0) waiting += " a controller_node subscribed to world/sensors;";
    if (commands_sub_.getNumPublishers() == 0) waiting += " a publisher of swarm/commands;";
    if (use_environment_ && throttle_sub_.getNumPublishers() == 0)
      waiting += " an environment_node publishing environment/throttle (or ~use_environment false);";
    if (static_cast<int>(performance_pub_.getNumSubscribers()) < wait_for_subscribers_)
      waiting += " " + std::to_string(wait_for_subscribers_) +
                 " subscribers of world/performance (~wait_for_subscribers);";
    if (waiting.empty()) {
      ros::WallDuration(0.5).sleep();  // lets the other nodes' links to each other settle too
      return "";
    }
    health_->phase("waiting for peers:" + waiting,
                   health_->waitLevel((ros::WallTime::now() - start).toSec()));
    health_->poll();
    if (ros::WallTime::now() > deadline) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "still waiting after ~startup_timeout %.1f s for:", startup_timeout_);
      return buf + waiting;
    }
    queue_.callAvailable(ros::WallDuration(0.05));
  }
  return "shut down before the run started";
}

void WorldRos::begin(const RunDescription& run, const World&) {
  commands_.resize(run.world.n_robots);
  range_error_.clear();
  heard_.clear();
}

StepOutcome WorldRos::decide(uint64_t tick, const World& world, const SensorData& sensors) {
  publishSensors(tick, world, sensors);
  markers_->publish(world, sensors, commands_, tickTime(tick, ns_per_tick_));
  frames_->publish(world, sensors, tickTime(tick, ns_per_tick_));
  awaited_tick_ = tick;
  health_->tickStarted(tick);
  commands_seen_.begin(world.config().n_robots);
  status_seen_.begin(world.config().n_robots);
  status_.clear();
  if (lockstep_ && use_environment_) throttle_.reset();
  // Realtime runs too wait for tick 0's replies: they tell the run's constants and who serves whom.
  std::string failed;
  if (lockstep_ || tick == 0) {
    failed = awaitReplies(tick, world, sensors);
    next_ = ros::WallTime::now();
  } else {
    next_ += ros::WallDuration(1.0 / (world.config().ticks_per_second * real_time_factor_));  // live pace
    failed = waitRealtime(tick, next_);
  }
  if (failed.empty()) failed = guard_->check();
  std::sort(status_.begin(), status_.end(),
            [](const StatusRecord& a, const StatusRecord& b) { return a.first_id < b.first_id; });
  return failed.empty() ? StepOutcome::ok() : StepOutcome::stop(failed);
}

std::string WorldRos::missingReplies() const {
  std::string missing = commands_seen_.missing();
  if (!status_seen_.complete()) missing += (missing.empty() ? "" : "; ") + status_seen_.missing();
  if (use_environment_ && !throttle_)
    missing +=
        (missing.empty() ? "" : "; ") + std::string("environment/throttle") +
        (throttle_sender_.empty() ? " (no environment node has ever answered)" : " from " + throttle_sender_);
  return missing;
}

std::string WorldRos::awaitReplies(uint64_t tick, const World& world, const SensorData& sensors) {
  const ros::WallTime start = ros::WallTime::now();
  ros::WallTime resend = start + ros::WallDuration(1.0);
  std::optional<ros::WallTime> replied;
  const std::string at = "tick " + std::to_string(tick) + ": ";
  for (;;) {
    if (!range_error_.empty()) return at + range_error_;
    const ros::WallTime now = ros::WallTime::now();
    if (commands_seen_.complete() && status_seen_.complete() && (throttle_ || !use_environment_)) {
      // Tick 0 also waits (briefly) for every node publishing commands, so that two nodes claiming the
      // same robots are caught before the run starts.
      if (!replied) {
        replied = now;
        health_->repliesIn();
      }
      if (tick != 0 || commands_seen_.senders() >= commands_sub_.getNumPublishers() ||
          now - *replied > ros::WallDuration(1.0))
        return "";
    }
    queue_.callAvailable(ros::WallDuration(0.01));
    if (stop_ || !ros::ok()) return shutdownReason(tick);
    health_->poll();
    if (now - start > ros::WallDuration(step_timeout_)) {
      health_->stepTimedOut();
      char buf[64];
      std::snprintf(buf, sizeof buf, "no reply within ~step_timeout %.2f s: ", step_timeout_);
      return at + buf + missingReplies();
    }
    if (now > resend) {  // a node that connected late missed the first send: offer the tick again
      publishSensors(tick, world, sensors);
      resend = now + ros::WallDuration(1.0);
    }
  }
}

std::string WorldRos::waitRealtime(uint64_t tick, ros::WallTime deadline) {
  while (!stop_ && ros::ok()) {
    if (!range_error_.empty()) return "tick " + std::to_string(tick) + ": " + range_error_;
    const ros::WallTime now = ros::WallTime::now();
    for (const auto& [node, last] : heard_)
      if (now - last.first > ros::WallDuration(step_timeout_)) {
        char buf[96];
        std::snprintf(buf, sizeof buf,
                      " has sent no swarm/commands for %.2f s (~step_timeout %.2f s, realtime)",
                      (now - last.first).toSec(), step_timeout_);
        return "tick " + std::to_string(tick) + ": " + node + " (robots " + last.second + ")" + buf;
      }
    if (now >= deadline) return "";
    health_->poll();
    queue_.callAvailable(std::min(deadline - now, ros::WallDuration(0.01)));
  }
  return shutdownReason(tick);
}

void WorldRos::publishSensors(uint64_t tick, const World& world, const SensorData& sensors) {
  const ros::Time stamp = tickTime(tick, ns_per_tick_);
  rosgraph_msgs::Clock clock;
  clock.clock = stamp;
  clock_pub_.publish(clock);
  // With sensor noise, the controllers get what the robots perceive; markers and frames show the truth.
  sensors_pub_.publish(
      sensorsMsg(world, world.perceived(sensors), tick, run_no_, run_->description().controller, stamp));
}

void WorldRos::onCommands(const ros::MessageEvent<const CommandBatch>& event) {
  const CommandBatch& msg = *event.getMessage();
  if (msg.run != run_no_ || (lockstep_ && msg.tick != awaited_tick_)) return;  // late: an earlier tick or run
  const std::size_t n = msg.left.size();
  if (msg.right.size() != n || msg.request.size() != n || (!msg.task.empty() && msg.task.size() != n)) {
    // Stops the tick with the reason: a node that always sends such arrays would otherwise look silent.
    if (range_error_.empty())
      range_error_ = "malformed swarm/commands from " + event.getPublisherName() + " (first_id " +
                     std::to_string(msg.first_id) + "): left has " + std::to_string(n) + " entries, right " +
                     std::to_string(msg.right.size()) + ", request " + std::to_string(msg.request.size()) +
                     ", task " + std::to_string(msg.task.size()) +
                     " (valid: left, right and request of one length, one entry per robot; task empty or of "
                     "that length too)";
    return;
  }
  const std::string& sender = event.getPublisherName();
  const auto added = commands_seen_.add(msg.first_id, static_cast<uint32_t>(n), sender);
  if (added == RangeCoverage::Added::kRejected) {
    if (range_error_.empty()) range_error_ = commands_seen_.rejection();
    return;
  }
  if (!lockstep_)  // who is silent is watched per node; lockstep waits per tick instead
    heard_[sender] = {ros::WallTime::now(),
                      "[" + std::to_string(msg.first_id) + ", " + std::to_string(msg.first_id + n) + ")"};
  // Realtime: the latest commands of every range drive the robots, whichever tick they answered.
  if (added == RangeCoverage::Added::kNew || !lockstep_) mergeInto(msg, commands_);
  health_->replied(sender);
}

void WorldRos::onStatus(const ros::MessageEvent<const SwarmStatus>& event) {
  const SwarmStatus& msg = *event.getMessage();
  if (msg.run != run_no_ || (lockstep_ && msg.tick != awaited_tick_)) return;
  const auto added = status_seen_.add(msg.first_id, msg.count, event.getPublisherName());
  if (added == RangeCoverage::Added::kRejected && range_error_.empty())
    range_error_ = status_seen_.rejection();
  if (added == RangeCoverage::Added::kNew) status_.push_back(statusOf(msg, event.getPublisherName()));
}

void WorldRos::onControllerError(const std_msgs::String& error) {
  if (range_error_.empty()) range_error_ = "controller node " + error.data;  // stops the tick it waits for
}

void WorldRos::onThrottle(const ros::MessageEvent<const Throttle>& event) {
  const Throttle& msg = *event.getMessage();
  if (lockstep_ && msg.tick != awaited_tick_) return;
  throttle_ = conditionSampleOf(msg);
  throttle_sender_ = event.getPublisherName();
  health_->replied(throttle_sender_);
}

}  // namespace swarm_forage
