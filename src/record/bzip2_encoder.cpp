#include "swarm_forage/record/bzip2_encoder.hpp"

#include <bzlib.h>
#include <divsufsort.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace swarm_forage {

namespace {

// The format's and libbz2's constants (bzlib_private.h): a block holds at most nblockMAX bytes after the
// first run-length step, leaving room for the 5 bytes of a run flushed at its end.
constexpr int kBlockSize100k = 9;
constexpr int32_t kBlockMax = 100000 * kBlockSize100k - 19;
constexpr uint16_t kRunA = 0, kRunB = 1;
constexpr int kGroupSize = 50, kGroups = 6, kIterations = 4, kMaxCodeLength = 17, kMaxAlphabet = 258;
constexpr uint8_t kLesserCost = 0, kGreaterCost = 15;

/// CRC-32 with polynomial 0x04c11db7, most significant bit first, four bytes a step.
class Crc {
 public:
  Crc() {
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i << 24;
      for (int b = 0; b < 8; ++b) c = (c & 0x80000000u) ? (c << 1) ^ 0x04c11db7u : c << 1;
      t_[0][i] = c;
    }
    for (int k = 1; k < 4; ++k)  // t_[k][v]: v's contribution k more bytes on
      for (uint32_t i = 0; i < 256; ++i) t_[k][i] = (t_[k - 1][i] << 8) ^ t_[0][t_[k - 1][i] >> 24];
  }
  uint32_t update(uint32_t crc, const uint8_t* p, std::size_t n) const {
    for (; n >= 4; n -= 4, p += 4) {
      const uint32_t x = crc ^ (uint32_t{p[0]} << 24 | uint32_t{p[1]} << 16 | uint32_t{p[2]} << 8 | p[3]);
      crc = t_[3][x >> 24] ^ t_[2][(x >> 16) & 0xff] ^ t_[1][(x >> 8) & 0xff] ^ t_[0][x & 0xff];
    }
    for (; n > 0; --n, ++p) crc = (crc << 8) ^ t_[0][(crc >> 24) ^ *p];
    return crc;
  }

 private:
  uint32_t t_[4][256];
};
const Crc kCrc;

class BitWriter {
 public:
  explicit BitWriter(std::string& out) : out_(out) {}
  void put(int n, uint32_t v) {  // n <= 24
    while (live_ >= 8) drain();
    buff_ |= v << (32 - live_ - n);
    live_ += n;
  }
  void putByte(uint8_t b) { put(8, b); }
  void put32(uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) put(8, (v >> shift) & 0xff);
  }
  void finish() {
    while (live_ > 0) drain();
  }

 private:
  void drain() {
    out_.push_back(static_cast<char>(buff_ >> 24));
    buff_ <<= 8;
    live_ -= 8;
  }
  std::string& out_;
  uint32_t buff_ = 0;
  int live_ = 0;
};

/// How many bytes the rotations of s[0, n) at p and q have in common, up to `limit`; eight at a time.
int32_t commonPrefix(const uint8_t* s, int32_t n, int32_t p, int32_t q, int32_t limit) {
  for (int32_t k = 0; k < limit;) {
    const int32_t a = p + k < n ? p + k : p + k - n, b = q + k < n ? q + k : q + k - n;
    const int32_t span = std::min({limit - k, n - a, n - b});
    int32_t m = 0;
    for (; m + 8 <= span; m += 8) {
      uint64_t x, y;
      std::memcpy(&x, s + a + m, 8);
      std::memcpy(&y, s + b + m, 8);
      if (x != y) return k + m + __builtin_ctzll(x ^ y) / 8;  // little-endian: the first byte is the lowest
    }
    for (; m < span; ++m)
      if (s[a + m] != s[b + m]) return k + m;
    k += span;
  }
  return limit;
}

