// WorldConfig validation and arena YAML loading.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {
namespace {

/// Runs f, which must throw ParameterError, and returns its message.
template <typename F>
std::string parameterErrorOf(F&& f) {
  try {
    f();
  } catch (const ParameterError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected ParameterError, got another exception: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected ParameterError, nothing was thrown";
  return {};
}

#define EXPECT_CONTAINS(haystack, needle) \
  EXPECT_NE(std::string(haystack).find(needle), std::string::npos) << "message: " << (haystack)

/// The package root, from this file's path (no compile-time macro for it).
std::string packageRoot() {
  const std::string file = __FILE__;
  const std::string tail = "test/core/test_config.cpp";
  EXPECT_GE(file.size(), tail.size());
  EXPECT_EQ(file.compare(file.size() - tail.size(), tail.size(), tail), 0) << file;
  return file.substr(0, file.size() - tail.size());
}

/// A temporary file removed when the test ends.
class TempFile {
 public:
  explicit TempFile(const std::string& text) {
    char name[] = "/tmp/swarm_forage_test_XXXXXX";
    const int fd = mkstemp(name);
    EXPECT_GE(fd, 0);
    if (fd >= 0) close(fd);
    path_ = name;
    std::ofstream(path_) << text;
  }
  ~TempFile() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

TEST(Config, DefaultsAreValid) {
  WorldConfig c;
  EXPECT_NO_THROW(c.validate());
  EXPECT_DOUBLE_EQ(c.dt(), 0.2);
  EXPECT_GT(c.maxRobots(), 1000u);
  c.n_robots = c.maxRobots();
  EXPECT_NO_THROW(c.validate());
}

TEST(Config, RejectsBadSwarmSize) {
  WorldConfig c;
  c.n_robots = 0;
  EXPECT_CONTAINS(parameterErrorOf([&] { c.validate(); }), "n_robots");
  c.n_robots = c.maxRobots() + 1;
  const std::string msg = parameterErrorOf([&] { c.validate(); });
  EXPECT_CONTAINS(msg, "n_robots");
  EXPECT_CONTAINS(msg, std::to_string(c.maxRobots()));  // says what the valid range is
  // Bigger arenas take bigger swarms.
  WorldConfig big;
  big.arena.width = 96;
  big.arena.height = 48;
  EXPECT_GT(big.maxRobots(), c.maxRobots());
  big.n_robots = c.maxRobots() + 1;
  EXPECT_NO_THROW(big.validate());
}

TEST(Config, RejectsBadArenaSize) {
  for (double w : {0.0, -5.0, 3.0}) {
    WorldConfig c;
    c.arena.width = w;
    EXPECT_CONTAINS(parameterErrorOf([&] { c.validate(); }), "width");
  }
  WorldConfig c;
  c.arena.height = -1;
  EXPECT_CONTAINS(parameterErrorOf([&] { c.validate(); }), "height");
  c = WorldConfig{};
  c.arena.width = std::nan("");
  EXPECT_CONTAINS(parameterErrorOf([&] { c.validate(); }), "width");
}

TEST(Config, RefusesAnArenaWhoseGridsExceedTheMemoryLimit) {
  // 10,000 x 10,000 m is within the range of each side, but its grids would need tens of GiB: refused at
  // start-up, naming ~arena, its size, the estimate and the limit, instead of std::bad_alloc later.
  WorldConfig c;
  c.arena.name = "huge";
  c.arena.width = c.arena.height = 10000;
  EXPECT_GT(c.gridBytes(), 8 * kMaxGridBytes);
  const std::string msg = parameterErrorOf([&] { c.validate(); });
  EXPECT_CONTAINS(msg, "~arena huge (10000 x 10000 m) needs an estimated ");
  EXPECT_CONTAINS(msg, " GiB for the world's grids");
  EXPECT_CONTAINS(msg, "more than the limit of 4 GiB");
  EXPECT_CONTAINS(msg, "valid arenas cover at most about 1.2e+07 square metres");
  // Line of sight adds its mask (at most 2 MiB); a smaller cell makes a finer contact grid.
  WorldConfig small;
  EXPECT_LT(small.gridBytes(), 1 << 20);  // 32 x 16 m: a few hundred kB
  WorldConfig sighted = small;
  sighted.line_of_sight = true;
  EXPECT_GT(sighted.gridBytes(), small.gridBytes());
  EXPECT_LE(sighted.gridBytes(), small.gridBytes() + (2 << 20));
  // Long and thin within the limit is valid; the same area's estimate is the same whatever its shape.
  WorldConfig strip;
  strip.arena.width = 10000;
  strip.arena.height = 1000;
  EXPECT_NO_THROW(strip.validate());
  EXPECT_LT(strip.gridBytes(), kMaxGridBytes);
  WorldConfig square;
  square.arena.width = square.arena.height = 3162.2776601683795;
  EXPECT_NEAR(square.gridBytes() / strip.gridBytes(), 1.0, 0.01);
}

TEST(Config, RejectsBadBlocks) {
  WorldConfig c;
  c.arena.n_blocks = 0;
  EXPECT_CONTAINS(parameterErrorOf([&] { c.validate(); }), "blocks");
  c.arena.n_blocks = 100000;  // cannot fit the source
  EXPECT_CONTAINS(parameterErrorOf([&] { c.validate(); }), "blocks");
  c = WorldConfig{};
  c.arena.cube_size = -0.2;
  EXPECT_CONTAINS(parameterErrorOf([&] { c.validate(); }), "cube_size");
  c = WorldConfig{};
  c.arena.ramp_length = 0.1;  // shorter than a cube
  EXPECT_CONTAINS(parameterErrorOf([&] { c.validate(); }), "ramp_length");
}

TEST(Config, RejectsBadRobotAndTime) {
  WorldConfig c;
  c.robot.radius = 0;
  EXPECT_CONTAINS(parameterErrorOf([&] { c.validate(); }), "radius");
  c = WorldConfig{};
  c.ticks_per_second = 0;
  EXPECT_CONTAINS(parameterErrorOf([&] { c.validate(); }), "ticks_per_second");
}

TEST(Config, LoadsArenaYaml) {
  TempFile f(
      "# test arena\nname: tiny\nwidth: 20\nheight: 10.5\nblocks: 12\ncube_size: 0.25\nramp_length: 0.5\n");
  const ArenaConfig a = loadArenaYaml(f.path());
  EXPECT_EQ(a.name, "tiny");
  EXPECT_DOUBLE_EQ(a.width, 20.0);
  EXPECT_DOUBLE_EQ(a.height, 10.5);
  EXPECT_EQ(a.n_blocks, 12u);
  EXPECT_DOUBLE_EQ(a.cube_size, 0.25);
  EXPECT_DOUBLE_EQ(a.ramp_length, 0.5);
}

TEST(Config, ArenaYamlKeysDefault) {
  TempFile f("width: 64\nheight: 32\n");
  const ArenaConfig a = loadArenaYaml(f.path());
  EXPECT_DOUBLE_EQ(a.width, 64.0);
  EXPECT_DOUBLE_EQ(a.height, 32.0);
  EXPECT_EQ(a.n_blocks, ArenaConfig{}.n_blocks);
  EXPECT_DOUBLE_EQ(a.cube_size, ArenaConfig{}.cube_size);
  // Without a name it is named after its file, never after the built-in 32x16 it may differ from.
  EXPECT_EQ(a.name, f.path().substr(f.path().rfind('/') + 1));
}

TEST(Config, ArenaYamlUnknownKeyIsNamed) {
  TempFile typo("name: t\nwidht: 20\nheight: 10\n");
  const std::string msg = parameterErrorOf([&] { loadArenaYaml(typo.path()); });
  EXPECT_CONTAINS(msg, "unknown key 'widht' (line 2)");
  EXPECT_CONTAINS(msg, "valid keys: name, width, height, blocks, cube_size, ramp_length");
  TempFile nest("width: 20\nheight: 10\nnest_width: 3\n");
  EXPECT_CONTAINS(parameterErrorOf([&] { loadArenaYaml(nest.path()); }), "'nest_width'");
}

TEST(Config, ArenaYamlErrors) {
  const std::string missing = "/tmp/swarm_forage_no_such_dir/none.yaml";
  EXPECT_CONTAINS(parameterErrorOf([&] { loadArenaYaml(missing); }), missing);

  TempFile malformed("width: [1, 2\nheight: 16\n");
  const std::string msg = parameterErrorOf([&] { loadArenaYaml(malformed.path()); });
  EXPECT_CONTAINS(msg, "malformed");
  EXPECT_CONTAINS(msg, malformed.path());

  TempFile wrong_type("width: wide\n");
  EXPECT_CONTAINS(parameterErrorOf([&] { loadArenaYaml(wrong_type.path()); }), "width");

  TempFile negative_blocks("blocks: -5\n");
  EXPECT_CONTAINS(parameterErrorOf([&] { loadArenaYaml(negative_blocks.path()); }), "blocks");

  TempFile not_a_map("- 1\n- 2\n");
  EXPECT_NE(parameterErrorOf([&] { loadArenaYaml(not_a_map.path()); }), "");

  // A directory gave libstdc++'s "basic_filebuf::underflow"; a 5,000-character name passed validation,
  // then no bag could be named after it.
  EXPECT_CONTAINS(parameterErrorOf([&] { loadArenaYaml("/tmp"); }), "/tmp is a directory");
  TempFile long_name("name: " + std::string(5000, 'a') + "\n");
  const std::string too_long = parameterErrorOf([&] { loadArenaYaml(long_name.path()); });
  EXPECT_CONTAINS(too_long, "name must be 1 to 64 characters (got 5000");
  TempFile longest("name: " + std::string(kMaxArenaName, 'a') + "\n");
  EXPECT_EQ(loadArenaYaml(longest.path()).name, std::string(kMaxArenaName, 'a'));
}

TEST(Config, PackageArenaFilesParseAndValidate) {
  const std::string root = packageRoot();
  struct Expected {
    const char* file;
    const char* name;
    double width, height;
    uint32_t blocks;
  };
  for (const Expected& e :
       {Expected{"32x16.yaml", "32x16", 32, 16, 50}, Expected{"64x32.yaml", "64x32", 64, 32, 200},
        Expected{"96x48.yaml", "96x48", 96, 48, 460}}) {
    SCOPED_TRACE(e.file);
    ArenaConfig a;
    ASSERT_NO_THROW(a = loadArenaYaml(root + "config/arenas/" + e.file));
    EXPECT_EQ(a.name, e.name);
    EXPECT_DOUBLE_EQ(a.width, e.width);
    EXPECT_DOUBLE_EQ(a.height, e.height);
    EXPECT_EQ(a.n_blocks, e.blocks);
    EXPECT_DOUBLE_EQ(a.cube_size, 0.2);
    EXPECT_DOUBLE_EQ(a.ramp_length, 0.4);
    WorldConfig c;
    c.arena = a;
    c.n_robots = 1000;
    EXPECT_NO_THROW(c.validate());
  }
}

}  // namespace
}  // namespace swarm_forage
