// FORDYCA 2019's light occlusion (docs/FIDELITY.md, "FORDYCA as it ran", (8)): whether a body cuts the ray
// from a robot to a nest light. Only the answer counts, never which body gave it or in which order the bodies
// were tested, so the search below may take any path that tests every body the exact test could accept.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

namespace {
// Calls f(c) for each set bit c in [b0, b1], ascending or descending, until f returns true (then true).
template <typename F>
bool forSetBits(const uint64_t* bits, std::size_t b0, std::size_t b1, bool ascending, F&& f) {
  const std::size_t w0 = b0 / 64, w1 = b1 / 64;
  const auto word = [&](std::size_t w) {
    uint64_t m = bits[w];
    if (w == w0) m &= ~uint64_t{0} << (b0 % 64);
    if (w == w1) m &= ~uint64_t{0} >> (63 - b1 % 64);
    return m;
  };
  if (ascending) {
    for (std::size_t w = w0; w <= w1; ++w)
      for (uint64_t m = word(w); m; m &= m - 1)
        if (f(w * 64 + static_cast<std::size_t>(__builtin_ctzll(m)))) return true;
  } else {
    for (std::size_t w = w1 + 1; w-- > w0;)
      for (uint64_t m = word(w); m;) {
        const int b = 63 - __builtin_clzll(m);
        if (f(w * 64 + static_cast<std::size_t>(b))) return true;
        m &= ~(uint64_t{1} << b);
      }
  }
  return false;
}

// A margin over the ray's search region that covers the roundings of its bounds (positions are at most
// 10 km, so they round at about 1e-12 m).
constexpr double kSearchMargin = 1e-6;

// The part of a ray, from the robot, along which it is still below a body's height (shadowReach / d).
constexpr double shadowFraction(double lz) { return lz <= kFootBotHeight ? 1.0 : kFootBotHeight / lz; }
constexpr double kShadowFraction[3] = {shadowFraction(kFordycaLightHeight[0]),
                                       shadowFraction(kFordycaLightHeight[1]),
                                       shadowFraction(kFordycaLightHeight[2])};
static_assert(ArenaConfig::kLights == 3, "a fraction per light");
}  // namespace

void World::prepareShadows() {
  const std::size_t cells = static_cast<std::size_t>(grid_.columns()) * grid_.rows(), n = robots_.size();
  const std::size_t words = cells / 64 + 1;
  // A small map is cleared whole; a large one (a sparse swarm in a big arena) bit by bit after the sensing.
  if (shadow_bits_.size() != words) shadow_bits_.assign(words, 0);
  if (words <= n) std::memset(shadow_bits_.data(), 0, words * sizeof(uint64_t));
  shadow_inv_cell_ = 1.0 / grid_.cellSize();
  uint64_t* const bits = shadow_bits_.data();
  // Which slots trace, set here by id: the sensing then reads a byte in slot order instead of a carried
  // block by id. Every slot is written (rank is a permutation), without a branch on the carriers.
  const bool all = !config_.light_only_carrying;
  traced_.resize(n);
  uint8_t* const traced = traced_.data();
  const uint32_t* const rank = grid_.rank().data();
  const int32_t* const carried = robots_.carried.data();
  for (std::size_t i = 0; i < n; ++i) {
    const uint32_t c = grid_.cellOf(static_cast<uint32_t>(i));
    if (c != UniformGrid::kNowhere) bits[c / 64] |= uint64_t{1} << (c % 64);
    traced[rank[i]] = static_cast<uint8_t>(all | (carried[i] >= 0));
  }
}

void World::clearShadowCells() {
  const std::size_t n = robots_.size();
  if (shadow_bits_.size() <= n) return;  // prepareShadows clears it whole
  for (std::size_t i = 0; i < n; ++i) {
    const uint32_t c = grid_.cellOf(static_cast<uint32_t>(i));
    if (c != UniformGrid::kNowhere) shadow_bits_[c / 64] = 0;
  }
}