/// Start of the least rotation of s[0, n), or -1 when two rotations are equal (s is periodic). Only
/// rotations greater than another one are skipped, so two least ones are always met and compared whole.
int32_t leastRotation(const uint8_t* s, int32_t n) {
  int32_t i = 0, j = 1;
  while (i < n && j < n) {
    const int32_t k = s[i] != s[j] ? 0 : commonPrefix(s, n, i, j, n);  // mostly 0: skip the call
    if (k == n) return -1;
    const int32_t a = i + k < n ? i + k : i + k - n, b = j + k < n ? j + k : j + k - n;
    (s[a] > s[b] ? i : j) += k + 1;
    if (i == j) ++j;
  }
  return std::min(i, j);
}

/// Huffman code lengths as libbz2 makes them (huffman.c): a heap ordered by weight, ties broken by subtree
/// depth kept in a weight's low byte, and weights halved until no code is longer than `max_len`.
void makeCodeLengths(uint8_t* len, const int32_t* freq, int alpha, int max_len) {
  int32_t heap[kMaxAlphabet + 2], weight[kMaxAlphabet * 2], parent[kMaxAlphabet * 2];
  for (int i = 0; i < alpha; ++i) weight[i + 1] = (freq[i] == 0 ? 1 : freq[i]) << 8;
  for (;;) {
    int nodes = alpha, n_heap = 0;
    heap[0] = 0;
    weight[0] = 0;
    parent[0] = -2;
    const auto up = [&](int z) {
      const int32_t tmp = heap[z];
      while (weight[tmp] < weight[heap[z >> 1]]) {
        heap[z] = heap[z >> 1];
        z >>= 1;
      }
      heap[z] = tmp;
    };
    const auto down = [&](int z) {
      const int32_t tmp = heap[z];
      for (;;) {
        int y = z << 1;
        if (y > n_heap) break;
        if (y < n_heap && weight[heap[y + 1]] < weight[heap[y]]) ++y;
        if (weight[tmp] < weight[heap[y]]) break;
        heap[z] = heap[y];
        z = y;
      }
      heap[z] = tmp;
    };
    for (int i = 1; i <= alpha; ++i) {
      parent[i] = -1;
      heap[++n_heap] = i;
      up(n_heap);
    }
    while (n_heap > 1) {
      const int32_t n1 = heap[1];
      heap[1] = heap[n_heap--];
      down(1);
      const int32_t n2 = heap[1];
      heap[1] = heap[n_heap--];
      down(1);
      parent[n1] = parent[n2] = ++nodes;
      weight[nodes] = ((weight[n1] & ~0xff) + (weight[n2] & ~0xff)) |
                      (1 + std::max(weight[n1] & 0xff, weight[n2] & 0xff));
      parent[nodes] = -1;
      heap[++n_heap] = nodes;
      up(n_heap);
    }
    bool too_long = false;
    for (int i = 1; i <= alpha; ++i) {
      int depth = 0;
      for (int k = i; parent[k] >= 0; k = parent[k]) ++depth;
      len[i - 1] = static_cast<uint8_t>(depth);
      too_long |= depth > max_len;
    }
    if (!too_long) return;
    for (int i = 1; i <= alpha; ++i) weight[i] = (1 + (weight[i] >> 8) / 2) << 8;
  }
}

/// One stream: the first run-length step into blocks, each block sorted, coded and written.
class Encoder {
 public:
  explicit Encoder(std::string& out) : bits_(out) { block_.resize(kBlockMax + 20); }

