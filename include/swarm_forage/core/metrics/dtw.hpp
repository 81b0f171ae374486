#pragma once
// Dynamic time warping (docs/design-model.md, Metrics): the total cost of the optimal warping path between
// two sequences, exact (no approximation), O(n m) time (O(n (2 r + 1)) with a band of r) and O(min(n, m))
// memory.
//
// A warping path runs from (0, 0) to (n - 1, m - 1) with steps (1, 0), (0, 1) and (1, 1); its cost is
// the sum of the cost of every cell it visits (no step weights, no normalisation).
//
// Sakoe-Chiba band r: only cells with |i - j| <= r are allowed. A band narrower than the length
// difference |n - m| would leave no path at all, so it is widened to |n - m|; a band >= max(n, m) - 1
// (in particular any band >= max(n, m)) allows every cell and gives exactly the unbanded result.
// A banded cost is never below the exact one.
#include <cstddef>
#include <optional>
#include <vector>

namespace swarm_forage {

/// The band actually used for sequences of lengths n and m: max(band, |n - m|); nullopt = no band.
std::optional<std::size_t> effectiveDtwBand(std::size_t n, std::size_t m, std::optional<std::size_t> band);

/// DTW with cost |x_i - y_j|. Symmetric: dtw(x, y) == dtw(y, x) bit for bit.
/// Throws std::invalid_argument if either sequence is empty or holds a non-finite value.
double dtw(const std::vector<double>& x, const std::vector<double>& y,
           std::optional<std::size_t> band = std::nullopt);

/// DTW over 2-D points (tx_i, x_i) and (ty_j, y_j) with the L1 cost |tx_i - ty_j| + |x_i - y_j| — the
/// quantity the authors' 2019 scripts estimate with `fastdtw.fastdtw(a, b)` (whose default distance on
/// 2-D points is the L1 norm). fastdtw with its default radius of 1 only approximates it (its result
/// is >= this exact value); we compute the exact value it approximates.
/// Throws std::invalid_argument if a sequence is empty, tx/x or ty/y differ in length, or a value is
/// not finite.
double dtwTimeValue(const std::vector<double>& tx, const std::vector<double>& x,
                    const std::vector<double>& ty, const std::vector<double>& y,
                    std::optional<std::size_t> band = std::nullopt);

}  // namespace swarm_forage
