// Population dynamics on bodies and blocks (docs/robustness-population.md): the processes decide
// (population.cpp), the world carries out. A robot out of the swarm is in no grid cell, so it is absent
// from sensing, collisions and motion (world_motion.cpp, world_sensing.cpp).
#include "swarm_forage/core/util/rng.hpp"
#include "swarm_forage/core/world/world.hpp"

namespace swarm_forage {

void World::populationStep() {
  const PopulationEvents& e =
      population_.update(tick_, [this](uint32_t i, bool rejoin) { return placeJoining(i, rejoin); });
  for (const auto* left : {&e.deaths, &e.malfunctions})
    for (const uint32_t i : *left) leave(i);
}

// The run's identity keeps the start-up rates; world/population marks the run changed from now on.
void World::setPopulationRates(const PopulationConfig& rates) {
  if (!population_.enabled())
    throw ParameterError(
        "population rates cannot change in a run that started without population dynamics "
        "(give population/... at start-up)");
  PopulationConfig next = config_.population;
  next.death = rates.death;
  next.birth = rates.birth;
  next.malfunction = rates.malfunction;
  next.repair = rates.repair;
  next.validate(config_.n_robots);
  population_.setRates(next);
}

void World::leave(uint32_t i) {
  int32_t& carried = robots_.carried[i];
  if (carried >= 0) blocks_.putDown(carried, robots_.x[i], robots_.y[i]);  // stays in the world
  carried = -1;
  robots_.last_request[i] = kNone;
}

bool World::placeJoining(uint32_t i, bool rejoin) {
  const double r = config_.robot.radius;
  const auto freeAt = [&](double x, double y) {  // no active robot there (a rare event: a plain scan)
    for (std::size_t j = 0; j < robots_.size(); ++j) {
      if (j == i || !active(j)) continue;
      const double dx = robots_.x[j] - x, dy = robots_.y[j] - y;
      if (dx * dx + dy * dy < 4 * r * r) return false;
    }
    return true;
  };
  // A repaired robot resumes where it stopped; another robot may have come there meanwhile (an inactive
  // robot has no body), and then it enters as a newcomer does.
  if (rejoin && freeAt(robots_.x[i], robots_.y[i])) return true;
  // A newcomer enters at a uniform spot of [2, W - 2] x [2, H - 2] (the start region) with heading 0, tried
  // up to 1000 times (jharwell/cosm src/argos/tv/pd_adaptor.cpp robot_attempt_add).
  const Rect s = config_.arena.start();
  CounterRng rng(config_.seed, RngStream::kPopulation, (uint64_t{1} << 32) + i, tick_);
  for (int attempt = 0; attempt < 1000; ++attempt) {
    const double x = rng.uniform(s.min_x, s.max_x), y = rng.uniform(s.min_y, s.max_y);
    if (!freeAt(x, y)) continue;
    leave(i);  // a robot born into the id of one that died this tick drops that one's block where it died
    robots_.x[i] = x;
    robots_.y[i] = y;
    if (!rejoin) {
      robots_.theta[i] = 0;
      robots_.events[i] |= kJoined;
    }
    return true;
  }
  return false;
}

}  // namespace swarm_forage
