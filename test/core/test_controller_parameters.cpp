// The controller registry and the constants' names: which kinds exist and what each needs, what the
// YAML files hold, what a run's identity lists.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/controllers/crw.hpp"
#include "swarm_forage/core/controllers/gp_dpo.hpp"

namespace swarm_forage {
namespace {

std::string packageDir() {
  const std::string file = __FILE__;  // .../test/core/test_controller_parameters.cpp
  return file.substr(0, file.rfind("/test/"));
}

TEST(ControllerRegistry, ListsEveryKindWithWhatTheWorldComputesForIt) {
  // A kind missing here was not linked in: its registrar never ran.
  const std::vector<std::string>& names = controllerNames();
  for (const char* kind : {"crw", "dpo", "gp_dpo"})
    EXPECT_NE(std::find(names.begin(), names.end(), kind), names.end()) << kind;
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
  EXPECT_FALSE(controllerKind("crw").line_of_sight);
  EXPECT_TRUE(controllerKind("dpo").line_of_sight);
  EXPECT_TRUE(controllerKind("gp_dpo").static_cache);
  EXPECT_FALSE(controllerKind("dpo").static_cache);
  EXPECT_EQ(controllerKind("gp_dpo").display_name, "GP-DPO");
  const WorldConfig w = configuredFor(WorldConfig{}, "gp_dpo");
  EXPECT_TRUE(w.line_of_sight && w.cache.enabled);
  try {
    controllerKind("levy");
    FAIL() << "no exception";
  } catch (const ParameterError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("controller 'levy' is unknown; valid: crw, dpo, gp_dpo", 0), 0u)
        << e.what();
  }
  const YAML::Node kinds = YAML::Load(describeControllerKinds());
  ASSERT_EQ(kinds.size(), names.size());
  for (std::size_t k = 0; k < names.size(); ++k) EXPECT_EQ(kinds[k]["name"].as<std::string>(), names[k]);
  EXPECT_EQ(kinds[0]["name"].as<std::string>(), "crw");
  EXPECT_FALSE(kinds[0]["line_of_sight"].as<bool>());
  EXPECT_EQ(kinds[2]["colour"].as<std::string>(), "tab:green");
  EXPECT_EQ(kinds[2]["constants"].as<std::vector<std::string>>(),
            (std::vector<std::string>{"crw", "dpo", "gp_dpo"}));
  for (std::size_t k = 0; k < names.size(); ++k) {  // every built-in saves and resumes (sweeps fork them)
    EXPECT_TRUE(kinds[k]["checkpointable"].as<bool>()) << names[k];
    EXPECT_TRUE(checkpointableKind(names[k])) << names[k];
  }
}

TEST(ControllerParameters, YamlFilesHoldExactlyTheKnownKeysAtTheCoreDefaults) {
  // run_experiment reads no YAML: its runs equal the graph's only while the files hold the defaults.
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(packageDir() + "/config/controllers"))
    files.push_back(e.path().stem().string());
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files, controllerNames()) << "one config/controllers/<kind>.yaml per registered kind";
  for (const std::string& kind : controllerNames())  // the check a plugin's defaults pass when it loads
    EXPECT_NO_THROW(
        checkDefaultsFile(controllerKind(kind), packageDir() + "/" + controllerKind(kind).defaults))
        << kind;
  const std::string crw = packageDir() + "/config/controllers/crw.yaml";
  try {
    checkDefaultsFile(controllerKind("dpo"), crw);
    FAIL() << "no exception";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("must hold the map 'dpo:'"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(parameterNames("nope").empty());
}

TEST(ControllerParameters, DescribeNamesWhatAKindUses) {
  ControllerConfigs c;
  const std::string crw = describeConstants("crw", c), gp = describeConstants("gp_dpo", c);
  EXPECT_NE(crw.find("crw/wander_force=9 "), std::string::npos) << crw;
  EXPECT_NE(crw.find("crw/wander_step_deg=5 "), std::string::npos) << crw;  // degrees, as in the YAML
  EXPECT_EQ(crw.find("dpo/"), std::string::npos);
  EXPECT_NE(describeConstants("dpo", c).find("dpo/pheromone_decay=1e-05"), std::string::npos);
  EXPECT_NE(gp.find("gp_dpo/estimates=ideal"), std::string::npos) << gp;
  EXPECT_LT(gp.find("crw/"), gp.find("dpo/"));  // base first
  c.of<CrwConfig>("crw").wander_force = 8;
  EXPECT_NE(describeConstants("crw", c), crw);
  c.of<GpDpoConfig>("gp_dpo").time_varying = true;
  EXPECT_NE(describeConstants("gp_dpo", c).find("gp_dpo/estimates=time_varying"), std::string::npos);
  EXPECT_THROW(c.of<CrwConfig>("dpo"), std::logic_error);
  const ControllerConfigs copy = c;  // a deep copy
  c.of<CrwConfig>("crw").wander_force = 7;
  EXPECT_EQ(copy.of<CrwConfig>("crw").wander_force, 8);
}

}  // namespace
}  // namespace swarm_forage
