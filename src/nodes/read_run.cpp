// read_run BAG [sample_interval:=1000] [ticks:=false]: one recorded run counted as metrics_node counts it
// (a replay of the bag), without a master: its samples as CSV, and with ticks:=true its joined ticks.
// What Python reads a run's series through (swarm_forage.runs), so the counting is not written twice.
#include <ros/time.h>

#include <cstdio>
#include <exception>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>

#include "swarm_forage/ros/params/known_params.hpp"
#include "swarm_forage/ros/params/params.hpp"
#include "swarm_forage/ros/runs/follower_messages.hpp"

namespace {
using namespace swarm_forage;

struct Options {
  uint32_t interval = 1000;
  bool ticks = false;
};

Options readOptions(const WordParams& p) {
  const std::vector<std::string> valid = knownParams(kReadRun);
  for (const std::string& name : p.unknown(valid))
    throw ParameterError(name + " is not a read_run parameter; valid: " + joinNames(valid));
  Options o;
  o.interval = static_cast<uint32_t>(readParam<int>(p, "sample_interval", kReadRun));
  o.ticks = readParam<bool>(p, "ticks", kReadRun);
  return o;
}

std::string usage() {
  return "usage: read_run BAG [NAME:=VALUE ...]\n"
         "One recorded run counted as metrics_node counts it when the bag is replayed: its samples as CSV\n"
         "(the columns of metrics_node's ~csv; a run cut short ends with a short, non-final sample) and, "
         "with\n"
         "ticks:=true, a blank line and each counted tick. Problems go to stderr.\n\nparameters:\n" +
         usageTable(tableUsage(kReadRun)) +
         "\nexample:\n  read_run results/demo.bag sample_interval:=500 ticks:=true\n\n"
         "exit codes: 0 read (or --help); 1 the bag cannot be read; 2 a bad or unknown parameter, or no "
         "BAG\n";
}

/// Collects what the follower counts; doubles are written exactly (17 digits).
class Printer : public RunFollower::Listener {
 public:
  std::ostringstream samples, ticks;
  Printer() {
    samples << std::setprecision(17) << kSampleCsvHeader;
    ticks << std::setprecision(17) << "tick,delivered,cumulative,in_avoidance,covered,ranges,throttle,last\n";
  }
  void counted(const FollowedRun&, const JoinedTick& t) override {
    const PerformanceRecord& p = t.performance;
    ticks << p.tick << ',' << p.delivered << ',' << p.cumulative << ',' << t.in_avoidance << ',' << t.covered
          << ',' << t.ranges << ',' << p.throttle << ',' << (p.last ? 1 : 0) << '\n';
  }
  void sample(const FollowedRun& run, const IntervalSample& s, uint64_t) override {
    writeSampleRow(samples, run.number, run.swarm_size, s);
  }
  void warn(const std::string& what) override { std::cerr << "read_run: " << what << '\n'; }
  void error(const std::string& what) override { std::cerr << "read_run: " << what << '\n'; }
};
}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--help" || std::string(argv[i]) == "-h") {
      std::cout << usage();
      return 0;
    }
  if (argc < 2 || std::string(argv[1]).find(":=") != std::string::npos) {
    std::cerr << usage();
    return 2;
  }
  ros::Time::init();
  Options o;
  try {
    o = readOptions(WordParams(std::vector<std::string>(argv + 2, argv + argc)));
  } catch (const std::exception& e) {
    std::cerr << "read_run: " << e.what() << '\n';
    return 2;
  }
  try {
    Printer printer;
    RunFollower follower(o.interval, RunFollower::Mode::kLive, &printer);
    feedBag(follower, argv[1]);
    follower.flush();
    std::cout << printer.samples.str();
    if (o.ticks) std::cout << '\n' << printer.ticks.str();
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "read_run: " << argv[1] << ": " << e.what() << '\n';
    return 1;
  }
}
