// checkBag: a whole bag is handed to rosbag; one with a byte flipped in its structure (record headers and
// lengths, chunk records, index records and their entries, connections, chunk infos) is refused with the
// reason, and what it lets through rosbag reads as the original: never a crash.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <std_msgs/String.h>
#include <std_msgs/UInt32.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "swarm_forage/core/metrics/run_follower.hpp"
#include "swarm_forage/record/bag_records.hpp"
#include "swarm_forage/ros/runs/follower_messages.hpp"

namespace swarm_forage {
namespace {

struct Files {
  std::vector<std::string> paths;
  std::string operator()(const std::string& name) {
    paths.push_back(testing::TempDir() + "bag_records_" + std::to_string(::getpid()) + "_" + name + ".bag");
    return paths.back();
  }
  ~Files() {
    for (const std::string& p : paths) std::remove(p.c_str());
  }
};

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}
void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

/// A small record: three topics (one first seen late), a few chunks.
std::string smallBag(Files& files, BagWriter::Compression c, const std::string& name) {
  const std::string path = files(name);
  BagWriter bag;
  bag.open(path, c);
  bag.setChunkThreshold(1500);
  for (int t = 0; t < 120; ++t) {
    const ros::Time stamp(1 + t / 5, 200000000u * static_cast<unsigned>(t % 5));
    std_msgs::String text;
    text.data = std::string(static_cast<std::size_t>(t % 23), 'a' + t % 26);
    bag.write("/a", stamp, text);
    std_msgs::UInt32 n;
    n.data = static_cast<uint32_t>(t);
    bag.write("/b", stamp, n);
    if (t >= 70 && t % 10 == 0) bag.write("/c", stamp, text);
  }
  bag.close();
  return path;
}

/// What rosbag reads: each message's time and bytes, in order.
std::vector<std::pair<uint64_t, std::vector<uint8_t>>> contents(const std::string& path) {
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  std::vector<std::pair<uint64_t, std::vector<uint8_t>>> out;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    std::vector<uint8_t> bytes(m.size());
    ros::serialization::OStream s(bytes.data(), bytes.size());
    m.write(s);
    out.emplace_back(m.getTime().toNSec(), std::move(bytes));
  }
  return out;
}

uint32_t u32(const std::string& bytes, uint64_t at) {
  uint32_t v;
  std::memcpy(&v, bytes.data() + at, 4);
  return v;
}

/// The positions of a bag's structure: the file header record's header, each chunk record's header and
/// data length, the index records after each chunk, and the whole index section at the end.
std::vector<uint64_t> structure(const std::string& bytes, const bag_records::Layout& layout) {
  std::vector<uint64_t> at;
  const auto span = [&at](uint64_t from, uint64_t to) {
    for (uint64_t p = from; p < to; ++p) at.push_back(p);
  };
  span(13, 13 + 8 + u32(bytes, 13));
  for (const bag_records::Chunk& c : layout.chunks) {
    const uint64_t header_end = c.pos + 8 + u32(bytes, c.pos);
    span(c.pos, header_end);
    span(header_end + u32(bytes, header_end - 4), c.end);
  }
  span(layout.index_pos, bytes.size());
  return at;
}

