// run_tables DIR [out:=DIR] [sample_interval:=1000] [definitions:=paper] [dtw_band:=0]: the metric tables and
// group series of a directory of recorded runs, without a ROS master (what metrics/compute writes).
#include "swarm_forage/ros/run_tables.hpp"

#include <ros/time.h>

#include <cstdio>
#include <exception>

#include "swarm_forage/ros/params.hpp"

int main(int argc, char** argv) {
  using namespace swarm_forage;
  if (argc < 2 || std::string(argv[1]).find(":=") != std::string::npos) {
    std::fprintf(
        stderr,
        "usage: run_tables DIR [out:=DIR] [sample_interval:=TICKS] [definitions:=paper|authors_code_2019] "
        "[dtw_band:=SAMPLES]\n");
    return 2;
  }
  ros::Time::init();
  try {
    const WordParams p(std::vector<std::string>(argv + 2, argv + argc));
    const std::vector<std::string> valid{"out", "sample_interval", "definitions", "dtw_band"};
    for (const std::string& name : p.unknown(valid))
      throw ParameterError(
          name + " is not a run_tables parameter; valid: out, sample_interval, definitions, dtw_band");
    const std::string dir = argv[1];
    const std::string out = param<std::string>(p, "out", dir);
    const auto interval = static_cast<uint32_t>(paramInRange(p, "sample_interval", 1000, 1, 100000000));
    const Definitions defs =
        parseDefinitions(paramOneOf(p, "definitions", "paper", {"paper", "authors_code_2019"}));
    const int band = paramInRange(p, "dtw_band", 0, 0, 100000000);
    RunBagCache bags(interval);
    const ComputedTables t =
        computeTables(bags, dir, out, defs, band > 0 ? std::optional<std::size_t>(band) : std::nullopt);
    for (const std::string& problem : t.problems) std::fprintf(stderr, "run_tables: %s\n", problem.c_str());
    std::printf("run_tables: %s: %s\n", dir.c_str(), t.summary.c_str());
    for (const std::string& f : t.files) std::printf("  %s\n", f.c_str());
    return 0;
  } catch (const ParameterError& e) {
    std::fprintf(stderr, "run_tables: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "run_tables: %s\n", e.what());
    return 1;
  }
}