  /// False if a block is periodic (the caller then uses libbz2).
  bool encode(const uint8_t* in, std::size_t n) {
    bits_.putByte('B');
    bits_.putByte('Z');
    bits_.putByte('h');
    bits_.putByte('0' + kBlockSize100k);
    in_ = in;
    newBlock(0);
    for (std::size_t i = 0, end; i < n; i = end) {  // a run of equal bytes at a time
      const uint8_t c = in[i];
      for (end = i + 1; end < n && in[end] == c;) ++end;
      // Each byte checks first whether the block is full: libbz2's blocks end where its do.
      if (n_block_ >= kBlockMax && !endBlock(run_from_)) return false;
      startRun(c, i);
      for (std::size_t left = end - i - 1; left > 0;) {
        if (n_block_ >= kBlockMax && !endBlock(run_from_)) return false;
        if (run_length_ == 255) {
          startRun(c, end - left--);
          continue;
        }
        const std::size_t more = std::min<std::size_t>(left, 255 - run_length_);  // the block does not fill
        run_length_ += static_cast<int>(more);
        left -= more;
      }
    }
    if (run_length_ > 0) addRun();
    if (n_block_ > 0 && !endBlock(n)) return false;
    for (uint8_t b : {0x17, 0x72, 0x45, 0x38, 0x50, 0x90}) bits_.putByte(b);
    bits_.put32(combined_crc_);
    bits_.finish();
    return true;
  }

 private:
  void newBlock(std::size_t from) {
    n_block_ = 0;
    block_from_ = from;
    std::fill(std::begin(in_use_), std::end(in_use_), false);
  }
  /// Ends the pending run (up to 255 equal bytes) and starts one of `c` at input byte `at`.
  void startRun(uint8_t c, std::size_t at) {
    if (run_length_ > 0) addRun();
    run_char_ = c;
    run_length_ = 1;
    run_from_ = at;
  }
  void addRun() {  // 1 to 3 bytes as they are, 4 or more as 4 and a count
    in_use_[run_char_] = true;
    for (int i = 0; i < std::min(run_length_, 4); ++i) block_[n_block_++] = run_char_;
    if (run_length_ >= 4) {
      in_use_[run_length_ - 4] = true;
      block_[n_block_++] = static_cast<uint8_t>(run_length_ - 4);
    }
    run_length_ = 0;
  }

  /// The block holds the input's bytes up to `to` (a pending run goes on in the next block).
  bool endBlock(std::size_t to) {
    const uint32_t crc = ~kCrc.update(0xffffffffu, in_ + block_from_, to - block_from_);
    combined_crc_ = ((combined_crc_ << 1) | (combined_crc_ >> 31)) ^ crc;
    int32_t orig_ptr = 0;
    if (!sortBlock(orig_ptr)) return false;
    for (uint8_t b : {0x31, 0x41, 0x59, 0x26, 0x53, 0x59}) bits_.putByte(b);
    bits_.put32(crc);
    bits_.put(1, 0);  // not randomised
    bits_.put(24, static_cast<uint32_t>(orig_ptr));
    moveToFront();
    sendValues();
    newBlock(to);
    return true;
  }

  /// last_: the last column of the block's sorted rotations, each byte as its rank among the bytes in use;
  /// `orig_ptr`: the block's own row.
  bool sortBlock(int32_t& orig_ptr) {
    n_in_use_ = 0;
    for (int c = 0; c < 256; ++c)
      if (in_use_[c]) seq_[c] = static_cast<uint8_t>(n_in_use_++);
    const int32_t n = n_block_;
    const int32_t k = leastRotation(block_.data(), n);
    if (k < 0) return false;
    rotated_.resize(n);
    std::memcpy(rotated_.data(), block_.data() + k, n - k);
    std::memcpy(rotated_.data() + (n - k), block_.data(), k);
    sa_.resize(n);
    if (divsufsort(rotated_.data(), sa_.data(), n) != 0) return false;
    last_.resize(n);
    const int32_t own = k == 0 ? 0 : n - k;
    for (int32_t r = 0; r < n; ++r) {
      const int32_t at = sa_[r];
      last_[r] = seq_[rotated_[at == 0 ? n - 1 : at - 1]];
      if (at == own) orig_ptr = r;
    }
    return true;
  }

