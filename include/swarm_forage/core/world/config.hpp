#pragma once
// Model parameters (docs/design-model.md, Model) with their defaults, and their validation.
#include <cstdint>
#include <stdexcept>
#include <string>

#include "swarm_forage/core/util/geometry.hpp"
#include "swarm_forage/core/world/fordyca_quirks.hpp"
#include "swarm_forage/core/world/population.hpp"
#include "swarm_forage/core/world/saa_noise.hpp"
#include "swarm_forage/core/world/sensing.hpp"

namespace swarm_forage {

/// Thrown for an invalid parameter; what() names the parameter and its valid range.
class ParameterError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

struct ArenaConfig {
  std::string name = "32x16";
  double width = 32.0;
  double height = 16.0;
  uint32_t n_blocks = 50;
  double cube_size = 0.2;    // cubes are cube_size x cube_size
  double ramp_length = 0.4;  // ramps are ramp_length x cube_size
  double start_margin = 2.0;

  Rect bounds() const { return {0, 0, width, height}; }
  Rect nest() const { return Rect::centered(0.1 * width, height / 2, 0.1 * width, 0.8 * height); }
  Rect source() const { return {0.8 * width, 1.0, 0.9 * width, height - 1.0}; }
  Rect start() const { return {start_margin, start_margin, width - start_margin, height - start_margin}; }
  /// The three nest lights along the nest's long axis (-25 %, centre, +25 %).
  Vec2 light(int i) const {
    const Rect n = nest();
    const double cx = (n.min_x + n.max_x) / 2, cy = (n.min_y + n.max_y) / 2;
    const double offset = (i - 1) * 0.25 * (n.width() > n.height() ? n.width() : n.height());
    return n.width() > n.height() ? Vec2(cx + offset, cy) : Vec2(cx, cy + offset);
  }
  static constexpr int kLights = 3;
};

struct RobotConfig {
  double radius = 0.085;
  double axle = 0.14;
  double max_speed = 0.1;        // per wheel [m/s]
  double threat_distance = 0.1;  // obstacles closer than this to the body threaten
  double fov = deg2rad(150.0);   // half-angle of the proximity field of view
};

/// The GP-DPO static cache (implemented in static_cache.cpp).
struct CacheConfig {
  bool enabled = false;
  double size_fraction = 0.1;     // side = size_fraction x arena width
  double block_fraction = 0.1;    // a new cache holds floor(block_fraction x blocks) blocks
  uint32_t min_blocks = 2;        // a pick-up leaving fewer removes the cache
  double recreation_rate = 0.05;  // P(re-create per tick) = 1 - exp(-rate H / C)  (-rate H when C = 0)

  /// Throws ParameterError when the cache would not fit between the nest and the source.
  void validate(const ArenaConfig& arena) const;
  Rect area(const ArenaConfig& arena) const;
  uint32_t initialBlocks(const ArenaConfig& arena) const;
};

struct WorldConfig {
  ArenaConfig arena;
  RobotConfig robot;
  uint32_t n_robots = 64;
  uint32_t seed = 0;
  double ticks_per_second = 5.0;
  /// Packing fraction of the start region above which robots are said not to fit.
  double max_start_packing = 0.35;
  /// Compute each robot's line of sight (DPO family).
  bool line_of_sight = false;
  /// With light_occlusion: the controller reads the light only while its robot carries a block, so only
  /// carriers' lights are shadowed (the costly part); the others' light readings are NaN, "not sensed".
  /// Changes no run's outcome (test_quirks_world), so it is no part of a run's identity.
  bool light_only_carrying = false;
  /// FORDYCA's penalty deconfliction: at most one free-block pick-up and one nest drop finish per tick,
  /// swarm wide, first requested first served (ties by robot id). Off by default. With the block_penalties
  /// quirk, FORDYCA's penalty handlers replace it (then it has no effect).
  bool serialize_block_ops = false;
  LineOfSight sight;
  CacheConfig cache;
  PopulationConfig population;  // off by default
  /// Sensor and actuator noise; off by default.
  SaaNoise noise;
  /// FORDYCA 2019's quirks (the world applies worldSide()); none by default.
  FordycaQuirks quirks;

  double dt() const { return 1.0 / ticks_per_second; }
  /// Largest swarm that fits the start region of this arena.
  uint32_t maxRobots() const;
  /// The bytes of the world's grids over the arena (contacts, blocks, line of sight): they grow with its
  /// area, whatever the swarm (world.cpp, beside the grids' cell sizes).
  double gridBytes() const;
  /// Throws ParameterError naming the offending parameter and its valid range (an arena whose grids
  /// need more than kMaxGridBytes too).
  void validate() const;
  /// The constants beyond arena, N, seed and run length that change a run's outcome, as canonical
  /// "name=value" words (robot body and sensors; line of sight, cache, noise, population dynamics and the
  /// world's quirks where enabled).
  std::string describeConstants() const;
};

/// The most memory the world's grids may take (WorldConfig::gridBytes): 4 GiB.
constexpr double kMaxGridBytes = 4.0 * (1ull << 30);

/// A number as canonical text: the shortest form that reads back to the same double.
std::string canonicalNumber(double v);

/// The longest arena name: it is part of every recorded run's file name.
constexpr std::size_t kMaxArenaName = 64;

/// Reads an arena from a YAML file (keys: name, width, height, blocks, cube_size, ramp_length; without
/// `name` the arena is named after the file). Throws ParameterError for a missing/malformed file, an
/// unknown key (naming it and the valid ones) or out-of-range values.
ArenaConfig loadArenaYaml(const std::string& path);

}  // namespace swarm_forage
