// run_experiment name:=value ...: one headless run (no ROS master), recorded like a node-graph run;
// check:=true only validates the parameters; --help (or no argument) prints every parameter;
// --conditions checks an experiment file's conditions (condition_ros.hpp); --models lists ~model's and
// ~quirks' valid values; --arenas the arenas ~arena names and their files; --identity prints the identity
// and bag name of the runs whose words it reads.
#include <ros/time.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <exception>
#include <iostream>
#include <sstream>

#include "swarm_forage/core/controllers/controller_registry.hpp"
#include "swarm_forage/core/run/model_version.hpp"
#include "swarm_forage/core/world/fordyca_quirks.hpp"
#include "swarm_forage/ros/headless/headless_run.hpp"
#include "swarm_forage/ros/messages/condition_ros.hpp"
#include "swarm_forage/ros/messages/run_messages.hpp"
#include "swarm_forage/ros/nodes/controller_plugins.hpp"

namespace {
std::atomic<bool> g_stop{false};
void onSignal(int) { g_stop = true; }

// YAML, for scripts: what would make a record.
int printVersion() {
  std::printf("model_version: %u\ncode: \"%s\"\n", swarm_forage::kModelVersion,
              swarm_forage::codeDescription());
  return 0;
}

// YAML, for scripts: the controller kinds. Every plugin found is loaded, each in a process of its own; one
// that cannot be is named on stderr and left out.
int printControllers() {
  std::ostringstream listing, errors;
  swarm_forage::listControllerKinds(listing, errors);
  std::istringstream lines(errors.str());
  for (std::string line; std::getline(lines, line);)
    std::fprintf(stderr, "run_experiment: %s\n", line.c_str());
  std::printf("%s", listing.str().c_str());
  return 0;
}

// YAML, for scripts: ~model's and ~quirks' valid values.
int printModels() {
  std::printf("default: %s\nmodels: [", swarm_forage::modelNames().front().c_str());
  for (std::size_t i = 0; i < swarm_forage::modelNames().size(); ++i)
    std::printf("%s%s", i ? ", " : "", swarm_forage::modelNames()[i].c_str());
  std::printf("]\nquirks:\n");
  for (const swarm_forage::QuirkInfo& q : swarm_forage::quirkList())
    std::printf("  - {name: %s, side: %s, fordyca_2019: %s, what: \"%s\"}\n", q.name,
                q.world ? "world" : "controller", q.fordyca_2019 ? "true" : "false", q.what);
  return 0;
}

// YAML, for scripts: what ~arena names.
int printArenas() {
  try {
    for (const std::string& name : swarm_forage::arenaNames()) {
      const swarm_forage::ArenaConfig a = swarm_forage::loadArena(name);
      std::printf("- {arena: \"%s\", name: \"%s\", file: \"%s\", width: %.17g, height: %.17g}\n",
                  name.c_str(), a.name.c_str(), swarm_forage::arenaFile(name).c_str(), a.width, a.height);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "run_experiment: %s\n", e.what());
    return 1;
  }
  return 0;
}

// Every parameter: asked for (--help), on stdout; with no arguments, on stderr and exit 2 (not 50,000 silent
// ticks of the defaults).
int printUsage(bool help) {
  try {
    std::fprintf(help ? stdout : stderr, "%s", swarm_forage::HeadlessRun::usage().c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "run_experiment: %s\n", e.what());
    return 1;
  }
  return help ? 0 : 2;
}

// Takes check:=true or check:=false out of `words`: whether only to validate every parameter (the world
// places its robots) and exit without running.
bool takeCheck(std::vector<std::string>& words) {
  bool check = false;
  for (auto it = words.begin(); it != words.end();)
    if (*it == "check:=true" || *it == "check:=false") {
      check = *it == "check:=true";
      it = words.erase(it);
    } else {
      ++it;
    }
  return check;
}

// The run of `words` until its end or a signal: 0 finished, 1 stopped or failed, 2 a parameter refused, 3 not
// the identity expect_identity:= names.
int runOnce(const std::vector<std::string>& words, bool check) {
  try {
    swarm_forage::HeadlessRun run{swarm_forage::WordParams(words)};
    if (check) return 0;
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    const std::string stopped = run.run(g_stop);
    const std::string where = run.bag().empty() ? "" : "; recorded in " + run.bag();
    if (!stopped.empty()) {
      std::fprintf(stderr, "run_experiment: stopped: %s%s\n", stopped.c_str(), where.c_str());
      return 1;
    }
    std::fprintf(stderr, "run_experiment: finished%s\n", where.c_str());
    return 0;
  } catch (const swarm_forage::ParameterError& e) {
    std::fprintf(stderr, "run_experiment: %s\n", e.what());
    return 2;
  } catch (const swarm_forage::IdentityMismatch& e) {
    std::fprintf(stderr, "run_experiment: %s\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "run_experiment: %s\n", e.what());
    return 1;
  }
}
}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> words;
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]).rfind("__", 0) != 0) words.emplace_back(argv[i]);  // roslaunch's __name:= etc.
  const std::string only = words.size() == 1 ? words[0] : "";
  if (only == "--version") return printVersion();
  if (only == "--controllers") return printControllers();
  if (only == "--models") return printModels();
  if (only == "--arenas") return printArenas();
  if (only == "--identity") {  // swarm_forage.experiment: one call per plan
    ros::Time::init();
    return swarm_forage::printIdentities(std::cin, std::cout);
  }
  if (!words.empty() && words[0] == "--conditions")  // swarm_forage.experiment: one call per experiment file
    return swarm_forage::checkConditions({words.begin() + 1, words.end()}, std::cin, std::cout);
  const bool help =
      std::any_of(words.begin(), words.end(), [](const auto& w) { return w == "--help" || w == "-h"; });
  if (help || words.empty()) return printUsage(help);
  ros::Time::init();
  const bool check = takeCheck(words);
  return runOnce(words, check);
}