  /// The move-to-front values of last_, with runs of zeros in bijective base 2 (RUNA, RUNB) and an EOB.
  void moveToFront() {
    uint8_t front[256];
    const int eob = n_in_use_ + 1;
    std::fill(freq_, freq_ + kMaxAlphabet, 0);
    for (int i = 0; i < n_in_use_; ++i) front[i] = static_cast<uint8_t>(i);
    mtf_.clear();
    int32_t zeros = 0;
    const auto emit = [&](uint16_t v) {
      mtf_.push_back(v);
      ++freq_[v];
    };
    const auto flushZeros = [&] {
      if (zeros == 0) return;
      for (--zeros;; zeros = (zeros - 2) / 2) {
        emit(zeros & 1 ? kRunB : kRunA);
        if (zeros < 2) break;
      }
      zeros = 0;
    };
    for (const uint8_t c : last_) {
      if (front[0] == c) {
        ++zeros;
        continue;
      }
      flushZeros();
      uint8_t carry = front[1];  // shifts the front down until c's place
      front[1] = front[0];
      int j = 1;
      while (carry != c) std::swap(carry, front[++j]);
      front[0] = c;
      emit(static_cast<uint16_t>(j + 1));
    }
    flushZeros();
    emit(static_cast<uint16_t>(eob));
  }

  /// The Huffman tables, chosen as libbz2 chooses them (compress.c, sendMTFValues), then the block's bits.
  void sendValues() {
    const int alpha = n_in_use_ + 2;
    const int32_t n_mtf = static_cast<int32_t>(mtf_.size());
    const int groups = n_mtf < 200 ? 2 : n_mtf < 600 ? 3 : n_mtf < 1200 ? 4 : n_mtf < 2400 ? 5 : 6;
    uint8_t len[kGroups][kMaxAlphabet];
    for (auto& l : len) std::fill(l, l + kMaxAlphabet, kGreaterCost);
    // Initial tables: the alphabet cut into `groups` ranges of about equal frequency.
    for (int part = groups, start = 0, left = n_mtf; part > 0; --part) {
      const int target = left / part;
      int end = start - 1, sum = 0;
      while (sum < target && end < alpha - 1) sum += freq_[++end];
      if (end > start && part != groups && part != 1 && (groups - part) % 2 == 1) sum -= freq_[end--];
      for (int v = 0; v < alpha; ++v) len[part - 1][v] = v >= start && v <= end ? kLesserCost : kGreaterCost;
      start = end + 1;
      left -= sum;
    }
    // Refined: each group of 50 values goes to its cheapest table, and the tables are rebuilt from them.
    for (int iter = 0; iter < kIterations; ++iter) {
      int32_t rfreq[kGroups][kMaxAlphabet] = {};
      selectors_.clear();
      // A value's lengths in the six tables as 16-bit lanes: a group's 50 of them add up to 850 at most.
      uint64_t packed[kMaxAlphabet][2] = {};
      for (int t = 0; t < groups; ++t)
        for (int v = 0; v < alpha; ++v) packed[v][t / 4] |= uint64_t{len[t][v]} << (16 * (t % 4));
      for (int32_t gs = 0; gs < n_mtf; gs += kGroupSize) {
        const int32_t ge = std::min(gs + kGroupSize, n_mtf);
        uint64_t sum[2] = {};
        for (int32_t i = gs; i < ge; ++i) {
          sum[0] += packed[mtf_[i]][0];
          sum[1] += packed[mtf_[i]][1];
        }
        uint32_t cost[kGroups];
        for (int t = 0; t < kGroups; ++t) cost[t] = (sum[t / 4] >> (16 * (t % 4))) & 0xffff;
        int best = 0;
        for (int t = 1; t < groups; ++t)
          if (cost[t] < cost[best]) best = t;
        selectors_.push_back(static_cast<uint8_t>(best));
        for (int32_t i = gs; i < ge; ++i) ++rfreq[best][mtf_[i]];
      }
      for (int t = 0; t < groups; ++t) makeCodeLengths(len[t], rfreq[t], alpha, kMaxCodeLength);
    }
    int32_t code[kGroups][kMaxAlphabet];
    for (int t = 0; t < groups; ++t) {
      const int min_len = *std::min_element(len[t], len[t] + alpha),
                max_len = *std::max_element(len[t], len[t] + alpha);
      int32_t next = 0;
      for (int l = min_len; l <= max_len; ++l, next <<= 1)
        for (int v = 0; v < alpha; ++v)
          if (len[t][v] == l) code[t][v] = next++;
    }
    // The bytes in use: which of 16 ranges hold one, then which bytes of those ranges.
    bool range_used[16] = {};
    for (int c = 0; c < 256; ++c) range_used[c / 16] |= in_use_[c];
    for (bool used : range_used) bits_.put(1, used);
    for (int r = 0; r < 16; ++r)
      if (range_used[r])
        for (int c = 16 * r; c < 16 * r + 16; ++c) bits_.put(1, in_use_[c]);
    // The selectors, move-to-front coded in unary.
    bits_.put(3, static_cast<uint32_t>(groups));
    bits_.put(15, static_cast<uint32_t>(selectors_.size()));
    uint8_t order[kGroups];
    for (int t = 0; t < groups; ++t) order[t] = static_cast<uint8_t>(t);
    for (uint8_t s : selectors_) {
      int j = 0;
      while (order[j] != s) ++j;
      std::memmove(order + 1, order, j);
      order[0] = s;
      for (int i = 0; i < j; ++i) bits_.put(1, 1);
      bits_.put(1, 0);
    }
    // The code lengths, each as a step from the one before.
    for (int t = 0; t < groups; ++t) {
      int current = len[t][0];
      bits_.put(5, static_cast<uint32_t>(current));
      for (int v = 0; v < alpha; ++v) {
        for (; current < len[t][v]; ++current) bits_.put(2, 2);
        for (; current > len[t][v]; --current) bits_.put(2, 3);
        bits_.put(1, 0);
      }
    }
    // The values.
    for (std::size_t g = 0; g < selectors_.size(); ++g) {
      const int t = selectors_[g];
      const std::size_t end = std::min(mtf_.size(), (g + 1) * kGroupSize);
      for (std::size_t i = g * kGroupSize; i < end; ++i) bits_.put(len[t][mtf_[i]], code[t][mtf_[i]]);
    }
  }

