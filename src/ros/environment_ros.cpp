#include "swarm_forage/ros/environment_ros.hpp"

#include <swarm_forage/Throttle.h>

#include <cmath>
#include <cstdio>

#include "swarm_forage/ros/params.hpp"

namespace swarm_forage {

EnvironmentRos::EnvironmentRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh,
                               std::function<void(int)>)
    : nh_(nh), pnh_(pnh) {
  const double tps = ticks_per_second_ = paramInRange(pnh_, "ticks_per_second", 5.0, 0.001, 1000.0);
  const int ticks = paramInRange(pnh_, "ticks", 50000, 1, 2000000000);
  waveform_.name = paramOneOf(pnh_, "waveform", "null", waveformNames());
  waveform_.amplitude = paramInRange(pnh_, "beta", 0.0, -1.0, 1.0);
  // alpha < 0 means the paper's choice: half the run.
  const double run_seconds = ticks / tps;
  waveform_.alpha = paramInRange(pnh_, "alpha", -1.0, -1.0, 1e9);
  if (waveform_.alpha < 0) waveform_.alpha = run_seconds / 2;
  // A step at or after the run's end never happens: the run would be labelled step_up yet be ideal.
  if ((waveform_.name == "step_up" || waveform_.name == "step_down") && waveform_.alpha >= run_seconds) {
    char buf[200];
    std::snprintf(
        buf, sizeof buf,
        "~alpha %g s is not within the run (~ticks %d at %g ticks/s = %g s): the %s would never happen; "
        "valid: [0, %g) s, or -1 for half the run",
        waveform_.alpha, ticks, tps, run_seconds, waveform_.name.c_str(), run_seconds);
    throw ParameterError(buf);
  }
  waveform_.frequency = param<double>(pnh_, "frequency", 0.001);  // 10 cycles in 50,000 ticks
  waveform_.phase = param<double>(pnh_, "phase", 0.0);
  waveform_.offset = param<double>(pnh_, "offset", 0.0);
  try {
    waveform_.validate();
  } catch (const ParameterError& e) {
    throw ParameterError("~" + std::string(e.what()));  // the core names the parameter
  }
  ns_per_tick_ = static_cast<uint64_t>(std::llround(1e9 / tps));
  throttle_pub_ = nh_.advertise<Throttle>("environment/throttle", 64);
  clock_sub_ =
      nh_.subscribe("/clock", 64, &EnvironmentRos::onClock, this, ros::TransportHints().tcpNoDelay());
  ROS_INFO("environment: %s, beta %.3f, alpha %.1f s, frequency %g Hz, phase %g rad, offset %g",
           waveform_.name.c_str(), waveform_.amplitude, waveform_.alpha, waveform_.frequency, waveform_.phase,
           waveform_.offset);
}

void EnvironmentRos::onClock(const rosgraph_msgs::Clock::ConstPtr& msg) {
  const uint64_t ns = msg->clock.toNSec();
  Throttle t;
  t.header.stamp = msg->clock;
  t.tick = (ns + ns_per_tick_ / 2) / ns_per_tick_;
  const double seconds = static_cast<double>(t.tick) / ticks_per_second_;  // exact at alpha
  t.value = waveformValue(waveform_, seconds);
  t.waveform = waveform_.name;
  t.amplitude = waveform_.amplitude;
  t.alpha = waveform_.alpha;
  t.frequency = waveform_.frequency;
  t.phase = waveform_.phase;
  t.offset = waveform_.offset;
  throttle_pub_.publish(t);
}

}  // namespace swarm_forage
