#include "swarm_forage/ros/world_node/world_health.hpp"

#include <diagnostic_msgs/DiagnosticStatus.h>

#include <algorithm>
#include <cstdio>

namespace swarm_forage {

namespace {
using Status = diagnostic_msgs::DiagnosticStatus;

std::string seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", s);
  return buf;
}
}  // namespace

WorldHealth::WorldHealth(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, bool lockstep,
                         std::function<std::string()> missing, Values more)
    : lockstep_(lockstep),
      missing_(std::move(missing)),
      more_(std::move(more)),
      wait_(readHealthThresholds(pnh, "wait")),
      reporter_(
          nh, pnh, "stepping", [this](diagnostic_updater::DiagnosticStatusWrapper& s) { fill(s); },
          /*timer=*/false) {}

void WorldHealth::phase(const std::string& what, unsigned char level) {
  phase_ = what;
  phase_level_ = level;
  running_ = false;
  waiting_ = false;
}

void WorldHealth::beginRun(uint32_t run, uint64_t ticks, uint32_t robots) {
  run_ = run;
  ticks_ = ticks;
  robots_ = robots;
  tick_ = ticks_done_ = reported_ticks_ = 0;
  waits_.clear();
  heard_.clear();
  phase_.clear();
  phase_level_ = Status::OK;
  running_ = true;
}

void WorldHealth::tickStarted(uint64_t tick) {
  tick_ = tick;
  tick_started_ = ros::WallTime::now();
  waiting_ = lockstep_;
  current_waits_.clear();
}

void WorldHealth::replied(const std::string& node) {
  const ros::WallTime now = ros::WallTime::now();
  heard_[node] = now;
  if (lockstep_) current_waits_[node] = (now - tick_started_).toSec();
}

void WorldHealth::repliesIn() {
  waiting_ = false;
  waits_ = current_waits_;
}

double WorldHealth::waiting(const ros::WallTime& now) const {
  if (!running_) return 0.0;
  if (lockstep_) return waiting_ ? (now - tick_started_).toSec() : 0.0;
  double quiet = 0.0;
  for (const auto& [node, when] : heard_) quiet = std::max(quiet, (now - when).toSec());
  return quiet;
}

void WorldHealth::fill(diagnostic_updater::DiagnosticStatusWrapper& s) {
  const ros::WallTime now = ros::WallTime::now();
  const double elapsed = reported_at_.isZero() ? 0.0 : (now - reported_at_).toSec();
  const double tick_rate = elapsed > 0 ? static_cast<double>(ticks_done_ - reported_ticks_) / elapsed : 0.0;
  reported_at_ = now;
  reported_ticks_ = ticks_done_;
  const double wait = waiting(now);

  // The peers' answer times: lockstep, how long each took at its latest answer; realtime, how long since
  // each spoke. Mid-tick, a peer that answered counts at this tick's time and one that has not at least at
  // the wait so far, so the peer holding the tick is the slowest even after another's slow last tick.
  std::map<std::string, double> answers = waits_;
  if (!lockstep_)
    for (const auto& [node, when] : heard_) answers[node] = (now - when).toSec();
  if (lockstep_ && waiting_)
    for (const auto& [node, when] : heard_) {
      const auto answered = current_waits_.find(node);
      answers[node] = answered != current_waits_.end() ? answered->second : std::max(answers[node], wait);
    }
  const auto slowest = std::max_element(answers.begin(), answers.end(),
                                        [](const auto& a, const auto& b) { return a.second < b.second; });

  const unsigned char level = std::max<unsigned char>(phase_level_, running_ ? wait_.level(wait) : 0);
  if (!running_)
    s.summary(level, phase_);
  else if (wait >= wait_.warn)
    s.summaryf(level, "tick %lu: %s %.1f s: %s", static_cast<unsigned long>(tick_),
               lockstep_ ? "waiting" : "a controller silent for", wait, missing_().c_str());
  else
    s.summaryf(level, "run %u: tick %lu of %lu, %.3g robot-ticks/s", run_, static_cast<unsigned long>(tick_),
               static_cast<unsigned long>(ticks_), tick_rate * robots_);

  s.add("mode", lockstep_ ? "lockstep" : "realtime");
  s.add("run", run_);
  s.add("tick", tick_);
  s.add("ticks", ticks_);
  s.add("robots", robots_);
  s.add("tick rate [ticks/s]", tick_rate);
  s.add("robot-ticks/s", tick_rate * robots_);
  s.add("waiting [s]", seconds(wait));
  s.add("waiting for", wait > 0 && running_ ? missing_() : std::string());
  s.add("slowest peer", slowest == answers.end() ? std::string() : slowest->first);
  s.add("slowest wait [s]", slowest == answers.end() ? std::string() : seconds(slowest->second));
  for (const auto& [node, t] : answers) s.add("wait " + node + " [s]", seconds(t));
  s.add("step timeouts", step_timeouts_);
  more_(s);
  s.add("diag_wait_warn [s]", wait_.warn);
  s.add("diag_wait_error [s]", wait_.error);
}

}  // namespace swarm_forage
