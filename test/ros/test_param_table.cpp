// The parameter table (param_table.hpp): its defaults are the core's, its condition rows the core's, and
// what run_experiment's readers accept is what it declares.
#include <gtest/gtest.h>
#include <ros/time.h>

#include <set>
#include <string>

#include "swarm_forage/core/run/condition.hpp"
#include "swarm_forage/core/world/config.hpp"
#include "swarm_forage/core/world/fordyca_quirks.hpp"
#include "swarm_forage/ros/headless/headless_run.hpp"
#include "swarm_forage/ros/params/known_params.hpp"
#include "swarm_forage/ros/params/param_table.hpp"
#include "swarm_forage/ros/params/params.hpp"

namespace swarm_forage {
namespace {

TEST(ParamTable, DefaultsAreTheCores) {
  // A run's identity holds these: a table default that drifted from the core would change every run.
  const WorldConfig c;
  EXPECT_EQ(fallbackOf<double>(paramSpec("cache/size_fraction")), c.cache.size_fraction);
  EXPECT_EQ(fallbackOf<double>(paramSpec("cache/block_fraction")), c.cache.block_fraction);
  EXPECT_EQ(fallbackOf<int>(paramSpec("cache/min_blocks")), static_cast<int>(c.cache.min_blocks));
  EXPECT_EQ(fallbackOf<double>(paramSpec("cache/recreation_rate")), c.cache.recreation_rate);
  EXPECT_EQ(fallbackOf<double>(paramSpec("los_cell")), c.sight.cell);
  EXPECT_EQ(fallbackOf<int>(paramSpec("los_radius")), c.sight.radius);
  EXPECT_EQ(fallbackOf<std::string>(paramSpec("model")), modelNames().front());
  EXPECT_EQ(fallbackOf<std::string>(paramSpec("waveform")), Condition().waveform);
  EXPECT_EQ(fallbackOf<std::string>(paramSpec("target")), Condition().target);
  EXPECT_EQ(paramSpec("seed").hi, kMaxSeed);
}

TEST(ParamTable, ConditionRowsAreTheCores) {
  std::set<std::string> core, table;
  for (const ConditionParameter& c : conditionParameters()) core.insert(c.name);
  for (const ParamSpec& s : paramTable())
    if (s.type == ParamType::kCondition) table.insert(s.name);
  EXPECT_EQ(core, table);
}

TEST(ParamTable, EveryRowIsReadAndNamedOncePerReader) {
  for (unsigned r = 1; *readerName(static_cast<ParamReader>(r)); r <<= 1) {
    std::set<std::string> seen;
    for (const ParamSpec& s : paramTable(static_cast<ParamReader>(r)))
      EXPECT_TRUE(seen.insert(s.name).second)
          << s.name << " twice for " << readerName(static_cast<ParamReader>(r));
  }
  for (const ParamSpec& s : paramTable()) {
    EXPECT_NE(s.readers, 0u) << s.name;
    EXPECT_NE(std::string(s.doc), "") << s.name;
    if (s.type == ParamType::kInt || s.type == ParamType::kNumber) {
      const double d = fallbackOf<double>(s);
      EXPECT_TRUE(d >= s.lo && d <= s.hi) << s.name << ": its default is out of its range";
    }
  }
  EXPECT_EQ(paramSpec("ticks", kReadRun).type, ParamType::kBool);
  EXPECT_EQ(paramSpec("ticks").type, ParamType::kInt);
  EXPECT_THROW(paramSpec("n_robts"), std::logic_error);
}

TEST(ParamTable, ValidTextIsWhatTheMessagesSay) {
  EXPECT_EQ(validText(paramSpec("n_robots")).rfind("a whole number in [1, 10000000]", 0), 0u);
  EXPECT_EQ(validText(paramSpec("seed")), "a whole number in [0, 2147483647]");
  EXPECT_EQ(validText(paramSpec("ticks_per_second")), "a number in [0.001, 1000]");
  EXPECT_EQ(validText(paramSpec("controller")).rfind("one of crw, dpo, gp_dpo or a plugin's", 0), 0u);
  EXPECT_EQ(validText(paramSpec("compression")), "one of none, lz4, bz2");
  EXPECT_EQ(fallbackText(paramSpec("bag")), "''");
}

TEST(ParamTable, RunExperimentReadsWhatItDeclares) {
  ros::Time::init();
  const WordParams defaults({});
  HeadlessRun probe(defaults);  // every reader tells what it accepts
  const std::vector<std::string> known = knownParams(kRunExperiment);
  std::set<std::string> read;
  for (const ParamUsage& u : defaults.usage()) {
    read.insert(u.name);
    EXPECT_TRUE(unknownNames({u.name}, known).empty()) << u.name << " is read but not declared";
    if (!unknownNames({u.name}, controllerSections()).empty() && u.name.rfind("noise/", 0) != 0) {
      const ParamSpec& s = paramSpec(u.name, kRunExperiment);
      EXPECT_EQ(u.fallback, fallbackText(s)) << u.name;
      EXPECT_EQ(u.valid, validText(s)) << u.name;
    }
  }
  for (const ParamSpec& s : paramTable(kRunExperiment)) {
    if (s.type != ParamType::kSection) {
      EXPECT_TRUE(read.count(s.name)) << s.name << " is declared but not read";
    }
  }
}

}  // namespace
}  // namespace swarm_forage
