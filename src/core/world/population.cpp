#include "swarm_forage/core/world/population.hpp"

#include <algorithm>
#include <cmath>

#include "swarm_forage/core/util/rng.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

namespace {
enum Process : uint64_t { kDeath = 0, kBirth = 1, kMalfunction = 2, kRepair = 3, kVictims = 4 };

void checkRate(const char* name, double rate) {
  // At most one operation per process and tick: a rate above 1 per tick would change nothing.
  if (!(rate >= 0 && rate <= 1))
    throw ParameterError(std::string("population/") + name + " must be a rate per tick in [0, 1] (got " +
                         canonicalNumber(rate) + ")");
}
}  // namespace

void PopulationConfig::validate(uint32_t n_robots) const {
  checkRate("death", death);
  checkRate("birth", birth);
  checkRate("malfunction", malfunction);
  checkRate("repair", repair);
  // The swarm size N is the most robots a run has bodies for (swarm_size stays the maximum N),
  // and a maximum below N is refused: N is the only valid maximum.
  if (max_size != 0 && max_size != n_robots)
    throw ParameterError("population/max_size must be the swarm size n_robots = " + std::to_string(n_robots) +
                         " (0: the same; N is the most robots present, births refill up to it), got " +
                         std::to_string(max_size));
}

std::string PopulationConfig::describe(uint32_t n_robots) const {
  if (!enabled()) return "";
  return "population/death=" + canonicalNumber(death) + " population/birth=" + canonicalNumber(birth) +
         " population/malfunction=" + canonicalNumber(malfunction) +
         " population/repair=" + canonicalNumber(repair) +
         " population/max_size=" + std::to_string(max_size ? max_size : n_robots);
}

std::string PopulationConfig::tag() const {
  if (!enabled()) return "";
  std::string s = "pd";
  const std::pair<const char*, double> rates[] = {
      {"d", death}, {"b", birth}, {"m", malfunction}, {"r", repair}};
  for (const auto& [name, rate] : rates)
    if (rate > 0) s += std::string("-") + name + canonicalNumber(rate);
  return max_size ? s + "-max" + std::to_string(max_size) : s;
}

bool PoissonClock::due(uint64_t tick) {
  if (rate_ <= 0) return false;
  if (!scheduled_) {
    // The waiting time in whole ticks, truncated as the authors' (uint) cast of an Exp(rate) draw.
    CounterRng rng(seed_, RngStream::kPopulation, process_, tick);
    const double wait = -std::log(1.0 - rng.uniform()) / rate_;
    next_ = last_ + static_cast<uint64_t>(std::min(wait, 0x1p62));
    scheduled_ = true;
  }
  return tick >= next_;
}

void PopulationDynamics::reset(const PopulationConfig& config, uint32_t seed, uint32_t n_robots) {
  config_ = config;
  seed_ = seed;
  max_size_ = config.max_size ? config.max_size : n_robots;
  enabled_ = config.enabled();
  changed_ = false;
  death_ = PoissonClock(config.death, seed, kDeath);
  birth_ = PoissonClock(config.birth, seed, kBirth);
  malfunction_ = PoissonClock(config.malfunction, seed, kMalfunction);
  repair_ = PoissonClock(config.repair, seed, kRepair);
  presence_.assign(n_robots, static_cast<uint8_t>(Presence::kActive));
  active_.assign(n_robots, 1);
  queue_.clear();
  events_ = PopulationEvents{};
  count();
}

void PopulationDynamics::setRates(const PopulationConfig& rates) {
  config_.death = rates.death;
  config_.birth = rates.birth;
  config_.malfunction = rates.malfunction;
  config_.repair = rates.repair;
  changed_ = true;
  death_.setRate(rates.death);
  birth_.setRate(rates.birth);
  malfunction_.setRate(rates.malfunction);
  repair_.setRate(rates.repair);
}

int64_t PopulationDynamics::victim(uint64_t tick, uint64_t process, Presence among) const {
  const auto accepts = [&](uint8_t p) {
    return among == Presence::kActive ? p == static_cast<uint8_t>(Presence::kActive)
                                      : p != static_cast<uint8_t>(Presence::kDead);
  };
  const auto n = static_cast<uint64_t>(std::count_if(presence_.begin(), presence_.end(), accepts));
  if (n == 0) return -1;
  CounterRng rng(seed_, RngStream::kPopulation, kVictims + process, tick);
  uint64_t k = std::min<uint64_t>(static_cast<uint64_t>(rng.uniform() * static_cast<double>(n)), n - 1);
  for (std::size_t i = 0; i < presence_.size(); ++i)
    if (accepts(presence_[i]) && k-- == 0) return static_cast<int64_t>(i);
  return -1;
}

void PopulationDynamics::setPresence(uint32_t i, Presence p) {
  presence_[i] = static_cast<uint8_t>(p);
  active_[i] = p == Presence::kActive ? 1 : 0;
}

void PopulationDynamics::count() {
  events_.active = static_cast<uint32_t>(std::count(active_.begin(), active_.end(), 1));
  events_.queue = static_cast<uint32_t>(queue_.size());
  events_.present = events_.active + events_.queue;
}

const PopulationEvents& PopulationDynamics::update(uint64_t tick,
                                                   const std::function<bool(uint32_t, bool)>& place) {
  for (auto* v : {&events_.deaths, &events_.births, &events_.malfunctions, &events_.repairs}) v->clear();
  if (!enabled()) return events_;
  // Death: any robot present (active or awaiting repair, as jharwell/cosm src/argos/tv/pd_adaptor.cpp
  // kill_victim_locate) leaves for good; one awaiting repair leaves the queue too.
  if (death_.due(tick)) {
    if (const int64_t v = victim(tick, kDeath, Presence::kRepair); v >= 0) {
      const auto id = static_cast<uint32_t>(v);
      if (presence(id) == Presence::kRepair) queue_.erase(std::find(queue_.begin(), queue_.end(), id));
      setPresence(id, Presence::kDead);
      events_.deaths.push_back(id);
      death_.done(tick);
    }
  }
  // Birth: refused while max_size robots are present. The newcomer takes the lowest free id.
  if (birth_.due(tick)) {
    count();
    const auto free = std::find(presence_.begin(), presence_.end(), static_cast<uint8_t>(Presence::kDead));
    if (events_.present < max_size_ && free != presence_.end()) {
      const auto id = static_cast<uint32_t>(free - presence_.begin());
      if (place(id, false)) {
        setPresence(id, Presence::kActive);
        events_.births.push_back(id);
        birth_.done(tick);
      }
    }
  }
  // Malfunction: an active robot joins the back of the repair queue.
  if (malfunction_.due(tick)) {
    if (const int64_t v = victim(tick, kMalfunction, Presence::kActive); v >= 0) {
      const auto id = static_cast<uint32_t>(v);
      setPresence(id, Presence::kRepair);
      queue_.push_back(id);
      events_.malfunctions.push_back(id);
      malfunction_.done(tick);
    }
  }
  // Repair: the queue's head rejoins. A passing check is consumed even with the queue empty (the
  // authors' "fake dequeue", jharwell/cosm src/tv/population_dynamics.cpp repair_dynamics).
  if (repair_.due(tick)) {
    if (!queue_.empty() && place(queue_.front(), true)) {
      const uint32_t id = queue_.front();
      queue_.pop_front();
      setPresence(id, Presence::kActive);
      events_.repairs.push_back(id);
    }
    repair_.done(tick);
  }
  count();
  return events_;
}

}  // namespace swarm_forage
