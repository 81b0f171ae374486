#pragma once
// K groups of 4 double lanes (AVX2, never FMA) whose operations are issued group after group, op by op:
// the K dependency chains of a long kernel (atan2, sine, divisions) are interleaved in the instruction
// stream, so the core overlaps them where it would otherwise wait on one chain at a time. Each lane gets
// the very operations of the 4-lane code, so the same bits. Only for callers that checked simdEnabled().
#include <immintrin.h>

#include <cstdint>

// A function that may use AVX2 (and inline the functions below); FMA stays off, so no contraction. Vectors
// go by reference: passed by value, GCC may warn that their ABI depends on AVX (-Wpsabi).
#define SWARM_FORAGE_AVX2 __attribute__((target("avx2")))
#define SWARM_FORAGE_LANES SWARM_FORAGE_AVX2 inline __attribute__((always_inline))

namespace swarm_forage::lanes {

template <int K>
struct D {  // K x 4 doubles
  __m256d v[K];
};
template <int K>
struct I {  // K x 4 64-bit integers
  __m256i v[K];
};

#define SWARM_FORAGE_LANES_OP(T, name, expr)                   \
  template <int K>                                             \
  SWARM_FORAGE_LANES T<K> name(const T<K>& a, const T<K>& b) { \
    T<K> r;                                                    \
    for (int k = 0; k < K; ++k) r.v[k] = expr(a.v[k], b.v[k]); \
    return r;                                                  \
  }
SWARM_FORAGE_LANES_OP(D, operator+, _mm256_add_pd)
SWARM_FORAGE_LANES_OP(D, operator-, _mm256_sub_pd)
SWARM_FORAGE_LANES_OP(D, operator*, _mm256_mul_pd)
SWARM_FORAGE_LANES_OP(D, operator/, _mm256_div_pd)
SWARM_FORAGE_LANES_OP(D, operator&, _mm256_and_pd)
SWARM_FORAGE_LANES_OP(D, operator|, _mm256_or_pd)
SWARM_FORAGE_LANES_OP(D, operator^, _mm256_xor_pd)
SWARM_FORAGE_LANES_OP(D, andNot, _mm256_andnot_pd)  // ~a & b
SWARM_FORAGE_LANES_OP(I, operator&, _mm256_and_si256)
SWARM_FORAGE_LANES_OP(I, operator+, _mm256_add_epi64)
SWARM_FORAGE_LANES_OP(I, operator-, _mm256_sub_epi64)
#undef SWARM_FORAGE_LANES_OP

template <int K>
SWARM_FORAGE_LANES D<K> set1(double x) {
  D<K> r;
  for (int k = 0; k < K; ++k) r.v[k] = _mm256_set1_pd(x);
  return r;
}
template <int K>
SWARM_FORAGE_LANES I<K> set1i(int64_t x) {
  I<K> r;
  for (int k = 0; k < K; ++k) r.v[k] = _mm256_set1_epi64x(x);
  return r;
}
/// Lane by lane: mask's lanes (sign bit) take b, the others a.
template <int K>
SWARM_FORAGE_LANES D<K> blend(const D<K>& a, const D<K>& b, const D<K>& mask) {
  D<K> r;
  for (int k = 0; k < K; ++k) r.v[k] = _mm256_blendv_pd(a.v[k], b.v[k], mask.v[k]);
  return r;
}
template <int C, int K>
SWARM_FORAGE_LANES D<K> cmp(const D<K>& a, const D<K>& b);
/// std::clamp(v, lo, hi) per lane: lo below lo, else hi above hi, else v (NaN stays).
template <int K>
SWARM_FORAGE_LANES D<K> clamp(const D<K>& v, const D<K>& lo, const D<K>& hi) {
  return blend(blend(v, hi, cmp<_CMP_LT_OQ>(hi, v)), lo, cmp<_CMP_LT_OQ>(v, lo));
}
template <int C, int K>
SWARM_FORAGE_LANES D<K> cmp(const D<K>& a, const D<K>& b) {
  D<K> r;
  for (int k = 0; k < K; ++k) r.v[k] = _mm256_cmp_pd(a.v[k], b.v[k], C);
  return r;
}
template <int K>
SWARM_FORAGE_LANES D<K> sqrt(const D<K>& a) {
  D<K> r;
  for (int k = 0; k < K; ++k) r.v[k] = _mm256_sqrt_pd(a.v[k]);
  return r;
}
template <int K>
SWARM_FORAGE_LANES D<K> floor(const D<K>& a) {
  D<K> r;
  for (int k = 0; k < K; ++k) r.v[k] = _mm256_round_pd(a.v[k], _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
  return r;
}
/// Integer lanes from doubles that hold small integers (through 32 bits, as _mm256_cvtpd_epi32).
template <int K>
SWARM_FORAGE_LANES I<K> toInt(const D<K>& a) {
  I<K> r;
  for (int k = 0; k < K; ++k) r.v[k] = _mm256_cvtepi32_epi64(_mm256_cvtpd_epi32(a.v[k]));
  return r;
}
template <int S, int K>
SWARM_FORAGE_LANES I<K> shiftLeft(const I<K>& a) {
  I<K> r;
  for (int k = 0; k < K; ++k) r.v[k] = _mm256_slli_epi64(a.v[k], S);
  return r;
}
template <int K>
SWARM_FORAGE_LANES D<K> asDouble(const I<K>& a) {
  D<K> r;
  for (int k = 0; k < K; ++k) r.v[k] = _mm256_castsi256_pd(a.v[k]);
  return r;
}

}  // namespace swarm_forage::lanes
