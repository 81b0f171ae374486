#pragma once
// The records of a bag of format 2.0, read by position: the one parser of a bag's structure, for joining a
// record's segments (bag_append) and for checking a bag before rosbag reads it (checkBag). rosbag trusts the
// lengths and offsets it reads: one flipped byte in an index can make it read past its buffers and crash.
#include <ros/time.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "swarm_forage/record/bag_writer.hpp"

namespace swarm_forage {
namespace bag_records {

using Fields = std::map<std::string, std::string>;

/// One bag file read by position; every error is `prefix` followed by what is wrong.
class BagFile {
 public:
  /// Throws std::runtime_error (prefix + "cannot be read") when the file cannot be opened.
  BagFile(const std::string& path, std::string prefix);
  const std::string& path() const { return path_; }
  uint64_t size() const { return size_; }
  /// Bytes [pos, pos + n); a range past the end is an error ("is cut short").
  std::string read(uint64_t pos, uint64_t n);
  /// Where errors say they are, from now on ("" for nowhere in particular).
  void at(std::string where) { where_ = std::move(where); }
  [[noreturn]] void fail(const std::string& why) const;

 private:
  std::string path_, prefix_, where_;
  std::ifstream in_;
  uint64_t size_ = 0;
};

uint32_t u32At(const std::string& bytes, std::size_t at);

/// The fields of a record header: [length]name=value ... over bytes [at, at + n).
Fields parseFields(const std::string& bytes, std::size_t at, std::size_t n, const BagFile& f);

/// A record [header length][header][data length][data] at `at` of `bytes`: its data is [data, data + size).
struct Record {
  Fields header;
  std::size_t data = 0, size = 0, next = 0;
};
Record parseRecord(const std::string& bytes, std::size_t at, const BagFile& f);

/// A header field of exactly sizeof(T) bytes; an error naming it when missing or of another size.
template <typename T>
T field(const Fields& h, const char* name, const BagFile& f) {
  const auto it = h.find(name);
  if (it == h.end() || it->second.size() != sizeof(T))
    f.fail(std::string("has a record without its ") + name);
  T v;
  std::memcpy(&v, it->second.data(), sizeof(T));
  return v;
}
ros::Time timeField(const Fields& h, const char* name, const BagFile& f);
void expectOp(const Fields& h, uint8_t op, const char* what, const BagFile& f);

/// A chunk as the index lists it.
struct Chunk {
  uint64_t pos = 0, end = 0;  // its chunk record and index records: [pos, end)
  ros::Time start, stop;
  std::vector<std::pair<uint32_t, uint32_t>> counts;  // connection id, messages
};
/// A bag's index section: its connections and chunks.
struct Layout {
  std::vector<BagWriter::ConnectionRecord> connections;  // by id
  std::vector<Chunk> chunks;                             // in file order
  uint64_t first_chunk = 0, index_pos = 0;               // where the chunks start and end
};
/// The connections and chunks of a bag of format 2.0, from its file header and index section: the index
/// records well formed and whole, ids within the connection count and each once, the chunks between the
/// file header and the index, in order, each ending where the next begins.
Layout readLayout(BagFile& f);

/// The `size` bytes of chunk data [at, at + n) of `bytes` compressed with `compression` (none, bz2, lz4).
std::string decompress(const std::string& compression, const std::string& bytes, std::size_t at,
                       std::size_t n, uint32_t size, const BagFile& f);

}  // namespace bag_records

/// Checks the bag at `path` before rosbag reads it: its file header, index, every chunk record and the
/// index records after it (every length and offset within its record, the file or the chunk; op codes and
/// versions known; counts that agree), and inside each decompressed chunk every record, each index entry
/// at a message of its connection and time, and every message indexed. Returns its layout. Throws
/// std::runtime_error "not a readable bag: ..." for a file that is not a bag of format 2.0, and "not a
/// whole bag: ..." saying what is wrong where for one whose records do not hold together.
bag_records::Layout checkBag(const std::string& path);

}  // namespace swarm_forage
