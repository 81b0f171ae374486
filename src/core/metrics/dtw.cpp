#include "swarm_forage/core/metrics/dtw.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace swarm_forage {

namespace {

void requireUsable(const std::vector<double>& v, const char* what) {
  if (v.empty()) throw std::invalid_argument(std::string("dtw: ") + what + " is empty");
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      throw std::invalid_argument(std::string("dtw: ") + what + " is not finite at index " +
                                  std::to_string(i));
}

/// Banded DTW over n rows and m columns; cost(i, j) for 0-based cells. Keeps two rows of m + 1
/// cells (column 0 is the boundary). Rows are computed only inside the band [lo, hi]. Both edges only
/// move right from row to row: the cell just left of the band may hold a value from two rows back and
/// is reset to infinity; cells right of the band were never written and still hold infinity.
template <typename Cost>
double dtwCore(std::size_t n, std::size_t m, std::optional<std::size_t> band, Cost cost) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // A band wider than max(n, m) changes nothing; clamping it keeps i + r from overflowing.
  const std::size_t r = std::min(effectiveDtwBand(n, m, band).value_or(std::max(n, m)), std::max(n, m));
  std::vector<double> prev(m + 1, kInf), cur(m + 1, kInf);
  prev[0] = 0.0;
  for (std::size_t i = 1; i <= n; ++i) {
    const std::size_t lo = i > r ? std::max<std::size_t>(1, i - r) : 1;
    const std::size_t hi = std::min(m, i + r);
    cur[lo - 1] = kInf;
    for (std::size_t j = lo; j <= hi; ++j)
      cur[j] = cost(i - 1, j - 1) + std::min({prev[j], prev[j - 1], cur[j - 1]});
    std::swap(prev, cur);
  }
  return prev[m];
}

}  // namespace

std::optional<std::size_t> effectiveDtwBand(std::size_t n, std::size_t m, std::optional<std::size_t> band) {
  if (!band) return std::nullopt;
  return std::max(*band, n > m ? n - m : m - n);
}

double dtw(const std::vector<double>& x, const std::vector<double>& y, std::optional<std::size_t> band) {
  requireUsable(x, "first sequence");
  requireUsable(y, "second sequence");
  // Rows over the longer sequence, so memory is O(min(n, m)); the transposed problem has the same
  // cells, costs and additions, hence the same result bit for bit.
  const std::vector<double>& a = x.size() >= y.size() ? x : y;
  const std::vector<double>& b = x.size() >= y.size() ? y : x;
  return dtwCore(a.size(), b.size(), band,
                 [&](std::size_t i, std::size_t j) { return std::fabs(a[i] - b[j]); });
}

double dtwTimeValue(const std::vector<double>& tx, const std::vector<double>& x,
                    const std::vector<double>& ty, const std::vector<double>& y,
                    std::optional<std::size_t> band) {
  requireUsable(tx, "first time axis");
  requireUsable(x, "first sequence");
  requireUsable(ty, "second time axis");
  requireUsable(y, "second sequence");
  if (tx.size() != x.size() || ty.size() != y.size())
    throw std::invalid_argument("dtw: a time axis and its values differ in length");
  const bool keep = x.size() >= y.size();
  const std::vector<double>& ta = keep ? tx : ty;
  const std::vector<double>& a = keep ? x : y;
  const std::vector<double>& tb = keep ? ty : tx;
  const std::vector<double>& b = keep ? y : x;
  return dtwCore(a.size(), b.size(), band, [&](std::size_t i, std::size_t j) {
    return std::fabs(ta[i] - tb[j]) + std::fabs(a[i] - b[j]);
  });
}

}  // namespace swarm_forage
