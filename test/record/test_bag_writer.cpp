// BagWriter writes the bytes rosbag::Bag writes for the same messages, for every compression and across
// chunk boundaries, and rosbag reads them back.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <std_msgs/String.h>
#include <swarm_forage/SwarmStatus.h>
#include <topic_tools/shape_shifter.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

#include "swarm_forage/record/bag_writer.hpp"

namespace swarm_forage {
namespace {

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

struct TempBag {
  std::string path;
  explicit TempBag(const std::string& name)
      : path(testing::TempDir() + "bag_writer_" + std::to_string(::getpid()) + "_" + name + ".bag") {}
  ~TempBag() { std::remove(path.c_str()); }
};

/// The same messages to either writer: two types on three topics, a time that goes back (a chunk's
/// start time and its index's order), and a topic that first appears in a later chunk.
template <typename Bag>
void writeRun(Bag& bag, int ticks) {
  for (int t = 1; t <= ticks; ++t) {
    const ros::Time stamp(t, 200000000u * static_cast<unsigned>(t % 5));
    SwarmStatus s;
    s.tick = t;
    s.controller = t % 3 ? "crw" : "dpo";
    s.state_names = {"explore", "homing"};
    s.state_counts = {static_cast<uint32_t>(t), static_cast<uint32_t>(2 * t)};
    bag.write("/swarm/status", stamp, s);
    std_msgs::String text;
    text.data = std::string(static_cast<std::size_t>(t % 97), 'a' + t % 26);
    bag.write("/world/performance", stamp, text);
    if (t % 17 == 0) bag.write("/world/performance", ros::Time(t > 2 ? t - 2 : 1, 0), text);
    if (t > ticks / 2 && t % 50 == 0) bag.write("/world/run_end", stamp, text);
  }
}

void expectSameBytes(const std::string& compression, uint32_t threshold, int ticks) {
  TempBag theirs("rosbag_" + compression), ours("ours_" + compression);
  rosbag::Bag bag(theirs.path, rosbag::bagmode::Write);
  bag.setCompression(compression == "bz2"   ? rosbag::compression::BZ2
                     : compression == "lz4" ? rosbag::compression::LZ4
                                            : rosbag::compression::Uncompressed);
  bag.setChunkThreshold(threshold);
  writeRun(bag, ticks);
  bag.close();

  BagWriter writer;
  writer.open(ours.path, BagWriter::compressionNamed(compression));
  writer.setChunkThreshold(threshold);
  writeRun(writer, ticks);
  writer.close();

  const std::string a = bytesOf(theirs.path), b = bytesOf(ours.path);
  ASSERT_GT(a.size(), 4096u);
  EXPECT_EQ(writer.size(), b.size());
  EXPECT_TRUE(a == b) << compression << ": rosbag wrote " << a.size() << " bytes, BagWriter " << b.size();

  rosbag::Bag read(ours.path, rosbag::bagmode::Read);
  std::size_t n = 0;
  for (const rosbag::MessageInstance& m : rosbag::View(read)) n += m.getTopic().empty() ? 0 : 1;
  EXPECT_EQ(n, static_cast<std::size_t>(2 * ticks + ticks / 17 + (ticks - ticks / 2) / 50));
}

TEST(BagWriter, WritesRosbagsBytesUncompressed) { expectSameBytes("none", 4000, 600); }
TEST(BagWriter, WritesRosbagsBytesBz2) { expectSameBytes("bz2", 4000, 600); }
TEST(BagWriter, WritesRosbagsBytesLz4) { expectSameBytes("lz4", 4000, 600); }
TEST(BagWriter, WritesRosbagsBytesInDefaultChunks) {
  for (const char* c : {"none", "bz2", "lz4"}) expectSameBytes(c, 768 * 1024, 20000);
}

TEST(BagWriter, CopiesMessagesOfAnyTypeAsRosbagDoes) {
  // The join's path: a bag's messages instantiated as ShapeShifter and written again.
  TempBag source("source"), theirs("copy_rosbag"), ours("copy_ours");
  {
    rosbag::Bag bag(source.path, rosbag::bagmode::Write);
    writeRun(bag, 300);
  }
  rosbag::Bag in(source.path, rosbag::bagmode::Read), copy(theirs.path, rosbag::bagmode::Write);
  copy.setCompression(rosbag::compression::BZ2);
  BagWriter writer;
  writer.open(ours.path, BagWriter::Compression::kBz2);
  for (const rosbag::MessageInstance& m : rosbag::View(in)) {
    const auto msg = m.instantiate<topic_tools::ShapeShifter>();
    copy.write(m.getTopic(), m.getTime(), *msg);
    writer.write(m.getTopic(), m.getTime(), *msg);
  }
  copy.close();
  writer.close();
  EXPECT_TRUE(bytesOf(theirs.path) == bytesOf(ours.path));
}

TEST(BagWriter, AnEmptyBagIsRosbags) {
  TempBag theirs("empty_rosbag"), ours("empty_ours");
  rosbag::Bag(theirs.path, rosbag::bagmode::Write).close();
  BagWriter writer;
  writer.open(ours.path, BagWriter::Compression::kNone);
  writer.close();
  EXPECT_TRUE(bytesOf(theirs.path) == bytesOf(ours.path));
}

TEST(BagWriter, RefusesWhatRosbagRefuses) {
  EXPECT_THROW(BagWriter::compressionNamed("zip"), std::invalid_argument);
  TempBag ours("time0");
  BagWriter writer;
  writer.open(ours.path, BagWriter::Compression::kNone);
  EXPECT_THROW(writer.write("/a", ros::Time(0, 0), std_msgs::String()), std::invalid_argument);
  writer.close();
  EXPECT_THROW(writer.open("/nonexistent_folder_of_swarm_forage/x.bag", BagWriter::Compression::kNone),
               std::runtime_error);
}

}  // namespace
}  // namespace swarm_forage
