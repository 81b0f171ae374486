#include "swarm_forage/core/controllers/block_memory.hpp"

#include <algorithm>
#include <cmath>

namespace swarm_forage {

Rect certainSight(const LineOfSight& los, double x, double y, double margin) {
  const Rect lo = los.around(x - margin, y - margin), hi = los.around(x + margin, y + margin);
  return {std::max(lo.min_x, hi.min_x) + margin, std::max(lo.min_y, hi.min_y) + margin,
          std::min(lo.max_x, hi.max_x) - margin, std::min(lo.max_y, hi.max_y) - margin};
}

double objectUtility(const Vec2& object, const Vec2& robot, const Vec2& nest, double rho) {
  return (object - nest).norm() / std::max((object - robot).norm(), 1e-9) * std::exp(rho);
}

int bestByUtility(const std::vector<Remembered>& entries, const Vec2& robot, const Vec2& nest,
                  double exclude) {
  int best = -1;
  double best_u = 0;
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const Vec2 p(entries[k].x, entries[k].y);
    if ((p - robot).norm() < exclude) continue;
    const double u = objectUtility(p, robot, nest, entries[k].rho);
    if (best < 0 || u > best_u) {
      best = static_cast<int>(k);
      best_u = u;
    }
  }
  return best;
}

const Remembered* ObjectMemory::find(uint32_t local, int32_t id) const {
  const auto& e = entries_[local];
  const auto it =
      std::lower_bound(e.begin(), e.end(), id, [](const Remembered& r, int32_t v) { return r.id < v; });
  return it != e.end() && it->id == id ? &*it : nullptr;
}

bool ObjectMemory::forget(uint32_t local, int32_t id) {
  auto& e = entries_[local];
  const auto it =
      std::lower_bound(e.begin(), e.end(), id, [](const Remembered& r, int32_t v) { return r.id < v; });
  if (it == e.end() || it->id != id) return false;
  e.erase(it);
  return true;
}

void ObjectMemory::update(uint32_t local, const PheromoneModel& model, const Rect& sight, const int32_t* ids,
                          const float* xs, const float* ys, uint32_t n, int32_t skip) {
  auto& e = entries_[local];
  if (e.empty() && n == 0) return;  // the common case: nothing known, nothing seen
  const double keep = 1.0 - model.decay;
  for (auto& r : e) r.rho *= keep;
  const auto inSight = [&](const Remembered& r) {
    return r.x > sight.min_x && r.x < sight.max_x && r.y > sight.min_y && r.y < sight.max_y;
  };
  if (n == 0 && std::none_of(e.begin(), e.end(), inSight)) return;
  // Merge the remembered entries with the (id-sorted) sightings.
  scratch_.clear();
  std::size_t a = 0;
  uint32_t b = 0;
  const double moved2 = model.new_place_distance * model.new_place_distance;
  while (a < e.size() || b < n) {
    if (b < n && ids[b] == skip) {
      ++b;
    } else if (b >= n || (a < e.size() && e[a].id < ids[b])) {  // remembered, not reported
      if (!inSight(e[a])) scratch_.push_back(e[a]);
      ++a;
    } else if (a >= e.size() || ids[b] < e[a].id) {  // first seen
      scratch_.push_back({ids[b], xs[b], ys[b], model.initial});
      ++b;
    } else {  // seen again: a new place resets the pheromone
      Remembered r = e[a];
      const double dx = static_cast<double>(xs[b]) - r.x, dy = static_cast<double>(ys[b]) - r.y;
      if (dx * dx + dy * dy > moved2) r = {ids[b], xs[b], ys[b], model.initial};
      scratch_.push_back(r);
      ++a;
      ++b;
    }
  }
  e.assign(scratch_.begin(), scratch_.end());
}

}  // namespace swarm_forage
