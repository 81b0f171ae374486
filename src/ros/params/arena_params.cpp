// ~arena: an arena's name (config/arenas/NAME.yaml) or a path. The one lookup of an arena by name; Python
// asks it through `run_experiment --arenas`.
#include <ros/package.h>

#include <algorithm>
#include <filesystem>

#include "swarm_forage/ros/params/known_params.hpp"
#include "swarm_forage/ros/params/params.hpp"

namespace swarm_forage {

namespace {
std::filesystem::path arenaDir() {
  return std::filesystem::path(ros::package::getPath("swarm_forage")) / "config" / "arenas";
}
}  // namespace

std::vector<std::string> arenaNames() {
  namespace fs = std::filesystem;
  std::vector<std::string> names;
  std::error_code ec;
  if (fs::is_directory(arenaDir(), ec))
    for (const auto& e : fs::directory_iterator(arenaDir()))
      if (e.path().extension() == ".yaml") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string arenaFile(const std::string& name_or_path) {
  // A file name (a '/' or an extension, e.g. arena.yml) is a path, never taken for an arena's name.
  if (name_or_path.find_first_of("/.") != std::string::npos) return name_or_path;
  return (arenaDir() / (name_or_path + ".yaml")).string();
}

ArenaConfig loadArena(const std::string& name_or_path) {
  const std::string file = arenaFile(name_or_path);
  if (file == name_or_path) try {
      return loadArenaYaml(file);
    } catch (const ParameterError& e) {
      throw ParameterError("~arena: " + std::string(e.what()));
    }
  std::error_code ec;  // a name too long for a file name is just not an arena's
  if (!std::filesystem::exists(file, ec))
    throw ParameterError("~arena '" + name_or_path + "' is unknown; valid: " + joinNames(arenaNames()) +
                         " (config/arenas/*.yaml) or a path to an arena YAML file");
  return loadArenaYaml(file);
}

}  // namespace swarm_forage