  BitWriter bits_;
  std::vector<uint8_t> block_, rotated_, last_, selectors_;
  std::vector<saidx_t> sa_;
  std::vector<uint16_t> mtf_;
  int32_t n_block_ = 0, freq_[kMaxAlphabet] = {};
  int n_in_use_ = 0;
  uint8_t seq_[256] = {};  // a byte's rank among the bytes in use
  bool in_use_[256] = {};
  uint32_t combined_crc_ = 0;
  const uint8_t* in_ = nullptr;
  std::size_t block_from_ = 0;  // the input's first byte in the block
  // The pending run: its byte, length (0: none) and first byte in the input.
  uint8_t run_char_ = 0;
  int run_length_ = 0;
  std::size_t run_from_ = 0;
};

}  // namespace

bool bzip2Compress(const char* in, std::size_t n, std::string& out) {
  out.clear();
  out.reserve(n / 8 + 64);
  if (Encoder(out).encode(reinterpret_cast<const uint8_t*>(in), n)) return true;
  // A periodic block: libbz2 sorts it (its rotations' order among equal ones is its own).
  unsigned int size = static_cast<unsigned int>(n + n / 100 + 600);
  out.resize(size);
  const int r = BZ2_bzBuffToBuffCompress(out.data(), &size, const_cast<char*>(in),
                                         static_cast<unsigned int>(n), kBlockSize100k, 0, 30);
  if (r != BZ_OK) throw std::runtime_error("bz2 compression failed (" + std::to_string(r) + ")");
  out.resize(size);
  return false;
}

}  // namespace swarm_forage
