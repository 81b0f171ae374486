#pragma once
// Counter-based randomness: every draw is a pure function of (seed, stream, id, tick, draw index),
// so results never depend on threading or on how robots are split across controller nodes.
#include <cmath>
#include <cstdint>

namespace swarm_forage {

enum class RngStream : uint64_t {
  kPlacement = 1,
  kBlocks = 2,
  kController = 3,
  kCache = 4,
  kNoise = 5,
  kPopulation = 6,
  kBootstrap = 7
};

inline uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

class CounterRng {
 public:
  CounterRng(uint64_t seed, RngStream stream, uint64_t id, uint64_t tick)
      : CounterRng(idKey(seed, stream, id), tick) {}
  /// The key's part that does not depend on the tick (two of its three mix64): callers that draw for the
  /// same robot every tick keep it, and atTick(idKey(seed, stream, id), tick) is the same generator.
  static uint64_t idKey(uint64_t seed, RngStream stream, uint64_t id) {
    return mix64(mix64(seed + 0x9e3779b97f4a7c15ULL * static_cast<uint64_t>(stream)) + id);
  }
  static CounterRng atTick(uint64_t id_key, uint64_t tick) { return CounterRng(id_key, tick); }
  CounterRng() = default;  // a placeholder to assign to (key 0)

  /// This generator as it is, to take its next draw later; this one skips that draw (as if it took it).
  CounterRng deferNext() {
    // Field by field, the key through a register: the compiler would copy both in one 16-byte load, which
    // the store buffer cannot serve when the caller just stored the counter (a stall of ~15 cycles).
    uint64_t key = key_;
    asm("" : "+r"(key));
    CounterRng later;
    later.key_ = key;
    later.counter_ = counter_++;
    return later;
  }

  uint64_t next() { return mix64(key_ + 0x9e3779b97f4a7c15ULL * ++counter_); }
  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Standard normal (Box-Muller on two uniforms; 1 - u keeps the logarithm's argument in (0, 1]).
  double gaussian() {
    const double r = std::sqrt(-2.0 * std::log(1.0 - uniform()));
    return r * std::cos(6.283185307179586 * uniform());
  }

 private:
  CounterRng(uint64_t id_key, uint64_t tick) : key_(mix64(id_key + tick * 0xd1b54a32d192ed03ULL)) {}

  uint64_t key_ = 0;
  uint64_t counter_ = 0;
};

}  // namespace swarm_forage
