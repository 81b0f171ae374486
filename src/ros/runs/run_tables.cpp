#include "swarm_forage/ros/runs/run_tables.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "swarm_forage/ros/params/known_params.hpp"

namespace swarm_forage {

namespace {
void writeFile(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
  if (!f) throw std::runtime_error("cannot write " + path);
}
}  // namespace

TablesOptions readTablesOptions(const WordParams& p, const std::string& dir) {
  const std::vector<std::string> valid = knownParams(kRunTables);
  for (const std::string& name : p.unknown(valid))
    throw ParameterError(name + " is not a run_tables parameter; valid: " + joinNames(valid));
  TablesOptions o;
  o.out = param<std::string>(p, "out", dir);  // the table's default says DIR
  o.sample_interval = static_cast<uint32_t>(readParam<int>(p, "sample_interval"));
  o.definitions = parseDefinitions(readParam<std::string>(p, "definitions"));
  const int band = readParam<int>(p, "dtw_band");
  if (band > 0) o.band = static_cast<std::size_t>(band);
  o.bootstrap.draws = static_cast<uint32_t>(readParam<int>(p, "bootstrap"));
  o.bootstrap.seed = static_cast<uint64_t>(readParam<int>(p, "bootstrap_seed"));
  return o;
}

std::string tablesUsage() {
  std::ostringstream out;
  out << "usage: run_tables DIR [NAME:=VALUE ...]\n"
         "The metric tables (scalability.csv, self_organization.csv, flexibility.csv), the robustness of "
         "runs\n"
         "with noise or population dynamics (robustness.csv per group, robustness_runs.csv per run) and "
         "each\n"
         "group's mean series (series.csv; tick_end is a sample's last tick) of the recorded runs (*.bag) "
         "in\n"
         "DIR, without a ROS master: what metrics/compute writes. Unusable bags are listed as problems.\n"
         "bootstrap.csv: P, e, Z, R and A of every group in draw 0 (as measured) and in `bootstrap` draws "
         "with\n"
         "each group's seeds resampled (docs/metrics.md, Bootstrap); metrics/compute writes none.\n\n"
         "parameters:\n"
      << usageTable(tableUsage(kRunTables))
      << "  (dtw_band 0: no band)\n\n"
         "examples:\n"
         "  run_tables results/sweep/runs out:=results/sweep/tables sample_interval:=1000\n"
         "  run_tables results/library definitions:=authors_code\n\n"
         "exit codes: 0 tables written (or --help); 1 no usable run in DIR, or DIR unreadable;\n"
         "2 a bad or unknown parameter, or no DIR\n";
  return out.str();
}

ComputedTables computeTables(RunBagCache& bags, const std::string& directory, const std::string& output,
                             Definitions defs, std::optional<std::size_t> band,
                             const BootstrapOptions& bootstrap) {
  ComputedTables result;
  RunLibrary runs;
  const RunBagCache::Scan scan = bags.scan(directory);
  result.problems = scan.problems;
  for (const std::string& path : scan.unfinished)
    result.problems.push_back(path +
                              ": never closed: still being recorded, or its writer was killed (incomplete)");
  for (const RunRecord* r : scan.runs) {
    const AddResult added = runs.add(*r);
    result.runs += added.added;
    if (!added.problem.empty()) result.problems.push_back(added.problem);
  }
  if (result.runs == 0) {  // tables of nothing would look like a finished, empty study
    result.error = directory + ": no usable recorded run (" +
                   (result.problems.empty()
                        ? std::string("no *.bag file")
                        : std::to_string(result.problems.size()) +
                              (result.problems.size() == 1 ? " problem" : " problems") + ", listed") +
                   "); no table written";
    return result;
  }
  result.groups = runs.groups().size();
  result.tables = metricTables(runs, defs, band);
  result.problems.insert(result.problems.end(), result.tables.problems.begin(), result.tables.problems.end());
  result.series = groupSeriesCsv(runs);
  const std::string draws = bootstrap.draws > 0 ? bootstrapCsv(runs, defs, band, bootstrap) : std::string();
  std::filesystem::create_directories(output);
  for (const auto& [name, text] :
       {std::pair<std::string, const std::string&>{"scalability", result.tables.scalability},
        {"self_organization", result.tables.self_organization},
        {"flexibility", result.tables.flexibility},
        {"robustness", result.tables.robustness},
        {"robustness_runs", result.tables.robustness_runs},
        {"series", result.series}}) {
    const std::string path = (std::filesystem::path(output) / (name + ".csv")).string();
    writeFile(path, text);
    result.files.push_back(path);
  }
  if (bootstrap.draws > 0) {
    const std::string path = (std::filesystem::path(output) / "bootstrap.csv").string();
    writeFile(path, draws);
    result.files.push_back(path);
  }
  result.summary = std::to_string(result.runs) + " runs in " + std::to_string(result.groups) + " groups (" +
                   definitionsName(defs) + " definitions, sample interval " +
                   std::to_string(bags.interval()) + " ticks); " + std::to_string(result.problems.size()) +
                   " problems" +
                   (bootstrap.draws > 0 ? "; bootstrap: " + std::to_string(bootstrap.draws) + " draws" : "");
  return result;
}

}  // namespace swarm_forage
