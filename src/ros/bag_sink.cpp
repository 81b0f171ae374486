#include "swarm_forage/ros/bag_sink.hpp"

#include "swarm_forage/ros/run_messages.hpp"
#include "swarm_forage/ros/world_messages.hpp"

namespace swarm_forage {

BagSink::BagSink(RunOutputs outputs, uint64_t ns_per_tick,
                 std::function<std::string(const std::string&)> topic)
    : outputs_(std::move(outputs)), ns_per_tick_(ns_per_tick) {
  for (const char* t : {"world/nest", "world/provenance", "world/robots", "world/blocks", "world/caches",
                        "world/run_info", "environment/throttle", "swarm/status", "world/performance",
                        "world/run_end", "world/noise", "world/population"})
    topics_[t] = topic(t);
}

void BagSink::begin(const RunDescription& run, const std::string& label) {
  // Named by what is known until tick 0 fixes the identity (fixed()).
  run_ = run.run;
  const std::string path = path_ = runBagPath(outputs_.bag, outputs_.bag_dir, run);
  if (path.empty()) return;
  ExistingBag existing = ExistingBag::kNumber;
  if (outputs_.bag_dir.empty())  // a later run's name is checked as the first one's was at start-up
    existing = run.run > 0          ? explicitBagPolicy("bag", path, outputs_.overwrite)
               : outputs_.overwrite ? ExistingBag::kReplace
                                    : ExistingBag::kRefuse;
  recorder_.open(path, outputs_.compression, existing);
  recorder_.write(topics_.at("world/nest"), tickTime(0, ns_per_tick_), nestMsg(run.world.arena));
  recorder_.write(topics_.at("world/provenance"), tickTime(0, ns_per_tick_), provenanceMsg(label));
}

void BagSink::snapshot(uint64_t tick, const SensorData& sensors, const BlockField& blocks) {
  const ros::Time stamp = tickTime(tick, ns_per_tick_);
  recorder_.write(topics_.at("world/robots"), stamp, robotsMsg(sensors, tick, stamp));
  recorder_.write(topics_.at("world/blocks"), stamp, blocksMsg(blocks, sensors, tick, stamp));
}

void BagSink::caches(uint64_t tick, const StaticCache& cache) {
  const ros::Time stamp = tickTime(tick, ns_per_tick_);
  recorder_.write(topics_.at("world/caches"), stamp, cachesMsg(cache, tick, stamp));
}

void BagSink::fixed(const RunDescription& run) {
  const RunInfo info = runInfoMsg(run, ns_per_tick_);
  recorder_.write(topics_.at("world/run_info"), info.header.stamp, info);
  if (!outputs_.bag_dir.empty()) recorder_.rename(runBagPath(outputs_.bag, outputs_.bag_dir, run));
}

void BagSink::condition(uint64_t tick, const ConditionSample& c) {
  recorder_.write(topics_.at("environment/throttle"), tickTime(tick, ns_per_tick_),
                  throttleMsg(c, ns_per_tick_));
}

void BagSink::population(const PopulationRecord& p) {
  if (recorder_.isOpen())
    recorder_.write(topics_.at("world/population"), tickTime(p.tick, ns_per_tick_),
                    populationMsg(p, ns_per_tick_));
}

void BagSink::noiseChanged(uint64_t tick, const SaaNoise& noise) {
  if (!recorder_.isOpen()) return;
  recorder_.write(topics_.at("world/noise"), tickTime(tick, ns_per_tick_),
                  noiseChangeMsg(run_, tick, noise, ns_per_tick_));
}

void BagSink::stepped(const std::vector<StatusRecord>& status, const PerformanceRecord& performance) {
  if (!recorder_.isOpen()) return;
  const ros::Time stamp = tickTime(performance.tick, ns_per_tick_);
  for (const StatusRecord& s : status)
    recorder_.write(topics_.at("swarm/status"), stamp, statusMsg(s, tickTime(s.tick, ns_per_tick_)));
  recorder_.write(topics_.at("world/performance"), stamp, performanceMsg(performance, ns_per_tick_));
}

void BagSink::end(RunEndRecord& end) {
  if (!recorder_.isOpen()) return;
  const RunEnd msg = runEndMsg(end, ns_per_tick_);
  recorder_.write(topics_.at("world/run_end"), msg.header.stamp, msg);
  end.bag = recorder_.close(end.complete);
  if (!recorder_.error().empty()) {  // recorded, but not under its name: not a finished record
    end.reason = (end.complete ? "" : end.reason + "; ") + recorder_.error();
    end.complete = false;
  }
}

}  // namespace swarm_forage