bool startsWith(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

TEST(BagRecords, AcceptsWholeBagsOfEveryCompression) {
  Files files;
  for (const auto c :
       {BagWriter::Compression::kNone, BagWriter::Compression::kBz2, BagWriter::Compression::kLz4}) {
    const std::string path = smallBag(files, c, "whole");
    bag_records::Layout layout;
    ASSERT_NO_THROW(layout = checkBag(path));
    EXPECT_GE(layout.chunks.size(), 4u);
    ASSERT_EQ(layout.connections.size(), 3u);
    EXPECT_EQ(layout.connections[2].topic, "/c");
    EXPECT_EQ(layout.connections[1].type, "std_msgs/UInt32");
  }
  // rosbag's own, and an empty bag.
  const std::string theirs = files("rosbag"), empty = files("empty");
  {
    rosbag::Bag bag(theirs, rosbag::bagmode::Write);
    bag.setCompression(rosbag::compression::BZ2);
    bag.setChunkThreshold(1000);
    for (uint32_t t = 1; t < 200; ++t) {
      std_msgs::UInt32 n;
      n.data = t;
      bag.write("/n", ros::Time(t, 0), n);
    }
  }
  rosbag::Bag(empty, rosbag::bagmode::Write).close();
  EXPECT_GE(checkBag(theirs).chunks.size(), 2u);
  EXPECT_TRUE(checkBag(empty).chunks.empty());
}

TEST(BagRecords, RefusesWhatIsNoBagOrNotAWholeOne) {
  Files files;
  const std::string whole = smallBag(files, BagWriter::Compression::kNone, "whole");
  const std::string bytes = bytesOf(whole);
  const std::string hello = files("hello"), cut = files("cut"), open = files("open");
  writeBytes(hello, "hello");
  writeBytes(cut, bytes.substr(0, bytes.size() - 100));
  std::string unindexed = bytes;  // index_pos 0: as a writer leaves it until it closes the bag
  const std::size_t index_pos = unindexed.find("index_pos=") + 10;
  std::fill(unindexed.begin() + index_pos, unindexed.begin() + index_pos + 8, '\0');
  writeBytes(open, unindexed);
  for (const auto& [path, message] :
       {std::pair<std::string, std::string>{files("missing"), "not a readable bag: it cannot be opened"},
        {hello, "not a readable bag: it is not a bag of format 2.0"},
        {cut, "not a whole bag: it "},
        {open, "not a whole bag: it has no index (it was not closed)"}}) {
    try {
      checkBag(path);
      ADD_FAILURE() << path << " was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_TRUE(startsWith(e.what(), message)) << e.what();
    }
    RunFollower follower(1000, RunFollower::Mode::kRecord);
    try {
      feedBag(follower, path);  // the offline readers' way in checks first
      ADD_FAILURE() << path << " was read";
    } catch (const std::runtime_error& e) {
      EXPECT_TRUE(startsWith(e.what(), message)) << e.what();
    }
  }
}

TEST(BagRecords, AFlippedByteInItsStructureIsRefusedOrHarmless) {
  Files files;
  for (const auto c : {BagWriter::Compression::kNone, BagWriter::Compression::kBz2}) {
    const std::string original = smallBag(files, c, "original"), flipped = files("flipped");
    const std::string bytes = bytesOf(original);
    const auto expected = contents(original);
    const std::vector<uint64_t> at = structure(bytes, checkBag(original));
    ASSERT_GT(at.size(), 1000u);
    // Every position of the structure, with three kinds of flip by position. The copy is changed in place,
    // one byte at a time.
    writeBytes(flipped, bytes);
    std::fstream copy(flipped, std::ios::binary | std::ios::in | std::ios::out);
    const auto put = [&copy](uint64_t pos, char byte) {
      copy.seekp(static_cast<std::streamoff>(pos));
      copy.put(byte);
      copy.flush();
    };
    // Refused with the reason (and by feedBag), or read by rosbag as the original (a topic or type name,
    // or a chunk's span, may differ).
    const auto refusedOrHarmless = [&](const std::string& where) {
      try {
        checkBag(flipped);
      } catch (const std::runtime_error& e) {
        EXPECT_TRUE(startsWith(e.what(), "not a whole bag: it ")) << where << ": " << e.what();
        RunFollower follower(1000, RunFollower::Mode::kRecord);
        EXPECT_THROW(feedBag(follower, flipped), std::runtime_error) << where;
        return true;
      }
      try {
        EXPECT_EQ(contents(flipped), expected) << where;
      } catch (const std::exception& e) {
        ADD_FAILURE() << where << " was let through, and rosbag fails: " << e.what();
      }
      return false;
    };
    std::size_t tried = 0, refused = 0;
    for (std::size_t k = 0; k < at.size(); ++k, ++tried) {
      put(at[k], static_cast<char>(bytes[at[k]] ^ std::vector<uint8_t>{0x01, 0x80, 0xff}[k % 3]));
      refused += refusedOrHarmless("byte " + std::to_string(at[k]) + " of " + std::to_string(bytes.size()));
      put(at[k], bytes[at[k]]);
    }
    EXPECT_EQ(tried, at.size());
    EXPECT_GT(refused, tried / 2);
    std::printf("compression %d: %zu flips, %zu refused, the rest read as the original\n",
                static_cast<int>(c), tried, refused);
  }
}

}  // namespace
}  // namespace swarm_forage
