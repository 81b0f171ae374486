#include "swarm_forage/ros/run_tables.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace swarm_forage {

namespace {
void writeFile(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
  if (!f) throw std::runtime_error("cannot write " + path);
}

double at(const std::vector<double>& v, std::size_t k) { return k < v.size() ? v[k] : 0.0; }
}  // namespace

std::string groupSeriesCsv(const RunLibrary& library) {
  std::ostringstream out;
  out.precision(10);
  out << "controller,arena,swarm_size,waveform,beta,alpha,runs,sample,tick_end,P_mean,P_ci95,p_mean,p_ci95,"
         "n_ca_mean,n_ca_ci95,sample_interval,identity\n";
  for (const auto& [key, group] : library.groups()) {
    if (!group.valid) continue;
    const RunSeries& m = group.mean;
    const RunSeries& c = group.ci95;
    for (std::size_t k = 0; k < m.P.size(); ++k)
      out << key.controller << ',' << key.arena << ',' << key.swarm_size << ',' << key.environment.waveform
          << ',' << key.environment.beta << ',' << key.environment.alpha << ',' << group.runs << ',' << k
          << ',' << (k + 1) * static_cast<uint64_t>(m.interval) << ',' << m.P[k] << ',' << at(c.P, k) << ','
          << at(m.p, k) << ',' << at(c.p, k) << ',' << at(m.n_ca, k) << ',' << at(c.n_ca, k) << ','
          << m.interval << ',' << key.identity() << '\n';
  }
  return out.str();
}

ComputedTables computeTables(RunBagCache& bags, const std::string& directory, const std::string& output,
                             Definitions defs, std::optional<std::size_t> band) {
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
  result.groups = runs.groups().size();
  result.tables = metricTables(runs, defs, band);
  result.problems.insert(result.problems.end(), result.tables.problems.begin(), result.tables.problems.end());
  result.series = groupSeriesCsv(runs);
  std::filesystem::create_directories(output);
  for (const auto& [name, text] :
       {std::pair<std::string, const std::string&>{"scalability", result.tables.scalability},
        {"self_organization", result.tables.self_organization},
        {"flexibility", result.tables.flexibility},
        {"series", result.series}}) {
    const std::string path = (std::filesystem::path(output) / (name + ".csv")).string();
    writeFile(path, text);
    result.files.push_back(path);
  }
  result.summary = std::to_string(result.runs) + " runs in " + std::to_string(result.groups) + " groups (" +
                   definitionsName(defs) + " definitions, sample interval " +
                   std::to_string(bags.interval()) + " ticks); " + std::to_string(result.problems.size()) +
                   " problems";
  return result;
}

}  // namespace swarm_forage
