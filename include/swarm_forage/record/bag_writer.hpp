#pragma once
// A rosbag (format 2.0) writer for one process's record: the bytes rosbag::Bag writes for the same
// messages (test/record/test_bag_writer.cpp), at a fraction of its cost. rosbag::Bag builds two string maps
// and seeks the file twice for every message (an lseek, fstat and read system call each); this writer
// builds a chunk in memory and writes it, compressed, with its index in one call.
#include <ros/serialization.h>
#include <ros/time.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <unordered_map>
#include <vector>

namespace swarm_forage {

/// rosbag's format 2.0 (rosbag_storage's constants.h), as BagWriter writes it and appendBags reads it.
namespace bag_format {
constexpr char kVersion[] = "#ROSBAG V2.0\n";
constexpr uint8_t kOpMessage = 0x02, kOpFileHeader = 0x03, kOpIndex = 0x04, kOpChunk = 0x05,
                  kOpChunkInfo = 0x06, kOpConnection = 0x07;
constexpr uint32_t kFileHeaderLength = 4096;  // the file header record is padded to it
}  // namespace bag_format

class BagWriter {
 public:
  enum class Compression { kNone, kBz2, kLz4 };
  /// rosbag's names of the compressions: "none", "lz4", "bz2".
  static std::vector<std::string> compressionNames();
  /// One of compressionNames(); throws std::invalid_argument for another.
  static Compression compressionNamed(const std::string& name);
  /// A connection as a bag's connection record holds it (bag_append.cpp reads them).
  struct ConnectionRecord {
    uint32_t id = 0;
    std::string topic, type, md5sum, definition;
    std::string record;  // the record's bytes: header and data
  };

  BagWriter() = default;
  BagWriter(const BagWriter&) = delete;
  BagWriter& operator=(const BagWriter&) = delete;
  ~BagWriter();

  /// Creates (truncates) `path`; throws std::runtime_error with the system's reason when it cannot.
  void open(const std::string& path, Compression compression);
  /// After close(): goes on in a new file, `path`, keeping the connections (their ids, and that their records
  /// were written): the parts of one record, which appendBags joins by copying their chunks.
  void reopen(const std::string& path);
  /// Right after open(): the record this file continues had `connections` (a bag's, by id), their records
  /// written there.
  void adopt(const std::vector<ConnectionRecord>& connections);
  /// rosbag's default is 768 KiB of uncompressed messages a chunk.
  void setChunkThreshold(uint32_t bytes) { threshold_ = bytes; }
  bool isOpen() const { return file_ != nullptr; }
  /// Closes the file without writing what is pending (after a write failed: the disk is full): the file is
  /// left as it is, without an index.
  void abandon();
  /// Bytes on disk so far (the chunk being built is not among them).
  uint64_t size() const { return size_; }

  /// Appends `msg` at `time` (>= ros::TIME_MIN) on `topic`; its type's first message makes the connection.
  template <typename M>
  void write(const std::string& topic, const ros::Time& time, const M& msg) {
    Connection& c = connection(topic, ros::message_traits::datatype(msg), ros::message_traits::md5sum(msg),
                               ros::message_traits::definition(msg));
    const uint32_t length = ros::serialization::serializationLength(msg);
    uint8_t* data = startMessage(c, time, length);
    ros::serialization::OStream stream(data, length);
    ros::serialization::serialize(stream, msg);
    endMessage();
  }
  /// Writes the open chunk, the connections and the chunk infos, then the file header; throws on an I/O
  /// error.
  void close();
  Compression compression() const { return compression_; }
  /// rosbag's name of it: "none", "bz2" or "lz4".
  const char* compressionName() const;

  /// Appends a message serialized already (another bag's), on `c.topic` with `c`'s type.
  void writeSerialized(const ConnectionRecord& c, const ros::Time& time, const char* data, uint32_t length);
  /// Appends another bag's chunk as it is: `bytes` is its chunk record (compressed as this writer compresses)
  /// and its index records, `counts` its chunk info's (connection id, messages), `connections` that bag's
  /// connections by id. The chunk's connection ids must be this writer's for the same topics (a bag this
  /// writer's record continues); a connection new to this writer takes the next id, its record being in
  /// the chunk. Returns false, writing nothing, when the ids do not match.
  bool copyChunk(const std::string& bytes, const ros::Time& start, const ros::Time& end,
                 const std::vector<std::pair<uint32_t, uint32_t>>& counts,
                 const std::vector<ConnectionRecord>& connections);

 private:
  struct IndexEntry {  // as an index record holds it: 12 bytes
    uint32_t sec, nsec, offset;
  };
  static_assert(sizeof(IndexEntry) == 12);
  struct Connection {
    uint32_t id;
    std::string topic, record;      // record: the connection record's bytes (header and data)
    std::vector<IndexEntry> index;  // its messages in the open chunk
  };
  struct ChunkInfo {
    uint64_t pos;
    ros::Time start, end;
    std::vector<std::pair<uint32_t, uint32_t>> counts;  // connection id, messages
  };
  Connection& connection(const std::string& topic, const char* type, const char* md5, const char* definition);
  uint8_t* startMessage(Connection& c, const ros::Time& time, uint32_t length);
  void endMessage();
  void writeChunk();
  void put(const void* bytes, std::size_t n);
  void writeFileHeader(uint64_t index_pos);

  std::FILE* file_ = nullptr;
  std::string path_;
  Compression compression_ = Compression::kNone;
  uint32_t threshold_ = 768 * 1024;
  uint64_t size_ = 0;
  std::vector<Connection> connections_;            // by id
  std::unordered_map<std::string, uint32_t> ids_;  // topic -> id
  std::vector<ChunkInfo> chunks_;
  // The chunk being built (uncompressed), its time range and the connections it holds, in id order.
  std::string chunk_, compressed_;
  bool chunk_open_ = false;
  bool fresh_ = false;  // connection() made a connection whose record the chunk does not hold yet
  ros::Time chunk_start_, chunk_end_;
};

}  // namespace swarm_forage
