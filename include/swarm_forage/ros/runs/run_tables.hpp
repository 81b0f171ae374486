#pragma once
// A directory of recorded runs into the metric tables (scalability, self-organization, flexibility)
// and each group's mean and 95 % confidence interval per sample: what metrics/compute answers and what
// run_tables (a sweep's last step, no master needed) writes.
#include <optional>
#include <string>
#include <vector>

#include "swarm_forage/core/metrics/bootstrap.hpp"
#include "swarm_forage/core/metrics/run_library.hpp"
#include "swarm_forage/ros/params/params.hpp"
#include "swarm_forage/ros/runs/run_bag.hpp"

namespace swarm_forage {

struct ComputedTables {
  std::size_t runs = 0, groups = 0;
  std::vector<std::string> problems;  // bags that cannot be used, duplicates, metrics that cannot be computed
  MetricTables tables;
  std::string series;              // series.csv: one row per group and sample
  std::vector<std::string> files;  // what was written
  std::string summary;             // "N runs in G groups (...); K problems"
  std::string error;               // why nothing was written: no usable run ("" when tables were written)
};

/// Reads the *.bag files of `directory` through `bags` (cut at its sample interval) and writes
/// scalability.csv, self_organization.csv, flexibility.csv and series.csv into `output` (created), and
/// bootstrap.csv when `bootstrap` asks for draws.
/// When no run is usable, writes nothing and says why in `error`. Throws std::runtime_error when the
/// directory cannot be read or a table cannot be written.
/// run_tables' options (out, sample_interval, definitions, dtw_band).
struct TablesOptions {
  std::string out;
  uint32_t sample_interval = 1000;
  Definitions definitions = Definitions::kPaper;
  std::optional<std::size_t> band;
  BootstrapOptions bootstrap{2000, 1};  // bootstrap.csv (bootstrap:=0: none)
};
/// Reads them from NAME:=VALUE words for the folder `dir` (out defaults to it); throws ParameterError for a
/// bad or unknown one, listing the valid ones.
TablesOptions readTablesOptions(const WordParams& p, const std::string& dir);
/// run_tables' --help: its options with defaults, valid values and docs, from the parameter table.
std::string tablesUsage();

ComputedTables computeTables(RunBagCache& bags, const std::string& directory, const std::string& output,
                             Definitions defs, std::optional<std::size_t> band = std::nullopt,
                             const BootstrapOptions& bootstrap = {});

}  // namespace swarm_forage
