#include "swarm_forage/ros/environment_ros.hpp"

#include <swarm_forage/Throttle.h>

#include <cmath>
#include <cstdio>

#include "swarm_forage/ros/known_params.hpp"
#include "swarm_forage/ros/params.hpp"
#include "swarm_forage/ros/run_messages.hpp"

namespace swarm_forage {

namespace {
EnvironmentConfig toConfig(const WaveformConfig& w) {
  EnvironmentConfig c;
  c.waveform = w.name;
  c.beta = w.amplitude;
  c.alpha = w.alpha;
  c.frequency = w.frequency;
  c.phase = w.phase;
  c.offset = w.offset;
  return c;
}

WaveformConfig fromConfig(const EnvironmentConfig& c) {
  WaveformConfig w;
  w.name = c.waveform;
  w.amplitude = c.beta;
  w.alpha = c.alpha;
  w.frequency = c.frequency;
  w.phase = c.phase;
  w.offset = c.offset;
  return w;
}
}  // namespace

EnvironmentRos::EnvironmentRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh,
                               std::function<void(int)>)
    : nh_(nh), pnh_(pnh) {
  refuseUnknownParams(pnh_, parameterNames(), "environment_node");
  const double tps = ticks_per_second_ = paramInRange(pnh_, "ticks_per_second", 5.0, 0.001, 1000.0);
  ticks_ = paramInRange(pnh_, "ticks", 50000, 1, 2000000000);
  waveform_ = readWaveform(NodeParams(pnh_), ticks_, tps);
  ns_per_tick_ = static_cast<uint64_t>(std::llround(1e9 / tps));
  throttle_pub_ = nh_.advertise<Throttle>("environment/throttle", 64);
  clock_sub_ =
      nh_.subscribe("/clock", 64, &EnvironmentRos::onClock, this, ros::TransportHints().tcpNoDelay());
  reconfigure_ = std::make_unique<Reconfigurable<EnvironmentConfig>>(
      pnh_, toConfig(waveform_), [this](const EnvironmentConfig& c) { return reconfigure(c); });
}

EnvironmentConfig EnvironmentRos::reconfigure(const EnvironmentConfig& requested) {
  WaveformConfig next = fromConfig(requested);
  checkWaveformForRun(next, ticks_, ticks_per_second_);  // throws: nothing changes
  waveform_ = next;
  ROS_INFO("environment: %s, beta %.3f, alpha %.1f s, frequency %g Hz, phase %g rad, offset %g",
           waveform_.name.c_str(), waveform_.amplitude, waveform_.alpha, waveform_.frequency, waveform_.phase,
           waveform_.offset);
  return toConfig(waveform_);
}

void EnvironmentRos::onClock(const rosgraph_msgs::Clock::ConstPtr& msg) {
  const uint64_t tick = (msg->clock.toNSec() + ns_per_tick_ / 2) / ns_per_tick_;
  Throttle t = throttleMsg(waveform_, tick, ticks_per_second_, ns_per_tick_);
  t.header.stamp = msg->clock;
  throttle_pub_.publish(t);
}

}  // namespace swarm_forage
