// Quirk (9) dynamics2d_contacts: contacts closer to ARGoS' dynamics2d (docs/FIDELITY.md, "(9)
// dynamics2d_contacts"). In ARGoS a foot-bot is a chipmunk body dragged towards its commanded velocity by a
// pivot joint whose force is limited to 15 N; a robot at rest is held at zero velocity by the same joint.
// Bodies in a rigid line then move at the median of their commanded velocities along it (each drive either
// reaches its velocity or pulls at its limit, and the limits are equal), which is what ARGoS' solver gives
// for one to six bodies. Here a blocked robot collects the bodies it would push, moves them together at that
// median, and follows them.
#include <algorithm>
#include <array>
#include <cmath>

#include "swarm_forage/core/util/fast_math.hpp"
#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

namespace {
// Coulomb friction between two foot-bots: chipmunk multiplies the shapes' u = 0.7
// (dynamics2d_footbot_model.cpp), u = 0.49 (cpArbiter.c). A push within atan(0.49) of the line of centres
// sticks, and the pushed body goes the pusher's way; a wider one pushes along the line of centres only and
// the pusher slides along the contact.
const double kStickCos = 1.0 / std::sqrt(1.0 + 0.49 * 0.49);

// The median of v[0..n) (n >= 1): the middle value, or the mean of the two middle ones.
double median(std::array<double, 16> v, int n) {
  std::sort(v.begin(), v.begin() + n);
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
}  // namespace

void World::prepareContacts(const CommandData& commands, double scale, double other_scale) {
  const std::size_t n = robots_.size();
  want_x_.assign(n, 0);
  want_y_.assign(n, 0);
  const double vmax = config_.robot.max_speed, axle = config_.robot.axle;
  push_left_.assign(n, vmax * dt_ * std::max({1.0, std::abs(scale), std::abs(other_scale)}));
  const std::vector<uint32_t>& order = grid_.order();
  const uint32_t placed = grid_.placed();
  pool_->run(chunks(n), [&](std::size_t chunk, unsigned) {  // by slot: each thread writes its own range
    const auto [first, end] = chunkSpan(chunk, n);
    for (std::size_t s = first; s < std::min<std::size_t>(end, placed); ++s) {
      const uint32_t i = order[s];
      const double f = robots_.carried[i] >= 0 ? scale : other_scale;
      const double left = std::clamp<double>(commands.left[i], -vmax, vmax) * f,
                   right = std::clamp<double>(commands.right[i], -vmax, vmax) * f;
      const double v = 0.5 * (left + right), mid = sth_[s] + 0.5 * (right - left) / axle * dt_;
      double sm, cm;
      fastSinCos(mid, sm, cm);
      want_x_[s] = v * cm * dt_;
      want_y_[s] = v * sm * dt_;
    }
  });
}

bool World::pushChain(uint32_t i, double dx, double dy, double& fx, double& fy) {
  const double r = config_.robot.radius, d2 = 4 * r * r, W = config_.arena.width, H = config_.arena.height;
  const double len = std::hypot(dx, dy);
  if (len < 1e-12) return false;
  const double x0 = sx_[i], y0 = sy_[i];
  const int32_t first = blocker(i, x0 + dx, y0 + dy);
  if (first < 0) return false;
  double nx = sx_[first] - x0, ny = sy_[first] - y0;
  const double nlen = std::hypot(nx, ny);
  if (nlen < 1e-12) return false;
  nx /= nlen;
  ny /= nlen;
  const double cos_a = (dx * nx + dy * ny) / len;
  if (cos_a <= 0) return false;
  // The push direction u and how far the pusher would go along it.
  const bool stick = cos_a >= kStickCos;
  const double ux = stick ? dx / len : nx, uy = stick ? dy / len : ny, reach = stick ? len : len * cos_a;
  // The bodies in the way: those the pusher overlaps after going `reach` along u, then those these overlap
  // when all of them go as far, breadth first (nearest the pusher first). More than kChainBodies: a crowd
  // no single drive moves.
  std::array<uint32_t, kChainBodies> chain;
  int k = 0;
  bool too_many = false;
  const auto inChain = [&](uint32_t b) {
    return std::find(chain.begin(), chain.begin() + k, b) != chain.begin() + k;
  };
  const auto collect = [&](double x, double y) {
    grid_.forNeighbours(x, y, [&](uint32_t b) {
      if (b == i || too_many || inChain(b)) return;
      const double ex = sx_[b] - x, ey = sy_[b] - y;
      if (ex * ex + ey * ey >= d2) return;
      if (k == kChainBodies)
        too_many = true;
      else
        chain[k++] = b;
    });
  };
  collect(x0 + ux * reach, y0 + uy * reach);
  for (int p = 0; p < k && !too_many; ++p) {
    const double x = sx_[chain[p]] + ux * reach, y = sy_[chain[p]] + uy * reach;
    if (x < r || y < r || x > W - r || y > H - r) return false;  // against a wall: the walls do not give
    collect(x, y);
  }
  if (too_many || k == 0) return false;
  // Their speed along u: the smallest median of the pusher's and the first t bodies' commanded steps
  // (bodies further on that want to go faster move away; contacts only push), at most what the pusher
  // asks and what each body may still be pushed this tick.
  std::array<double, 16> want;
  want[0] = reach;
  double step = reach;
  for (int t = 0; t < k; ++t) {
    want[t + 1] = want_x_[chain[t]] * ux + want_y_[chain[t]] * uy;
    step = std::min(step, median(want, t + 2));
    step = std::min(step, push_left_[chain[t]]);
  }
  if (step <= 1e-9) return false;
  // They move together (their own distances do not change), each clear of every other body.
  for (int t = 0; t < k; ++t) {
    const uint32_t b = chain[t];
    const double x = sx_[b] + ux * step, y = sy_[b] + uy * step;
    bool ok = true;
    grid_.forNeighbours(x, y, [&](uint32_t c) {
      if (c == b || !ok || inChain(c)) return;
      const double ex = sx_[c] - x, ey = sy_[c] - y;
      if (ex * ex + ey * ey < d2) ok = false;
    });
    if (!ok) return false;
  }
  for (int t = 0; t < k; ++t) {
    const uint32_t b = chain[t];
    sx_[b] += ux * step;
    sy_[b] += uy * step;
    push_left_[b] -= step;
  }
  if (stick) {  // behind them
    fx = dx * (step / len);
    fy = dy * (step / len);
  } else {  // behind them along the line of centres, sliding along the contact
    fx = ux * step + dx - ux * reach;
    fy = uy * step + dy - uy * reach;
  }
  return true;
}

}  // namespace swarm_forage
