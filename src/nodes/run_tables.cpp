// run_tables DIR [out:=DIR] [sample_interval:=1000] [definitions:=paper] [dtw_band:=0]: the metric tables and
// group series of a directory of recorded runs, without a ROS master (what metrics/compute writes).
#include "swarm_forage/ros/runs/run_tables.hpp"

#include <ros/time.h>

#include <cstdio>
#include <exception>
#include <string>

int main(int argc, char** argv) {
  using namespace swarm_forage;
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--help" || std::string(argv[i]) == "-h") {
      std::printf("%s", tablesUsage().c_str());
      return 0;
    }
  if (argc < 2 || std::string(argv[1]).find(":=") != std::string::npos) {
    std::fprintf(stderr, "%s", tablesUsage().c_str());
    return 2;
  }
  ros::Time::init();
  try {
    const std::string dir = argv[1];
    const TablesOptions o =
        readTablesOptions(WordParams(std::vector<std::string>(argv + 2, argv + argc)), dir);
    RunBagCache bags(o.sample_interval);
    const ComputedTables t = computeTables(bags, dir, o.out, o.definitions, o.band, o.bootstrap);
    for (const std::string& problem : t.problems) std::fprintf(stderr, "run_tables: %s\n", problem.c_str());
    if (!t.error.empty()) {
      std::fprintf(stderr, "run_tables: %s\n", t.error.c_str());
      return 1;
    }
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
