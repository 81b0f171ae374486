#include "swarm_forage/core/world/config.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

namespace swarm_forage {

namespace {
[[noreturn]] void fail(const std::string& what) { throw ParameterError(what); }

template <typename T>
T read(const YAML::Node& node, const char* key, T fallback, const std::string& path) {
  if (!node[key]) return fallback;
  try {
    return node[key].as<T>();
  } catch (const YAML::Exception&) {
    fail("arena file " + path + ": '" + key + "' has the wrong type (line " +
         std::to_string(node[key].Mark().line + 1) + ")");
  }
}
}  // namespace

uint32_t WorldConfig::maxRobots() const {
  const Rect s = arena.start();
  if (s.width() <= 0 || s.height() <= 0) return 0;
  const double disk = kPi * robot.radius * robot.radius;
  return static_cast<uint32_t>(std::floor(max_start_packing * s.width() * s.height() / disk));
}

void WorldConfig::validate() const {
  const double min_side = 2 * arena.start_margin + 1.0;
  if (!(arena.width >= min_side && arena.width <= 10000))
    fail("arena width must be in [" + std::to_string(min_side) + ", 10000] m (got " +
         std::to_string(arena.width) + ")");
  if (!(arena.height >= min_side && arena.height <= 10000))
    fail("arena height must be in [" + std::to_string(min_side) + ", 10000] m (got " +
         std::to_string(arena.height) + ")");
  if (!(arena.cube_size > 0 && arena.cube_size <= 1.0))
    fail("arena cube_size must be in (0, 1] m (got " + std::to_string(arena.cube_size) + ")");
  if (!(arena.ramp_length >= arena.cube_size && arena.ramp_length <= 2.0))
    fail("arena ramp_length must be in [cube_size, 2] m (got " + std::to_string(arena.ramp_length) + ")");
  const Rect src = arena.source();
  const uint32_t max_blocks = static_cast<uint32_t>(
      std::floor(0.25 * src.width() * src.height() / (arena.ramp_length * arena.cube_size)));
  if (arena.n_blocks < 1 || arena.n_blocks > max_blocks)
    fail("arena blocks must be in [1, " + std::to_string(max_blocks) + "] for a " + arena.name +
         " arena (got " + std::to_string(arena.n_blocks) + ")");
  if (!(robot.radius > 0 && robot.radius <= 1.0))
    fail("robot radius must be in (0, 1] m (got " + std::to_string(robot.radius) + ")");
  if (!(robot.axle > 0 && robot.axle <= 2.0)) fail("robot axle must be in (0, 2] m");
  if (!(robot.max_speed > 0 && robot.max_speed <= 1.0)) fail("robot max_speed must be in (0, 1] m/s");
  if (!(ticks_per_second > 0 && ticks_per_second <= 1000))
    fail("ticks_per_second must be in (0, 1000] (got " + std::to_string(ticks_per_second) + ")");
  if (!(sight.cell > 0 && sight.cell <= 10)) fail("line of sight cell must be in (0, 10] m");
  if (sight.radius < 0 || sight.radius > 100) fail("line of sight radius must be in [0, 100] cells");
  if (const double bytes = gridBytes(); !(bytes <= kMaxGridBytes)) {
    // The grids grow with the area, whatever the swarm: say how large an area fits.
    const double area = arena.width * arena.height, per_m2 = bytes / area;
    char text[400];
    std::snprintf(
        text, sizeof text,
        " (%s x %s m) needs an estimated %.1f GiB for the world's grids (%.0f bytes a square metre), "
        "more than the limit of %.0f GiB: valid arenas cover at most about %.3g square metres",
        canonicalNumber(arena.width).c_str(), canonicalNumber(arena.height).c_str(), bytes / (1ull << 30),
        per_m2, kMaxGridBytes / (1ull << 30), kMaxGridBytes / per_m2);
    fail("~arena " + arena.name + text);
  }
  cache.validate(arena);
  population.validate(n_robots);
  noise.validate();
  const uint32_t max_n = maxRobots();
  if (n_robots < 1 || n_robots > max_n)
    fail("n_robots must be in [1, " + std::to_string(max_n) + "] for a " + arena.name + " arena (got " +
         std::to_string(n_robots) + "): robots start in [" + std::to_string(arena.start_margin) + ", X-" +
         std::to_string(arena.start_margin) + "] x [" + std::to_string(arena.start_margin) + ", Y-" +
         std::to_string(arena.start_margin) + "] without overlap");
}

std::string canonicalNumber(double v) {
  char buf[40];
  for (int precision = 6; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

std::string WorldConfig::describeConstants() const {
  std::string s;
  const auto add = [&s](const char* name, double v) {
    s += (s.empty() ? "" : " ") + std::string(name) + "=" + canonicalNumber(v);
  };
  add("robot/radius", robot.radius);
  add("robot/axle", robot.axle);
  add("robot/max_speed", robot.max_speed);
  add("robot/threat_distance", robot.threat_distance);
  add("robot/fov", robot.fov);
  add("start_margin", arena.start_margin);
  if (serialize_block_ops) add("serialize_block_ops", 1);
  if (line_of_sight) {
    add("los_cell", sight.cell);
    add("los_radius", sight.radius);
  }
  if (cache.enabled) {
    add("cache/size_fraction", cache.size_fraction);
    add("cache/block_fraction", cache.block_fraction);
    add("cache/min_blocks", cache.min_blocks);
    add("cache/recreation_rate", cache.recreation_rate);
  }
  if (population.enabled()) s += " " + population.describe(n_robots);
  if (noise.enabled()) s += " " + noise.describe();
  if (quirks.worldSide().any()) s += " " + quirks.worldSide().describe();
  return s;
}

ArenaConfig loadArenaYaml(const std::string& path) {
  YAML::Node root;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail("arena file " + path + " does not exist");
  if (std::filesystem::is_directory(path)) fail("arena file " + path + " is a directory, not a YAML file");
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    fail("arena file " + path + " cannot be read");
  } catch (const YAML::ParserException& e) {
    fail("arena file " + path + " is malformed YAML: " + e.what());
  }
  if (!root.IsMap()) fail("arena file " + path + " must be a YAML map with width, height, blocks");
  static const char* const kKeys[] = {"name", "width", "height", "blocks", "cube_size", "ramp_length"};
  for (const auto& entry : root) {
    const std::string key = entry.first.as<std::string>();
    if (std::find(std::begin(kKeys), std::end(kKeys), key) == std::end(kKeys))
      fail("arena file " + path + ": unknown key '" + key + "' (line " +
           std::to_string(entry.first.Mark().line + 1) +
           "); valid keys: name, width, height, blocks, cube_size, ramp_length");
  }
  ArenaConfig a;
  // Without a name, the arena is named after its file: never after a built-in arena it may differ from.
  a.name = read<std::string>(root, "name", std::filesystem::path(path).stem().string(), path);
  // The name enters every bag's file name (at most 255 bytes) and the run's identity.
  if (a.name.empty() || a.name.size() > kMaxArenaName)
    fail("arena file " + path + ": name must be 1 to " + std::to_string(kMaxArenaName) + " characters (got " +
         std::to_string(a.name.size()) + "; without name: the file's name is used): it names the run's bags");
  a.width = read<double>(root, "width", a.width, path);
  a.height = read<double>(root, "height", a.height, path);
  const int blocks = read<int>(root, "blocks", static_cast<int>(a.n_blocks), path);
  if (blocks < 1) fail("arena file " + path + ": blocks must be >= 1 (got " + std::to_string(blocks) + ")");
  a.n_blocks = static_cast<uint32_t>(blocks);
  a.cube_size = read<double>(root, "cube_size", a.cube_size, path);
  a.ramp_length = read<double>(root, "ramp_length", a.ramp_length, path);
  return a;
}

}  // namespace swarm_forage
