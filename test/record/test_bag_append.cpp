// appendBags joins a record's parts by copying their chunks, decoding only those with a message to
// replace, into the messages of the record written without a break.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <std_msgs/String.h>
#include <swarm_forage/SwarmStatus.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

#include "swarm_forage/record/bag_append.hpp"

namespace swarm_forage {
namespace {

using Message = std::tuple<std::string, uint64_t, std::vector<uint8_t>>;

std::vector<Message> contents(const std::string& path) {
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  std::vector<Message> out;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    std::vector<uint8_t> bytes(m.size());
    ros::serialization::OStream s(bytes.data(), bytes.size());
    m.write(s);
    out.emplace_back(m.getTopic(), m.getTime().toNSec(), std::move(bytes));
  }
  return out;
}

struct Files {
  std::vector<std::string> paths;
  std::string operator()(const std::string& name) {
    paths.push_back(testing::TempDir() + "bag_append_" + std::to_string(::getpid()) + "_" + name + ".bag");
    return paths.back();
  }
  ~Files() {
    for (const std::string& p : paths) std::remove(p.c_str());
  }
};

/// Ticks [from, to) of a record: tick-0 records, two messages a tick, a topic that first appears late.
void ticks(BagWriter& bag, int from, int to) {
  for (int t = from; t < to; ++t) {
    const ros::Time stamp(1 + t / 5, 200000000u * static_cast<unsigned>(t % 5));
    std_msgs::String text;
    if (t == 0) {
      text.data = "provenance of the first process";
      bag.write("/world/provenance", stamp, text);
    }
    SwarmStatus s;
    s.tick = t;
    s.controller = "crw";
    s.state_names = {"explore", "homing"};
    s.state_counts = {static_cast<uint32_t>(t), static_cast<uint32_t>(t % 7)};
    bag.write("/swarm/status", stamp, s);
    text.data = std::string(static_cast<std::size_t>(t % 61), 'a' + t % 26);
    bag.write("/world/performance", stamp, text);
    if (t == 2900) bag.write("/world/run_end", stamp, text);
  }
}

constexpr uint32_t kChunk = 8000;  // bytes: a few dozen chunks a record

std::string whole(Files& files, BagWriter::Compression c) {
  const std::string path = files("whole");
  BagWriter bag;
  bag.open(path, c);
  bag.setChunkThreshold(kChunk);
  ticks(bag, 0, 3000);
  bag.close();
  return path;
}

TEST(BagAppend, CopiesEveryChunkOfAOneProcessRecord) {
  Files files;
  const std::string reference = whole(files, BagWriter::Compression::kBz2);
  // One process: checkpoints at ticks 1000 and 2000 (reopen keeps the connection ids), then the join.
  std::vector<std::string> parts = {files("part0"), files("part1"), files("part2")};
  BagWriter bag;
  bag.open(parts[0], BagWriter::Compression::kBz2);
  bag.setChunkThreshold(kChunk);
  for (int k = 0; k < 3; ++k) {
    if (k) bag.reopen(parts[k]);
    ticks(bag, 1000 * k, 1000 * (k + 1));
    bag.close();
  }
  BagWriter joined;
  joined.open(files("joined"), BagWriter::Compression::kBz2);
  const AppendCounts n = appendBags(parts, joined, {});
  joined.close();
  EXPECT_EQ(n.decoded, 0u);
  EXPECT_GT(n.copied, 20u);
  EXPECT_EQ(contents(files.paths.back()), contents(reference));
}

TEST(BagAppend, DecodesOnlyTheChunksWithAMessageToReplace) {
  Files files;
  const std::string reference = files("reference");
  {
    BagWriter bag;
    bag.open(reference, BagWriter::Compression::kLz4);
    bag.setChunkThreshold(kChunk);
    ticks(bag, 0, 3000);
    bag.close();
  }
  // A second process resumes from the checkpoint at tick 1500: its part adopts the first part's ids.
  const std::string first = files("first"), second = files("second");
  BagWriter a;
  a.open(first, BagWriter::Compression::kLz4);
  a.setChunkThreshold(kChunk);
  ticks(a, 0, 1500);
  a.close();
  BagWriter b;
  b.open(second, BagWriter::Compression::kLz4);
  b.adopt(bagConnections(first));
  b.setChunkThreshold(kChunk);
  ticks(b, 1500, 3000);
  b.close();
  std_msgs::String mine;
  mine.data = "provenance of the second process";
  Substitute provenance{{"/world/provenance"},
                        [&](const std::string& topic, const ros::Time& time, BagWriter& out) {
                          if (topic != "/world/provenance") return false;
                          out.write(topic, time, mine);
                          return true;
                        }};
  BagWriter joined;
  joined.open(files("joined"), BagWriter::Compression::kLz4);
  const AppendCounts n = appendBags({first, second}, joined, provenance);
  joined.close();
  EXPECT_EQ(n.decoded, 1u);
  EXPECT_GT(n.copied, 20u);
  std::vector<Message> expected = contents(reference), got = contents(files.paths.back());
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    if (std::get<0>(expected[i]) != "/world/provenance") {
      EXPECT_EQ(got[i], expected[i]) << "message " << i;
    } else {
      EXPECT_EQ(std::get<2>(got[i]).size(), 4 + mine.data.size());
    }
  }
}

TEST(BagAppend, DecodesChunksOfAnotherCompressionOrFromRosbag) {
  Files files;
  const std::string reference = whole(files, BagWriter::Compression::kBz2);
  BagWriter lz4;
  const std::string part = files("lz4");
  lz4.open(part, BagWriter::Compression::kLz4);
  ticks(lz4, 0, 3000);
  lz4.close();
  BagWriter joined;
  joined.open(files("joined"), BagWriter::Compression::kBz2);
  const AppendCounts n = appendBags({part}, joined, {});
  joined.close();
  EXPECT_EQ(n.copied, 0u);
  EXPECT_GT(n.decoded, 0u);
  EXPECT_EQ(contents(files.paths.back()), contents(reference));
  // rosbag's own bags have the same bytes, so their chunks are copied.
  const std::string theirs = files("rosbag");
  {
    rosbag::Bag bag(theirs, rosbag::bagmode::Write);
    bag.setCompression(rosbag::compression::BZ2);
    std_msgs::String text;
    for (int t = 1; t <= 100; ++t) bag.write("/a", ros::Time(t, 0), text);
  }
  BagWriter copy;
  copy.open(files("copy"), BagWriter::Compression::kBz2);
  EXPECT_EQ(appendBags({theirs}, copy, {}).copied, 1u);
  copy.close();
  EXPECT_EQ(contents(files.paths.back()), contents(theirs));
}

TEST(BagAppend, ABrokenPartIsNamed) {
  Files files;
  const std::string reference = whole(files, BagWriter::Compression::kNone), cut = files("cut"),
                    other = files("not_a_bag");
  std::ifstream in(reference, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() - 100);
  std::ofstream(other, std::ios::binary) << "hello";
  for (const std::string& bad : {cut, other, files("missing")}) {
    BagWriter out;
    out.open(files("out"), BagWriter::Compression::kNone);
    try {
      appendBags({bad}, out, {});
      ADD_FAILURE() << bad << " was read";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
    out.close();
  }
  std::atomic<bool> stop{true};
  BagWriter out;
  out.open(files("stopped"), BagWriter::Compression::kNone);
  EXPECT_THROW(appendBags({reference}, out, {}, &stop), JoinInterrupted);
  out.close();
}

}  // namespace
}  // namespace swarm_forage
