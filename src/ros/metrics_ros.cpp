#include "swarm_forage/ros/metrics_ros.hpp"

#include <swarm_forage/IntervalPerformance.h>

#include "swarm_forage/ros/params.hpp"

namespace swarm_forage {

namespace {
constexpr std::size_t kMaxPendingTicks = 5000;  // beyond this a tick is declared incomplete
}

MetricsRos::MetricsRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, std::function<void(int)> finish)
    : nh_(nh), pnh_(pnh), finish_(std::move(finish)) {
  interval_ = static_cast<uint32_t>(paramInRange(pnh_, "sample_interval", 1000, 1, 100000000));
  exit_on_final_ = param<bool>(pnh_, "exit_on_final", false);
  const std::string csv = param<std::string>(pnh_, "csv", "");
  if (!csv.empty()) {
    csv_.open(csv);
    if (!csv_) throw ParameterError("~csv '" + csv + "' cannot be written");
    csv_ << "run,swarm_size,tick_end,interval_ticks,P,p,n_ca,final\n" << std::flush;
  }
  accumulator_ = IntervalAccumulator(interval_);
  // Replays publish as fast as asked: queues deep enough that no tick is dropped.
  const auto fast = ros::TransportHints().tcpNoDelay();
  interval_pub_ = nh_.advertise<IntervalPerformance>("metrics/performance", 100, /*latch=*/false);
  performance_sub_ = nh_.subscribe("world/performance", 100000, &MetricsRos::onPerformance, this, fast);
  status_sub_ = nh_.subscribe("swarm/status", 100000, &MetricsRos::onStatus, this, fast);
}

bool MetricsRos::follow(uint32_t run) {
  if (following_ && run == run_) return true;
  if (following_ && run < run_) return false;
  following_ = true;
  run_ = run;
  next_tick_.reset();
  pending_.clear();
  accumulator_.reset();
  ticks_seen_ = in_avoidance_total_ = 0;
  return true;
}

MetricsRos::Pending& MetricsRos::pending(uint64_t tick, uint32_t swarm_size) {
  auto [it, fresh] = pending_.try_emplace(tick);
  if (fresh) it->second.status.begin(swarm_size);
  return it->second;
}

void MetricsRos::onPerformance(const Performance::ConstPtr& msg) {
  if (!follow(msg->run)) return;
  if (!next_tick_) {
    next_tick_ = msg->tick;
    if (msg->tick != 0)
      ROS_WARN("metrics: joined run %u at tick %lu; intervals count from there", msg->run,
               static_cast<unsigned long>(msg->tick));
  }
  if (msg->tick < *next_tick_) return;
  swarm_size_ = msg->swarm_size;
  pending(msg->tick, msg->swarm_size).performance = *msg;
  drain();
}

void MetricsRos::onStatus(const ros::MessageEvent<const SwarmStatus>& event) {
  const SwarmStatus& msg = *event.getMessage();
  if (!follow(msg.run) || (next_tick_ && msg.tick < *next_tick_)) return;
  Pending& p = pending(msg.tick, msg.swarm_size);
  if (p.status.add(msg.first_id, msg.count, event.getPublisherName())) p.in_avoidance += msg.in_avoidance;
  drain();
}

void MetricsRos::drain() {
  while (next_tick_ && !pending_.empty()) {
    auto it = pending_.find(*next_tick_);
    const bool complete = it != pending_.end() && it->second.performance && it->second.status.complete();
    if (!complete) {
      if (pending_.size() < kMaxPendingTicks) return;
      ROS_ERROR("metrics: tick %lu never completed (%s); counting it with what arrived",
                static_cast<unsigned long>(*next_tick_),
                it == pending_.end()      ? "nothing arrived"
                : !it->second.performance ? "no world/performance"
                                          : it->second.status.missing().c_str());
      if (it == pending_.end() || !it->second.performance) {
        if (it != pending_.end()) pending_.erase(it);
        ++*next_tick_;
        continue;
      }
    }
    const Performance& perf = *it->second.performance;
    ++ticks_seen_;
    in_avoidance_total_ += it->second.in_avoidance;
    if (auto sample =
            accumulator_.add(perf.tick, perf.delivered, perf.cumulative, it->second.in_avoidance, perf.last))
      publish(*sample, perf.header.stamp);
    pending_.erase(it);
    ++*next_tick_;
  }
}

void MetricsRos::publish(const IntervalSample& s, const ros::Time& stamp) {
  IntervalPerformance msg;
  msg.header.stamp = stamp;
  msg.run = run_;
  msg.swarm_size = swarm_size_;
  msg.tick_end = s.tick_end;
  msg.interval_ticks = s.interval_ticks;
  msg.P = s.cumulative;
  msg.p = s.delivered;
  msg.n_ca = s.mean_in_avoidance;
  msg.final = s.final;
  interval_pub_.publish(msg);
  if (csv_.is_open())
    csv_ << run_ << ',' << swarm_size_ << ',' << s.tick_end << ',' << s.interval_ticks << ',' << s.cumulative
         << ',' << s.delivered << ',' << s.mean_in_avoidance << ',' << (s.final ? 1 : 0) << '\n'
         << std::flush;
  if (!s.final) return;
  ROS_INFO("metrics: run %u done: %u robots, %lu ticks, %lu blocks delivered, mean interference %.2f robots",
           run_, swarm_size_, static_cast<unsigned long>(ticks_seen_),
           static_cast<unsigned long>(s.cumulative),
           ticks_seen_ ? static_cast<double>(in_avoidance_total_) / ticks_seen_ : 0.0);
  if (exit_on_final_ && finish_) finish_(0);
}

}  // namespace swarm_forage
