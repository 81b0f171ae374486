#include "swarm_forage/core/world/spatial_grid.hpp"

#include <algorithm>
#include <cmath>

#include "swarm_forage/core/util/fast_math_x4.hpp"
#include "swarm_forage/core/util/simd.hpp"

namespace swarm_forage {

namespace {
// UniformGrid::build's cells of points [0, n - n % 4), 4 at a time: cellY(y) * cols + cellX(x), the same
// IEEE division and truncation (positions are never NaN), clamped as std::clamp does.
SWARM_FORAGE_AVX2 void cellsX4(const double* xs, const double* ys, std::size_t n, double cell, int cols,
                               int rows, uint32_t* out) {
  const __m256d c = _mm256_set1_pd(cell);
  const __m128i zero = _mm_setzero_si128(), x_hi = _mm_set1_epi32(cols - 1), y_hi = _mm_set1_epi32(rows - 1),
                width = _mm_set1_epi32(cols);
  for (std::size_t i = 0; i + 4 <= n; i += 4) {
    const __m128i cx = _mm_max_epi32(
        _mm_min_epi32(_mm256_cvttpd_epi32(_mm256_div_pd(_mm256_loadu_pd(xs + i), c)), x_hi), zero);
    const __m128i cy = _mm_max_epi32(
        _mm_min_epi32(_mm256_cvttpd_epi32(_mm256_div_pd(_mm256_loadu_pd(ys + i), c)), y_hi), zero);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), _mm_add_epi32(_mm_mullo_epi32(cy, width), cx));
  }
}

// The dense layout's running sum for cells [0, n8), 8 at a time (n8 a multiple of 8), as the scalar loop in
// build(): start[c + 1] = the points in cells before c, count[c] = 0; returns the points in all n8 cells.
SWARM_FORAGE_AVX2 uint32_t layOutX8(uint32_t* count, uint32_t* start, std::size_t n8) {
  const __m256i zero = _mm256_setzero_si256(), lane3 = _mm256_set1_epi32(3), lane7 = _mm256_set1_epi32(7);
  __m256i before = zero;  // the points in the cells before this group, in every lane
  for (std::size_t c = 0; c < n8; c += 8) {
    const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(count + c));
    __m256i sum = _mm256_add_epi32(x, _mm256_slli_si256(x, 4));  // within each half
    sum = _mm256_add_epi32(sum, _mm256_slli_si256(sum, 8));
    sum = _mm256_add_epi32(sum, _mm256_blend_epi32(zero, _mm256_permutevar8x32_epi32(sum, lane3), 0xf0));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(start + c + 1),
                        _mm256_add_epi32(before, _mm256_sub_epi32(sum, x)));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(count + c), zero);
    before = _mm256_add_epi32(before, _mm256_permutevar8x32_epi32(sum, lane7));
  }
  return static_cast<uint32_t>(_mm256_extract_epi32(before, 0));
}
}  // namespace

UniformGrid::UniformGrid(double width, double height, double cell_size)
    : cell_(cell_size),
      nx_(std::max(1, static_cast<int>(std::ceil(width / cell_size)))),
      ny_(std::max(1, static_cast<int>(std::ceil(height / cell_size)))) {
  clear();
}

double UniformGrid::bytesFor(double width, double height, double cell_size) {
  const double cells =
      std::max(1.0, std::ceil(width / cell_size)) * std::max(1.0, std::ceil(height / cell_size));
  return cells * (sizeof(Range) + 3 * sizeof(uint32_t) + 1.0 / 8) + sizeof(uint32_t);
}

void UniformGrid::clear() {
  const std::size_t cells = static_cast<std::size_t>(nx_) * ny_;
  range_.assign(cells, Range{0, 0});
  start_.assign(cells + 1, 0);
  count_.assign(cells, 0);
  dense_ = false;
  touched_.clear();
  sorted_.clear();
  placed_ = 0;
  extra_head_.assign(cells, kNone);
  extra_touched_.clear();
  extra_next_.clear();
  has_extra_ = false;
}

