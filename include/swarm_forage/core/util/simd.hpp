#pragma once
// Whether the hot loops may take their 4-lane AVX2 paths. Those paths are compiled with
// __attribute__((target("avx2"))) and never with FMA: IEEE +, -, *, / and sqrt give the same bits in
// every lane as the scalar path, and without FMA the compiler cannot contract a product and a sum, so
// a run is bit-identical with and without them (tests switch them off to check that).
#include <cstdlib>

namespace swarm_forage {

namespace simd_detail {
inline bool& enabledFlag() {
  // SWARM_FORAGE_SIMD=0 in the environment forces the scalar paths (for comparisons and old CPUs).
  static bool enabled = [] {
    const char* env = std::getenv("SWARM_FORAGE_SIMD");
    if (env && env[0] == '0') return false;
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return enabled;
}
}  // namespace simd_detail

/// True when this CPU has AVX2 and the 4-lane paths are not switched off.
inline bool simdEnabled() { return simd_detail::enabledFlag(); }

/// Switches the 4-lane paths off (or back on, where the CPU has AVX2); for tests and benchmarks.
inline void setSimdEnabled(bool on) {
  __builtin_cpu_init();
  simd_detail::enabledFlag() = on && __builtin_cpu_supports("avx2") != 0;
}

}  // namespace swarm_forage
