// bzip2Compress against libbz2 itself: the same bytes for every input, a bag's chunks, runs across block
// ends, many blocks, periodic blocks (left to libbz2) and the empty input.
#include <bzlib.h>
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "swarm_forage/record/bzip2_encoder.hpp"

namespace swarm_forage {
namespace {

std::string libbz2(const std::string& in) {
  std::string out(in.size() + in.size() / 100 + 600, '\0');
  unsigned int n = static_cast<unsigned int>(out.size());
  EXPECT_EQ(BZ2_bzBuffToBuffCompress(out.data(), &n, const_cast<char*>(in.data()),
                                     static_cast<unsigned int>(in.size()), 9, 0, 30),
            BZ_OK);
  out.resize(n);
  return out;
}

std::string decoded(const std::string& bz2, std::size_t size) {
  std::string out(size + 1, '\0');
  unsigned int n = static_cast<unsigned int>(out.size());
  EXPECT_EQ(BZ2_bzBuffToBuffDecompress(out.data(), &n, const_cast<char*>(bz2.data()),
                                       static_cast<unsigned int>(bz2.size()), 0, 0),
            BZ_OK);
  out.resize(n);
  return out;
}

/// `periodic`: the input has a periodic block, which libbz2 must sort.
void expectSameAsLibbz2(const std::string& in, const std::string& what, bool periodic = false) {
  std::string ours;
  EXPECT_EQ(bzip2Compress(in.data(), in.size(), ours), !periodic) << what;
  EXPECT_EQ(ours, libbz2(in)) << what << " (" << in.size() << " bytes)";
  EXPECT_EQ(decoded(ours, in.size()), in) << what;
}

/// `n` bytes from `alphabet` symbols, each repeated 1 to `max_run` times.
std::string runs(std::mt19937& rng, std::size_t n, int alphabet, int max_run) {
  std::string s;
  std::uniform_int_distribution<int> sym(0, alphabet - 1), run(1, max_run);
  while (s.size() < n) s.append(static_cast<std::size_t>(run(rng)), static_cast<char>(sym(rng) * 7 + 3));
  s.resize(n);
  return s;
}

/// A record like a run's: small messages, mostly alike, a counter and a few changing fields.
std::string recordLike(std::size_t n) {
  std::string s;
  for (uint32_t tick = 0; s.size() < n; ++tick) {
    s += "\x2e\x00\x00\x00\x04\x00\x00\x00conn=\x01\x00\x00\x00\x03\x00\x00\x00op=\x02";
    s.append(reinterpret_cast<const char*>(&tick), 4);
    s += "crw\x00\x00\x00\x00status:explore=12,homing=4";
    const uint32_t delivered = tick / 37, carrying = (tick * 2654435761u) >> 29;
    s.append(reinterpret_cast<const char*>(&delivered), 4);
    s.append(reinterpret_cast<const char*>(&carrying), 4);
  }
  s.resize(n);
  return s;
}

TEST(Bzip2Encoder, WritesLibbz2sBytesForSmallInputs) {
  expectSameAsLibbz2("", "empty");
  expectSameAsLibbz2("a", "one byte");
  expectSameAsLibbz2("ab", "two bytes");
  expectSameAsLibbz2("banana bandana", "a word");
  std::string all;
  for (int c = 0; c < 256; ++c) all += static_cast<char>(c);
  expectSameAsLibbz2(all, "every byte once");
  for (int length = 1; length <= 300; length += 13)
    expectSameAsLibbz2("x" + std::string(static_cast<std::size_t>(length), 'q') + "y", "a run");
}

TEST(Bzip2Encoder, WritesLibbz2sBytesForRandomInputs) {
  std::mt19937 rng(7);
  for (int alphabet : {1, 2, 3, 17, 256})
    for (int max_run : {1, 3, 6, 300})
      for (std::size_t n : {std::size_t{57}, std::size_t{4099}, std::size_t{70000}})
        expectSameAsLibbz2(runs(rng, n, alphabet, max_run), "alphabet " + std::to_string(alphabet) +
                                                                ", runs up to " + std::to_string(max_run));
}

TEST(Bzip2Encoder, WritesLibbz2sBytesForABagsChunks) {
  expectSameAsLibbz2(recordLike(768 * 1024), "a 768 KiB chunk");
  expectSameAsLibbz2(recordLike(100000), "a short chunk");
}

TEST(Bzip2Encoder, WritesLibbz2sBytesAcrossBlocks) {
  std::mt19937 rng(11);
  const std::size_t block = 900000 - 19;  // libbz2's nblockMAX
  expectSameAsLibbz2(runs(rng, 2500000, 256, 1), "three blocks of noise");
  expectSameAsLibbz2(recordLike(3000000), "a long record");
  // A run that a block's end cuts (it goes on in the next block), and an input ending on a block's end.
  for (std::size_t at : {block - 3, block - 1, block, block + 2}) {
    std::string s = runs(rng, at, 256, 1);
    expectSameAsLibbz2(s, "ends at a block's end");
    s.append(600, 'z');
    s += runs(rng, 1000, 5, 2);
    expectSameAsLibbz2(s, "a run across a block's end");
  }
}

TEST(Bzip2Encoder, LeavesPeriodicBlocksToLibbz2) {
  expectSameAsLibbz2(std::string(1000000, '\0'), "zeros");  // not periodic: its last run is shorter
  expectSameAsLibbz2(std::string(255 * 400, '\0'), "zeros in runs of 255", true);
  std::string abc;
  while (abc.size() < 300000) abc += "abcd";
  expectSameAsLibbz2(abc, "abcd repeated", true);
  std::string first;  // a whole block without runs, then the periodic block
  for (std::size_t i = 0; i < 900000 - 19; ++i) first += static_cast<char>(i * 7 % 251);
  std::string both = first;
  while (both.size() < first.size() + 800000) both += "abcd";
  expectSameAsLibbz2(both, "a periodic second block", true);
}

}  // namespace
}  // namespace swarm_forage