// A counting sort by cell. With at most 16 cells per point, every cell is laid out in start_ (O(cells) =
// O(n)); otherwise only the occupied cells are, in range_, in row-major order from a bitmap of the cells
// (O(cells / 64) = O(n)), or sorted when even the bitmap is far larger than the points: the cost follows the
// points, not the arena's area. Every path gives the same order (measured: docs/performance.md).
void UniformGrid::build(const double* xs, const double* ys, std::size_t n, const uint8_t* present,
                        Bands* bands) {
  const std::size_t cells = range_.size();
  const bool dense = cells <= 16 * n + 64;
  for (uint32_t c : touched_) range_[c] = Range{0, 0};  // the last sparse layout's: the others are empty
  touched_.clear();
  for (uint32_t c : extra_touched_) extra_head_[c] = kNone;
  extra_touched_.clear();
  extra_next_.clear();
  has_extra_ = false;
  dense_ = dense;
  cell_of_.resize(n);
  // The cells first (4 at a time where the CPU can), then the counts: that loop's scattered increments
  // overlap better without the divisions between them.
  const std::size_t x4 = simdEnabled() ? n - n % 4 : 0;
  if (x4) cellsX4(xs, ys, x4, cell_, nx_, ny_, cell_of_.data());
  for (std::size_t i = x4; i < n; ++i) cell_of_[i] = static_cast<uint32_t>(cellY(ys[i]) * nx_ + cellX(xs[i]));
  if (present)
    for (std::size_t i = 0; i < n; ++i)
      if (!present[i]) cell_of_[i] = kNowhere;
  // A cell's band, cell / (columns x rows per band), without a division per point: Lemire's exact 32-bit
  // quotient ((2^64 - 1) / d + 1) cell / 2^64 (d > 1).
  const uint32_t per_band = bands ? static_cast<uint32_t>(nx_ * bands->rows) : 1;
  const uint64_t inverse = per_band > 1 ? ~0ULL / per_band + 1 : 0;
  const auto bandOf = [&](uint32_t c) {
    return per_band > 1 ? static_cast<uint32_t>((static_cast<unsigned __int128>(inverse) * c) >> 64) : c;
  };
  uint32_t* count = count_.data();
  const uint32_t* cell_of = cell_of_.data();
  if (dense_) {  // no branch on a cell's first point: in a crowd it is a coin flip
    for (std::size_t i = 0; i < n; ++i)
      if (cell_of[i] != kNowhere) ++count[cell_of[i]];
  } else {
    for (std::size_t i = 0; i < n; ++i)
      if (cell_of[i] != kNowhere && count[cell_of[i]]++ == 0) touched_.push_back(cell_of[i]);
  }
  sorted_.resize(n);
  rank_.resize(n);
  // Band b starts at the first sorted position of its first cell, b x per_band: no count per point. The dense
  // layout reads it from start_, the sparse one sets it as its layout reaches that cell.
  std::size_t band = 0;
  if (bands) bands->start.resize(static_cast<std::size_t>(ny_ / bands->rows) + 2);
  uint32_t offset = 0;
  const auto bandsUpTo = [&](std::size_t c) {
    for (; band < bands->start.size() && band * per_band <= c; ++band) bands->start[band] = offset;
  };
  if (dense_) {
    // start_[c + 1] is cell c's next position until the points are placed, and then cell c + 1's first:
    // 4 bytes a cell to write (lines the other threads read), and the ends need no pass of their own.
    start_[0] = 0;
    std::size_t c = 0;
    if (simdEnabled()) {
      c = cells - cells % 8;
      offset = layOutX8(count, start_.data(), c);
    }
    for (; c < cells; ++c) {
      start_[c + 1] = offset;
      offset += count[c];
      count[c] = 0;  // ready for the next build, without a pass of its own
    }
    if (bands)
      for (; band < bands->start.size(); ++band) {
        const std::size_t first = band * per_band;
        bands->start[band] = first < cells ? start_[first + 1] : offset;
      }
  } else {
    const auto layOut = [&](uint32_t c) {
      if (bands) bandsUpTo(c);
      range_[c] = Range{offset, offset};
      offset += count[c];
      count[c] = 0;
    };
    if (cells / 64 <= 16 * n + 64) {  // a bit per cell: row-major order by a scan of the words
      bits_.resize(cells / 64 + 1);
      for (uint32_t c : touched_) bits_[c / 64] |= uint64_t{1} << (c % 64);
      for (std::size_t w = 0; w < bits_.size(); ++w) {
        for (uint64_t b = bits_[w]; b; b &= b - 1) layOut(static_cast<uint32_t>(w * 64 + __builtin_ctzll(b)));
        bits_[w] = 0;
      }
    } else {
      std::sort(touched_.begin(), touched_.end());
      for (uint32_t c : touched_) layOut(c);
    }
    if (bands) bandsUpTo(SIZE_MAX);
  }
  placed_ = offset;
  uint32_t* band_next = nullptr;  // each band's next position in bands->order
  if (bands) {
    band_next_.assign(bands->start.begin(), bands->start.end() - 1);
    band_next = band_next_.data();
    bands->order.resize(placed_);
  }
  // The points in index order to their sorted positions k: next(c) is cell c's next position, and the
  // points in no cell follow the placed ones.
  const auto place = [&](auto next) {
    uint32_t nowhere = placed_;
    for (std::size_t i = 0; i < n; ++i) {
      const uint32_t c = cell_of[i], k = c == kNowhere ? nowhere++ : next(c)++;
      sorted_[k] = static_cast<uint32_t>(i);
      rank_[i] = k;
      if (band_next && c != kNowhere) bands->order[band_next[bandOf(c)]++] = k;
    }
  };
  if (dense_)
    place([this](uint32_t c) -> uint32_t& { return start_[c + 1]; });
  else
    place([this](uint32_t c) -> uint32_t& { return range_[c].end; });
}

void UniformGrid::insert(uint32_t index, double x, double y) {
  if (extra_next_.size() <= index) extra_next_.resize(index + 1, kNone);
  const std::size_t c = static_cast<std::size_t>(cellY(y)) * nx_ + cellX(x);
  if (extra_head_[c] == kNone) extra_touched_.push_back(static_cast<uint32_t>(c));
  has_extra_ = true;
  extra_next_[index] = extra_head_[c];
  extra_head_[c] = index;
}

}  // namespace swarm_forage
