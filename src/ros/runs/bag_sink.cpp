#include "swarm_forage/ros/runs/bag_sink.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "swarm_forage/ros/messages/run_messages.hpp"
#include "swarm_forage/ros/messages/world_messages.hpp"

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
  // Named by what is known until tick 0 fixes the identity (identityFixed()).
  run_ = run.run;
  const std::string path = path_ = runBagPath(outputs_.bag, outputs_.bag_dir, run);
  if (path.empty()) return;
  recorder_.open(path, outputs_.compression, policy(run, path));
  recorder_.write(topics_.at("world/nest"), tickTime(0, ns_per_tick_), nestMsg(run.world.arena));
  recorder_.write(topics_.at("world/provenance"), tickTime(0, ns_per_tick_), provenanceMsg(label));
}

ExistingBag BagSink::policy(const RunDescription& run, const std::string& path) const {
  if (!outputs_.bag_dir.empty()) return ExistingBag::kNumber;
  // a later run's name is checked as the first one's was at start-up
  return run.run > 0          ? explicitBagPolicy("bag", path, outputs_.overwrite)
         : outputs_.overwrite ? ExistingBag::kReplace
                              : ExistingBag::kRefuse;
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

void BagSink::identityFixed(const RunDescription& run) {
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
  if (!end.complete && recorder_.covered()) {  // the checkpoint holds the whole record
    recorder_.close(false);
    end.bag.clear();
    end.reason += "; recorded up to here in the segments of " + checkpoint_ + ": resume:=" + checkpoint_ +
                  " continues it";
    return;
  }
  const RunEnd msg = runEndMsg(end, ns_per_tick_);
  recorder_.write(topics_.at("world/run_end"), msg.header.stamp, msg);
  end.bag = recorder_.close(end.complete);
  if (!recorder_.error().empty()) {  // recorded, but not under its name: not a finished record
    end.reason = (end.complete ? "" : end.reason + "; ") + recorder_.error();
    end.complete = false;
  }
}

void persistValue(StateArchive& a, BagSegment& s) { a.io(s.file, s.size, s.checksum, s.bytes); }

void BagSink::save(StateArchive& a) {
  a.section("bag");
  bool recorded = recorder_.isOpen();
  // Absolute: the resumed process may run in another folder.
  std::string active = recorded ? std::filesystem::absolute(recorder_.active()).string() : "";
  std::vector<BagSegment> segments = recorder_.checkpoint();
  if (carry_)
    for (BagSegment& s : segments) {
      std::ifstream in(s.file, std::ios::binary);
      s.bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
      if (!in || s.bytes.size() != s.size) throw std::runtime_error("cannot read back " + s.file);
    }
  a.io(recorded, active, segments);
}

void BagSink::checkpointWritten(const std::string& file) {
  if (!recorder_.isOpen()) return;
  recorder_.checkpointWritten();
  checkpoint_ = file;
}

namespace {
/// The process that wrote `active` (PATH.<pid>.active) is gone: its file is a killed run's leftover.
bool orphaned(const std::string& active) {
  const auto end = active.rfind(".active"), dot = active.rfind('.', end - 1);
  if (end == std::string::npos || dot == std::string::npos) return false;
  const int pid = std::atoi(active.substr(dot + 1, end - dot - 1).c_str());
  return pid > 0 && pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH;
}
}  // namespace

void BagSink::resume(StateArchive& a, const RunDescription& run, uint64_t tick,
                     const std::vector<ConditionSample>* fork) {
  a.section("bag");
  bool recorded = false;
  std::string active;
  std::vector<BagSegment> segments;
  a.io(recorded, active, segments);
  run_ = run.run;
  path_ = runBagPath(outputs_.bag, outputs_.bag_dir, run);
  if (path_.empty()) return;
  if (!recorded)
    throw ParameterError(
        "resume: the checkpointed run was not recorded, so its bag cannot be continued; "
        "resume without bag:= and bag_dir:=");
  // What a fresh run of these words records at tick 0 replaces the parent's: the provenance (this build,
  // this label) always; for a fork also its run info and condition records.
  std::vector<Throttle> throttles;
  if (fork)
    for (const ConditionSample& c : *fork) throttles.push_back(throttleMsg(c, ns_per_tick_));
  std::size_t next = 0;  // the next throttle record
  const std::string provenance_topic = topics_.at("world/provenance"),
                    info_topic = topics_.at("world/run_info"),
                    throttle_topic = topics_.at("environment/throttle");
  RunRecorder::Substitute substitute{
      fork ? std::vector<std::string>{provenance_topic, info_topic, throttle_topic}
           : std::vector<std::string>{provenance_topic},
      [&, provenance = provenanceMsg(outputs_.label), info = runInfoMsg(run, ns_per_tick_)](
          const std::string& topic, const ros::Time& time, BagWriter& out) {
        if (topic == provenance_topic) {
          out.write(topic, time, provenance);
        } else if (fork && topic == info_topic) {
          out.write(topic, time, info);
        } else if (fork && topic == throttle_topic) {
          if (next < throttles.size()) out.write(topic, time, throttles[next]);
          ++next;
        } else {
          return false;
        }
        return true;
      }};
  if (fork) {
    recorder_.resume(path_, outputs_.compression, policy(run, path_), std::move(segments), substitute, true);
  } else {  // the segments stay as they are; the provenance is replaced when they are joined
    std::vector<BagSegment> named(segments.size());
    for (std::size_t k = 0; k < segments.size(); ++k) named[k].file = segments[k].file;
    // Captures by value: the join that applies it runs at close().
    RunRecorder::Substitute provenance{{provenance_topic},
                                       [provenance_topic, msg = provenanceMsg(outputs_.label)](
                                           const std::string& topic, const ros::Time& time, BagWriter& out) {
                                         if (topic != provenance_topic) return false;
                                         out.write(topic, time, msg);
                                         return true;
                                       }};
    recorder_.resume(path_, outputs_.compression, policy(run, path_), std::move(segments), provenance, false);
    // Once the segments are verified: the interrupted writer's temporary bag and unnamed segments hold
    // ticks after the checkpoint, which this run records again (a fork's parent may still be running, so
    // only a resume clears them, and only once their writer has gone).
    if (!active.empty() && orphaned(active)) RunRecorder::removeLeftovers(active, named);
  }
  if (fork && next != throttles.size())
    throw std::runtime_error("the checkpoint's bag holds " + std::to_string(next) +
                             " condition records before tick " + std::to_string(tick) +
                             ", a fresh run of the fork " + std::to_string(throttles.size()));
}

}  // namespace swarm_forage
