// The controller constants' names: what the YAML files hold, what a run's identity lists.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <string>

#include "swarm_forage/core/controllers/controller_parameters.hpp"

namespace swarm_forage {
namespace {

std::string packageDir() {
  const std::string file = __FILE__;  // .../test/test_controller_parameters.cpp
  return file.substr(0, file.rfind("/test/"));
}

TEST(ControllerParameters, YamlFilesHoldExactlyTheKnownKeys) {
  for (const std::string& section : parameterSections()) {
    const YAML::Node root = YAML::LoadFile(packageDir() + "/config/controllers/" + section + ".yaml");
    const std::vector<std::string> names = parameterNames(section);
    std::vector<std::string> in_file;
    for (const auto& entry : root[section]) in_file.push_back(entry.first.as<std::string>());
    EXPECT_EQ(in_file, names) << section;
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
  c.crw.wander_force = 8;
  EXPECT_NE(describeConstants("crw", c), crw);
  c.gp_dpo.time_varying = true;
  EXPECT_NE(describeConstants("gp_dpo", c).find("gp_dpo/estimates=time_varying"), std::string::npos);
}

}  // namespace
}  // namespace swarm_forage
