#pragma once
// Single-source blocks (cubes and ramps) on the floor, with a coarse grid for point look-ups.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

class StateArchive;

enum BlockKind : uint8_t { kCube = 0, kRamp = 1 };
/// carrier() of a block on the floor and of a block held in a cache (else: the carrying robot id).
constexpr int32_t kFree = -1;
constexpr int32_t kInCache = -2;

class BlockField {
 public:
  /// Places arena.n_blocks blocks (half cubes, half ramps) uniformly without overlap in the source.
  void init(const ArenaConfig& arena, uint32_t seed);

  /// The free block whose footprint contains (x, y), or -1. Inline: every robot asks every tick, and
  /// mostly of a cell without blocks.
  int32_t blockAt(double x, double y) const {
    const int cx = static_cast<int>(x / kCell), cy = static_cast<int>(y / kCell);
    if (cx < 0 || cy < 0 || cx >= nx_ || cy >= ny_) return -1;
    const std::size_t c = static_cast<std::size_t>(cy) * nx_ + cx;
    return occupied_[c] ? blockIn(c, x, y) : -1;
  }
  /// Whether a free block's footprint may lie within kNearReach of (x, y) (false: it does not). A bit per
  /// kNearCell square, for the test every robot makes every tick.
  bool nearBlock(double x, double y) const {
    if (!(x >= 0 && y >= 0 && x < near_w_ && y < near_h_)) return true;
    // x / kNearCell is exact (a power of 2): below near_w_, its square is on the grid.
    const std::size_t c = static_cast<std::size_t>(static_cast<int>(y * (1 / kNearCell))) * near_nx_ +
                          static_cast<std::size_t>(static_cast<int>(x * (1 / kNearCell)));
    return (near_bits_[c / 64] >> (c % 64)) & 1;
  }
  static constexpr double kNearCell = 0.25, kNearReach = 0.065;  // metres
  /// Whether a free block's footprint meets the box [x0, x1] x [y0, y1], edges included (false: blockAt is
  /// -1 everywhere in it).
  bool touchesBlock(double x0, double y0, double x1, double y1) const {
    const int cx0 = std::max(0, static_cast<int>(x0 / kCell)),
              cx1 = std::min(nx_ - 1, static_cast<int>(x1 / kCell));
    const int cy0 = std::max(0, static_cast<int>(y0 / kCell)),
              cy1 = std::min(ny_ - 1, static_cast<int>(y1 / kCell));
    for (int cy = cy0; cy <= cy1; ++cy)
      for (int cx = cx0; cx <= cx1; ++cx) {
        const std::size_t c = static_cast<std::size_t>(cy) * nx_ + cx;
        if (!occupied_[c]) continue;
        for (const int32_t b : cells_[c]) {
          const Rect f = footprint(b);
          if (f.min_x <= x1 && x0 <= f.max_x && f.min_y <= y1 && y0 <= f.max_y) return true;
        }
      }
    return false;
  }
  /// Marks a free block as carried by `robot`.
  void pickUp(int32_t block, int32_t robot);
  /// Puts a carried (or cached) block down on the floor at (x, y).
  void putDown(int32_t block, double x, double y);
  /// Moves a free or carried block into a cache at (x, y): off the floor, not carried.
  void stash(int32_t block, double x, double y);
  /// Hands a cached block to `robot`.
  void assign(int32_t block, int32_t robot) { carrier_[block] = robot; }
  /// The cells of the look-up grid (kCell metres) a rectangle touches, clamped to the grid; false if none.
  bool gridSpan(const Rect& r, int& x0, int& x1, int& y0, int& y1) const;
  /// The cell a free block counts in when blocks are looked for by area: the one holding its centre;
  /// false when that is off the grid.
  bool centreCell(int32_t b, int& cx, int& cy) const;
  int gridRows() const { return ny_; }
  /// Re-places a delivered block uniformly in the source, without overlapping free blocks.
  void respawn(int32_t block);

  std::size_t size() const { return x_.size(); }
  double x(int32_t b) const { return x_[b]; }
  double y(int32_t b) const { return y_[b]; }
  BlockKind kind(int32_t b) const { return static_cast<BlockKind>(kind_[b]); }
  int32_t carrier(int32_t b) const { return carrier_[b]; }  // robot id, kFree or kInCache
  double sizeX(int32_t b) const { return kind_[b] == kRamp ? arena_.ramp_length : arena_.cube_size; }
  double sizeY(int32_t) const { return arena_.cube_size; }
  Rect footprint(int32_t b) const { return Rect::centered(x_[b], y_[b], sizeX(b), sizeY(b)); }
  /// Incremented whenever a block moves, is picked up or put down.
  uint64_t version() const { return version_; }
  /// Saves or loads the blocks (world_checkpoint.cpp); the arena comes from init().
  void persist(StateArchive& a);

  static constexpr double kCell = 0.5;  // metres
  /// The bytes of the look-up grid over `arena` (init() allocates them).
  static double gridBytes(const ArenaConfig& arena) {
    return std::ceil(arena.width / kCell) * std::ceil(arena.height / kCell) *
               (sizeof(std::vector<int32_t>) + sizeof(uint8_t)) +
           std::ceil(arena.width / kNearCell) * std::ceil(arena.height / kNearCell) / 8;
  }

 private:
  void placeInSource(int32_t b);
  int32_t blockIn(std::size_t cell, double x, double y) const;  // blockAt's in an occupied cell
  void link(int32_t b);
  void unlink(int32_t b);
  // The near bits: the squares within kNearReach of b's footprint, set as it is linked, and as it is unlinked
  // cleared where no other free block is near; none anywhere; those of every free block.
  bool nearSquares(int32_t b, int& x0, int& x1, int& y0, int& y1) const;
  void markNear(int32_t b);
  void unmarkNear(int32_t b);
  void clearNear();
  void layOutNear();
  template <typename F>
  void forCells(const Rect& r, F&& f);

  ArenaConfig arena_;
  uint32_t seed_ = 0;
  uint64_t draws_ = 0;  // placement draws so far; the counter of the block RNG
  uint64_t version_ = 0;
  std::vector<double> x_, y_;
  std::vector<uint8_t> kind_;
  std::vector<int32_t> carrier_;
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<int32_t>> cells_;  // free blocks overlapping each cell
  std::vector<uint8_t> occupied_;            // cells_[c] is not empty: a flat test for the hot loops
  int near_nx_ = 0, near_ny_ = 0;
  double near_w_ = 0, near_h_ = 0;   // near_nx_ and near_ny_ squares, in metres
  std::vector<uint64_t> near_bits_;  // a bit per kNearCell square: a free block lies within kNearReach of it
};

}  // namespace swarm_forage
