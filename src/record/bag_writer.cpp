#include "swarm_forage/record/bag_writer.hpp"

#include <roslz4/lz4s.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <map>
#include <stdexcept>

#include "swarm_forage/record/bzip2_encoder.hpp"

namespace swarm_forage {

using namespace bag_format;

namespace {
template <typename T>
std::string bytesOf(const T& value) {
  return std::string(reinterpret_cast<const char*>(&value), sizeof value);
}
std::string bytesOf(const ros::Time& t) { return bytesOf(t.sec) + bytesOf(t.nsec); }

/// A record header as ros::Header::write lays it out: the fields in name order, each as its length and
/// "name=value", after the length of them all.
std::string header(const std::map<std::string, std::string>& fields) {
  std::string body;
  for (const auto& [name, value] : fields) {
    const uint32_t n = static_cast<uint32_t>(name.size() + 1 + value.size());
    body += bytesOf(n) + name + "=" + value;
  }
  return bytesOf(static_cast<uint32_t>(body.size())) + body;
}

std::string op(uint8_t code) { return std::string(1, static_cast<char>(code)); }

void append(std::string& out, const void* bytes, std::size_t n) {
  out.append(static_cast<const char*>(bytes), n);
}

// A message record's header is the same but for its connection and time: built once, patched per message.
// Fields in name order: conn (4 bytes), op (1), time (8).
const std::string kMessageHeader =
    header({{"conn", bytesOf(uint32_t{0})}, {"op", op(kOpMessage)}, {"time", bytesOf(ros::Time())}});
// [length][4]conn=[4 bytes][4]op=[1][4]time=[8 bytes]
constexpr std::size_t kConnAt = 4 + 4 + 5, kTimeAt = kConnAt + 4 + 4 + 3 + 1 + 4 + 5;

/// rosbag's streams' settings: bz2 with 900 kB blocks (bzip2Compress writes libbz2's bytes for them); roslz4
/// block size 6.
void compress(BagWriter::Compression c, std::string& in, std::string& out) {
  if (c == BagWriter::Compression::kBz2) {
    bzip2Compress(in.data(), in.size(), out);
    return;
  }
  for (std::size_t bound = in.size() + in.size() / 64 + 4096;; bound *= 2) {
    unsigned int n = static_cast<unsigned int>(bound);
    out.resize(n);
    const int r =
        roslz4_buffToBuffCompress(in.data(), static_cast<unsigned int>(in.size()), out.data(), &n, 6);
    if (r == ROSLZ4_OK) {
      out.resize(n);
      return;
    }
    if (r != ROSLZ4_OUTPUT_SMALL)
      throw std::runtime_error("lz4 compression failed (" + std::to_string(r) + ")");
  }
}

const std::pair<const char*, BagWriter::Compression> kCompressions[] = {
    {"none", BagWriter::Compression::kNone},
    {"lz4", BagWriter::Compression::kLz4},
    {"bz2", BagWriter::Compression::kBz2}};
}  // namespace

std::vector<std::string> BagWriter::compressionNames() {
  std::vector<std::string> names;
  for (const auto& [name, c] : kCompressions) names.emplace_back(name);
  return names;
}

BagWriter::Compression BagWriter::compressionNamed(const std::string& name) {
  for (const auto& [n, c] : kCompressions)
    if (name == n) return c;
  throw std::invalid_argument("unknown bag compression '" + name + "' (none, lz4 or bz2)");
}

const char* BagWriter::compressionName() const {
  for (const auto& [n, c] : kCompressions)
    if (c == compression_) return n;
  return "none";
}

BagWriter::~BagWriter() {
  if (file_) std::fclose(file_);  // close() was not reached: an exception is on its way
}

void BagWriter::abandon() {
  if (file_) std::fclose(file_);
  file_ = nullptr;
  chunk_.clear();
  chunk_open_ = false;
}

void BagWriter::open(const std::string& path, Compression compression) {
  if (file_) close();
  connections_.clear();
  ids_.clear();
  compression_ = compression;
  reopen(path);
}

void BagWriter::reopen(const std::string& path) {
  if (file_) close();
  file_ = std::fopen(path.c_str(), "wb");
  if (!file_) throw std::runtime_error("cannot create " + path + ": " + std::strerror(errno));
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
  path_ = path;
  size_ = 0;
  chunks_.clear();
  chunk_.clear();
  chunk_open_ = fresh_ = false;
  for (Connection& c : connections_) c.index.clear();
  put(kVersion, sizeof kVersion - 1);
  writeFileHeader(0);
}

void BagWriter::adopt(const std::vector<ConnectionRecord>& connections) {
  if (!connections_.empty() || chunk_open_) throw std::logic_error("BagWriter::adopt after a write");
  for (const ConnectionRecord& c : connections) {
    if (c.id != connections_.size())
      throw std::invalid_argument("BagWriter::adopt: connection ids out of order");
    ids_.emplace(c.topic, c.id);
    connections_.push_back({c.id, c.topic, c.record, {}});
  }
}

void BagWriter::writeFileHeader(uint64_t index_pos) {
  const std::string h = header({{"chunk_count", bytesOf(static_cast<uint32_t>(chunks_.size()))},
                                {"conn_count", bytesOf(static_cast<uint32_t>(connections_.size()))},
                                {"index_pos", bytesOf(index_pos)},
                                {"op", op(kOpFileHeader)}});
  const uint32_t padding = h.size() - 4 < kFileHeaderLength ? kFileHeaderLength - (h.size() - 4) : 0;
  const std::string record = h + bytesOf(padding) + std::string(padding, ' ');
  put(record.data(), record.size());
}

BagWriter::Connection& BagWriter::connection(const std::string& topic, const char* type, const char* md5,
                                             const char* definition) {
  const auto found = ids_.find(topic);
  if (found != ids_.end()) return connections_[found->second];
  // rosbag's connection for a write without a connection header: one per topic, ids in order of first write.
  const uint32_t id = static_cast<uint32_t>(connections_.size());
  ids_.emplace(topic, id);
  Connection c{id,
               topic,
               header({{"conn", bytesOf(id)}, {"op", op(kOpConnection)}, {"topic", topic}}) +
                   header({{"md5sum", md5}, {"message_definition", definition}, {"type", type}}),
               {}};
  connections_.push_back(std::move(c));
  fresh_ = true;
  return connections_.back();
}

uint8_t* BagWriter::startMessage(Connection& c, const ros::Time& time, uint32_t length) {
  if (time < ros::TIME_MIN) throw std::invalid_argument("a bag cannot hold a message at time 0");
  if (!file_) throw std::logic_error("BagWriter::write before open()");
  if (!chunk_open_) {
    chunk_open_ = true;
    chunk_start_ = chunk_end_ = time;
  }
  if (fresh_) {  // a new connection's record goes into the chunk before its first message, as rosbag's
    chunk_ += c.record;
    fresh_ = false;
  }
  c.index.push_back({time.sec, time.nsec, static_cast<uint32_t>(chunk_.size())});
  const std::size_t at = chunk_.size();
  chunk_ += kMessageHeader;
  std::memcpy(&chunk_[at + kConnAt], &c.id, 4);
  std::memcpy(&chunk_[at + kTimeAt], &time.sec, 4);
  std::memcpy(&chunk_[at + kTimeAt + 4], &time.nsec, 4);
  append(chunk_, &length, 4);
  if (time > chunk_end_)
    chunk_end_ = time;
  else if (time < chunk_start_)
    chunk_start_ = time;
  chunk_.resize(chunk_.size() + length);
  return reinterpret_cast<uint8_t*>(&chunk_[chunk_.size() - length]);
}

void BagWriter::writeSerialized(const ConnectionRecord& c, const ros::Time& time, const char* data,
                                uint32_t length) {
  Connection& own = connection(c.topic, c.type.c_str(), c.md5sum.c_str(), c.definition.c_str());
  std::memcpy(startMessage(own, time, length), data, length);
  endMessage();
}

bool BagWriter::copyChunk(const std::string& bytes, const ros::Time& start, const ros::Time& end,
                          const std::vector<std::pair<uint32_t, uint32_t>>& counts,
                          const std::vector<ConnectionRecord>& connections) {
  if (!file_) throw std::logic_error("BagWriter::copyChunk before open()");
  std::size_t next = connections_.size();
  for (const auto& [id, count] : counts) {
    if (id >= connections.size() || connections[id].id != id) return false;
    if (id < connections_.size() ? connections_[id].record != connections[id].record : id != next++)
      return false;
  }
  writeChunk();  // what this writer holds comes first
  for (const auto& [id, count] : counts)
    if (id == connections_.size()) {  // its record is in the chunk: not written again
      ids_.emplace(connections[id].topic, id);
      connections_.push_back({id, connections[id].topic, connections[id].record, {}});
    }
  chunks_.push_back({size_, start, end, counts});
  put(bytes.data(), bytes.size());
  return true;
}

void BagWriter::endMessage() {
  if (chunk_.size() > threshold_) writeChunk();
}

void BagWriter::writeChunk() {
  if (!chunk_open_) return;
  ChunkInfo info{size_, chunk_start_, chunk_end_, {}};
  const std::string* data = &chunk_;
  if (compression_ != Compression::kNone) {
    compress(compression_, chunk_, compressed_);
    data = &compressed_;
  }
  std::string out = header({{"compression", compressionName()},
                            {"op", op(kOpChunk)},
                            {"size", bytesOf(static_cast<uint32_t>(chunk_.size()))}}) +
                    bytesOf(static_cast<uint32_t>(data->size()));
  put(out.data(), out.size());
  put(data->data(), data->size());
  // Its index: a record per connection in the chunk, in id order, the entries in time order (stable, as
  // rosbag's multiset with an end hint keeps them).
  out.clear();
  for (Connection& c : connections_) {
    if (c.index.empty()) continue;
    const uint32_t count = static_cast<uint32_t>(c.index.size());
    std::stable_sort(c.index.begin(), c.index.end(), [](const IndexEntry& a, const IndexEntry& b) {
      return a.sec != b.sec ? a.sec < b.sec : a.nsec < b.nsec;
    });
    out += header({{"conn", bytesOf(c.id)},
                   {"count", bytesOf(count)},
                   {"op", op(kOpIndex)},
                   {"ver", bytesOf(uint32_t{1})}});
    out += bytesOf(count * 12);
    append(out, c.index.data(), c.index.size() * sizeof(IndexEntry));
    info.counts.emplace_back(c.id, count);
    c.index.clear();
  }
  put(out.data(), out.size());
  chunks_.push_back(std::move(info));
  chunk_.clear();
  chunk_open_ = false;
}

void BagWriter::put(const void* bytes, std::size_t n) {
  if (n && std::fwrite(bytes, 1, n, file_) != n)
    throw std::runtime_error("cannot write " + path_ + ": " + std::strerror(errno));
  size_ += n;
}

void BagWriter::close() {
  if (!file_) return;
  writeChunk();
  const uint64_t index_pos = size_;
  std::string out;
  for (const Connection& c : connections_) out += c.record;
  for (const ChunkInfo& k : chunks_) {
    out += header({{"chunk_pos", bytesOf(k.pos)},
                   {"count", bytesOf(static_cast<uint32_t>(k.counts.size()))},
                   {"end_time", bytesOf(k.end)},
                   {"op", op(kOpChunkInfo)},
                   {"start_time", bytesOf(k.start)},
                   {"ver", bytesOf(uint32_t{1})}});
    out += bytesOf(static_cast<uint32_t>(8 * k.counts.size()));
    for (const auto& [id, count] : k.counts) out += bytesOf(id) + bytesOf(count);
  }
  put(out.data(), out.size());
  const uint64_t end = size_;
  if (std::fseek(file_, sizeof kVersion - 1, SEEK_SET) != 0)
    throw std::runtime_error("cannot write " + path_ + ": " + std::strerror(errno));
  writeFileHeader(index_pos);
  size_ = end;
  std::FILE* f = file_;
  file_ = nullptr;
  if (std::fclose(f) != 0) throw std::runtime_error("cannot write " + path_ + ": " + std::strerror(errno));
}

}  // namespace swarm_forage
