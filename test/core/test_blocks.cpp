// BlockField: placement in the source without overlap, point look-ups, pick-up and respawn.
#include <gtest/gtest.h>

#include <cstdint>

#include "swarm_forage/core/world/blocks.hpp"

namespace swarm_forage {
namespace {

ArenaConfig arena(double w, double h, uint32_t blocks) {
  ArenaConfig a;
  a.name = "test";
  a.width = w;
  a.height = h;
  a.n_blocks = blocks;
  return a;
}

bool inside(const Rect& inner, const Rect& outer) {
  return inner.min_x >= outer.min_x && inner.max_x <= outer.max_x && inner.min_y >= outer.min_y &&
         inner.max_y <= outer.max_y;
}

/// Every free block lies in the source and overlaps no other free block.
void expectValidLayout(const BlockField& f, const ArenaConfig& a) {
  const Rect src = a.source();
  for (std::size_t i = 0; i < f.size(); ++i) {
    const auto b = static_cast<int32_t>(i);
    if (f.carrier(b) >= 0) continue;
    EXPECT_TRUE(inside(f.footprint(b), src)) << "block " << b;
    for (std::size_t j = i + 1; j < f.size(); ++j) {
      const auto o = static_cast<int32_t>(j);
      if (f.carrier(o) >= 0) continue;
      EXPECT_FALSE(f.footprint(b).overlaps(f.footprint(o))) << "blocks " << b << " and " << o;
    }
  }
}

TEST(Blocks, InitPlacesAllBlocksInSourceWithoutOverlap) {
  for (const ArenaConfig& a : {arena(32, 16, 50), arena(64, 32, 200), arena(96, 48, 460)}) {
    BlockField f;
    f.init(a, 17);
    ASSERT_EQ(f.size(), a.n_blocks);
    expectValidLayout(f, a);
    uint32_t cubes = 0;
    for (std::size_t i = 0; i < f.size(); ++i) {
      const auto b = static_cast<int32_t>(i);
      EXPECT_EQ(f.carrier(b), -1);
      if (f.kind(b) == kCube) {
        ++cubes;
        EXPECT_DOUBLE_EQ(f.sizeX(b), a.cube_size);
      } else {
        EXPECT_DOUBLE_EQ(f.sizeX(b), a.ramp_length);
      }
      EXPECT_DOUBLE_EQ(f.sizeY(b), a.cube_size);
    }
    EXPECT_EQ(cubes, (a.n_blocks + 1) / 2);  // half cubes, half ramps
  }
}

TEST(Blocks, DenseSourceStillWithoutOverlap) {
  // Close to the most validation lets a 32 x 16 source take (a quarter of its area in ramps).
  const ArenaConfig a = arena(32, 16, 130);
  BlockField f;
  f.init(a, 5);
  ASSERT_EQ(f.size(), 130u);
  expectValidLayout(f, a);
}

TEST(Blocks, BlockAtFindsBlocksAndNothingElse) {
  const ArenaConfig a = arena(32, 16, 50);
  BlockField f;
  f.init(a, 2);
  for (std::size_t i = 0; i < f.size(); ++i) {
    const auto b = static_cast<int32_t>(i);
    EXPECT_EQ(f.blockAt(f.x(b), f.y(b)), b);
    const Rect fp = f.footprint(b);
    EXPECT_EQ(f.blockAt(fp.min_x + 1e-6, fp.min_y + 1e-6), b);  // corners of the footprint
    EXPECT_EQ(f.blockAt(fp.max_x - 1e-6, fp.max_y - 1e-6), b);
    EXPECT_NE(f.blockAt(fp.max_x + 1e-3, f.y(b)), b);  // just beside it
  }
  EXPECT_EQ(f.blockAt(16.0, 8.0), -1);  // open floor
  EXPECT_EQ(f.blockAt(1.0, 1.0), -1);
  EXPECT_EQ(f.blockAt(-1.0, 8.0), -1);  // outside the arena
  EXPECT_EQ(f.blockAt(40.0, 8.0), -1);
  EXPECT_EQ(f.blockAt(16.0, -0.3), -1);
}

TEST(Blocks, PickUpHidesAndRespawnRestores) {
  const ArenaConfig a = arena(32, 16, 50);
  BlockField f;
  f.init(a, 8);
  const int32_t b = 7;
  const double x = f.x(b), y = f.y(b);
  const uint64_t v0 = f.version();
  f.pickUp(b, 3);
  EXPECT_EQ(f.carrier(b), 3);
  EXPECT_EQ(f.blockAt(x, y), -1);
  EXPECT_GT(f.version(), v0);

  const uint64_t v1 = f.version();
  f.respawn(b);
  EXPECT_EQ(f.carrier(b), -1);
  EXPECT_GT(f.version(), v1);
  EXPECT_EQ(f.blockAt(f.x(b), f.y(b)), b);
  EXPECT_EQ(f.size(), 50u);
  expectValidLayout(f, a);

  // Many pick-up / respawn cycles keep the layout valid.
  for (int k = 0; k < 500; ++k) {
    const auto c = static_cast<int32_t>((k * 13) % f.size());
    f.pickUp(c, k);
    f.respawn(c);
  }
  expectValidLayout(f, a);
  for (std::size_t i = 0; i < f.size(); ++i) {
    const auto c = static_cast<int32_t>(i);
    EXPECT_EQ(f.blockAt(f.x(c), f.y(c)), c);
  }
}

TEST(Blocks, PutDownPlacesAtThePoint) {
  const ArenaConfig a = arena(32, 16, 50);
  BlockField f;
  f.init(a, 8);
  f.pickUp(0, 1);
  f.putDown(0, 12.0, 5.0);
  EXPECT_EQ(f.carrier(0), -1);
  EXPECT_EQ(f.blockAt(12.0, 5.0), 0);
  EXPECT_DOUBLE_EQ(f.x(0), 12.0);
  EXPECT_DOUBLE_EQ(f.y(0), 5.0);
}

TEST(Blocks, SameSeedSameLayoutDifferentSeedDiffers) {
  const ArenaConfig a = arena(64, 32, 200);
  BlockField f1, f2, f3;
  f1.init(a, 99);
  f2.init(a, 99);
  f3.init(a, 100);
  bool differs = false;
  for (std::size_t i = 0; i < f1.size(); ++i) {
    const auto b = static_cast<int32_t>(i);
    EXPECT_EQ(f1.x(b), f2.x(b));
    EXPECT_EQ(f1.y(b), f2.y(b));
    EXPECT_EQ(f1.kind(b), f2.kind(b));
    differs |= f1.x(b) != f3.x(b) || f1.y(b) != f3.y(b);
  }
  EXPECT_TRUE(differs);
  // Respawns are reproducible too.
  f1.pickUp(4, 0);
  f1.respawn(4);
  f2.pickUp(4, 0);
  f2.respawn(4);
  EXPECT_EQ(f1.x(4), f2.x(4));
  EXPECT_EQ(f1.y(4), f2.y(4));
  // Re-initialising gives the same layout again.
  BlockField f4, f5;
  f4.init(a, 100);
  f4.init(a, 99);
  f5.init(a, 99);
  for (std::size_t i = 0; i < f4.size(); ++i) {
    const auto b = static_cast<int32_t>(i);
    EXPECT_EQ(f4.x(b), f5.x(b));
    EXPECT_EQ(f4.y(b), f5.y(b));
    EXPECT_EQ(f4.blockAt(f4.x(b), f4.y(b)), b);
  }
}

}  // namespace
}  // namespace swarm_forage