// The lights in `search` (a mask) that a body shadows from the robot in `self`, each by a search of its
// own (one walk over the hull of the three rays' cells tested every body against every ray left: more
// branches, more mispredicted).
unsigned World::searchShadows(uint32_t self, unsigned search, const double* d, const double* ux,
                              const double* uy) const {
  const double x = sx_[self], y = sy_[self];
  const double r = config_.robot.radius;
  const uint32_t* const order = grid_.order().data();
  uint32_t* const witness = &shadow_witness_[static_cast<std::size_t>(order[self]) * ArenaConfig::kLights];
  const double cell = grid_.cellSize(), inv_cell = shadow_inv_cell_;
  const int nx = grid_.columns(), ny = grid_.rows();
  const auto cellIn = [inv_cell](double v, int n) {
    return std::clamp(static_cast<int>(v * inv_cell), 0, n - 1);
  };
  const uint64_t* const bits = shadow_bits_.data();
  unsigned found = 0;
  for (unsigned left = search; left; left &= left - 1) {
    const int l = __builtin_ctz(left);
    const double lx = lights_[l].x(), ly = lights_[l].y(), lz = kFordycaLightHeight[l], dx = ux[l],
                 dy = uy[l];
    // Only a body entered within shadowReach of the robot (seen from above) is low enough to cut the ray:
    // a body whose centre lies within pad (its disc and its gripper) of that stretch of the ray's ground
    // projection, extended by pad. The bound in `test` only chooses which bodies get the exact test; pad's
    // 1e-9 covers its roundings (and those of reach, a product for shadowReach's quotient).
    const double pad = r + kGripperRadius + 1e-9, reach = kShadowFraction[l] * d[l] + pad;
    uint32_t hit = kNoWitness;
    const auto test = [&](uint32_t k) {
      if (k == self) return false;
      const double ox = sx_[k] - x, oy = sy_[k] - y, along = ox * dx + oy * dy;
      if (along < 0 || along > reach || std::abs(ox * dy - oy * dx) > pad) return false;
      if (!footBotShadows(x, y, lx, ly, lz, sx_[k], sy_[k], sth_[k], r)) return false;
      hit = k;
      return true;
    };
    // The cells of grid_ within m of the segment from the robot along the ray for `reach`, row by row from
    // the robot's row outward, each row's from the robot's side: in a crowd a body near the robot shadows
    // it, and the search ends there. Empty cells cost a bit each (shadow_bits_), 64 to a word. The bounds
    // are rounded a little differently from the grid's cells (a product for a quotient); the margin covers
    // that too.
    const double m = pad + kSearchMargin;
    const double qy = y + reach * dy;
    const int row0 = cellIn(std::min(y, qy) - m, ny), row1 = cellIn(std::max(y, qy) + m, ny);
    const bool up = dy >= 0, right = dx >= 0;
    // Row i (from the robot's) holds the part of the segment whose height lies within m of it: t in
    // [t_near + i step, t_near + i step + span] (all of it when the ray runs along the rows).
    double t_near = 0, step = 0, span = reach;
    if (std::abs(dy) >= 1e-9) {
      const double inv = 1.0 / std::abs(dy);
      step = cell * inv;
      span = step + 2 * m * inv;
      t_near = (up ? row0 * cell - m - y : y - (row1 + 1) * cell - m) * inv;
    }
    const auto inCell = [&](std::size_t c) {
      const UniformGrid::Run run = grid_.cellRun(c);
      for (uint32_t k = run.begin; k < run.end; ++k)
        if (test(k)) return true;
      return false;
    };
    for (int i = 0, rows = row1 - row0 + 1; i < rows; ++i) {
      const double ta = t_near + i * step, t0 = std::max(0.0, ta), t1 = std::min(reach, ta + span);
      if (t0 > t1) continue;
      const double xa = x + t0 * dx, xb = x + t1 * dx;  // xa <= xb when right
      const int c0 = cellIn((right ? xa : xb) - m, nx), c1 = cellIn((right ? xb : xa) + m, nx);
      const std::size_t base = static_cast<std::size_t>(up ? row0 + i : row1 - i) * nx;
      if (forSetBits(bits, base + c0, base + c1, right, inCell)) break;
    }
    witness[l] = hit == kNoWitness ? kNoWitness : order[hit];
    found |= (hit != kNoWitness ? 1u : 0u) << l;
  }
  return found;
}

void World::shadowedLights(uint32_t slot, double& light_x, double& light_y, uint8_t& shadowed) const {
  const double x = sx_[slot], y = sy_[slot];
  const double r = config_.robot.radius;
  const uint32_t* const rank = grid_.rank().data();
  const uint32_t placed = grid_.placed();
  const uint32_t* const witness =
      &shadow_witness_[static_cast<std::size_t>(grid_.order()[slot]) * ArenaConfig::kLights];
  // A light's direction is also its ray's.
  double d[ArenaConfig::kLights], ux[ArenaConfig::kLights], uy[ArenaConfig::kLights];
  unsigned skip = 0, search = 0;
  for (int l = 0; l < ArenaConfig::kLights; ++l) {
    const double lx = lights_[l].x(), ly = lights_[l].y(), dx = lx - x, dy = ly - y;
    d[l] = std::sqrt(dx * dx + dy * dy);
    if (d[l] < 1e-12) continue;  // at the light: not shadowed, and no direction to it
    const double inv = 1.0 / d[l];
    ux[l] = dx * inv;
    uy[l] = dy * inv;
    // The body that shadowed this light last tick most often still does (bodies move little in a tick):
    // one exact test instead of a search. It changes no result, only how soon it is found.
    const uint32_t w = witness[l];
    if (w != kNoWitness) {
      const uint32_t k = rank[w];
      if (k < placed && k != slot &&
          footBotShadows(x, y, lx, ly, kFordycaLightHeight[l], sx_[k], sy_[k], sth_[k], r)) {
        skip |= 1u << l;
        continue;
      }
    }
    search |= 1u << l;
  }
  if (search) skip |= searchShadows(slot, search, d, ux, uy);
  // The sum of unit vectors to the lights not shadowed, as lightSum (world_sensing.cpp) adds them.
  double sum_x = 0, sum_y = 0;
  for (int l = 0; l < ArenaConfig::kLights; ++l)
    if (d[l] > 1e-9 && !(skip >> l & 1)) {
      sum_x += ux[l];
      sum_y += uy[l];
    }
  shadowed = static_cast<uint8_t>(skip);
  light_x = sum_x;
  light_y = sum_y;
}

}  // namespace swarm_forage
