#include "swarm_forage/ros/bag_append.hpp"

#include <bzlib.h>
#include <roslz4/lz4s.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>

namespace swarm_forage {

namespace {
using Fields = std::map<std::string, std::string>;

/// One bag file read by position; every error names it.
class BagFile {
 public:
  explicit BagFile(const std::string& path) : path_(path), in_(path, std::ios::binary | std::ios::ate) {
    if (!in_) fail("cannot be read");
    size_ = static_cast<uint64_t>(in_.tellg());
  }
  uint64_t size() const { return size_; }
  std::string read(uint64_t pos, uint64_t n) {
    if (pos + n > size_) fail("is cut short (a record ends past its end)");
    std::string bytes(n, '\0');
    in_.seekg(static_cast<std::streamoff>(pos));
    if (!in_.read(bytes.data(), static_cast<std::streamsize>(n))) fail("cannot be read");
    return bytes;
  }
  [[noreturn]] void fail(const std::string& why) const {
    throw std::runtime_error("the bag " + path_ + " " + why);
  }

 private:
  std::string path_;
  std::ifstream in_;
  uint64_t size_ = 0;
};

uint32_t u32At(const std::string& bytes, std::size_t at) {
  uint32_t v;
  std::memcpy(&v, bytes.data() + at, 4);
  return v;
}

/// The fields of a record header: [length]name=value ... over bytes [at, at + n).
Fields parseFields(const std::string& bytes, std::size_t at, std::size_t n, const BagFile& f) {
  Fields fields;
  const std::size_t end = at + n;
  while (at < end) {
    if (at + 4 > end) f.fail("has a malformed record header");
    const uint32_t len = u32At(bytes, at);
    at += 4;
    if (len > end - at) f.fail("has a malformed record header");
    const std::size_t eq = bytes.find('=', at);
    if (eq == std::string::npos || eq >= at + len) f.fail("has a record header field without '='");
    fields.emplace(bytes.substr(at, eq - at), bytes.substr(eq + 1, at + len - eq - 1));
    at += len;
  }
  return fields;
}

/// A record [header length][header][data length][data] at `at`.
struct Record {
  Fields header;
  std::size_t data = 0, size = 0, next = 0;
};
Record parseRecord(const std::string& bytes, std::size_t at, const BagFile& f) {
  Record r;
  if (at + 4 > bytes.size()) f.fail("is cut short");
  const uint32_t header = u32At(bytes, at);
  if (header > bytes.size() - at - 4 || bytes.size() - at - 4 - header < 4) f.fail("is cut short");
  r.header = parseFields(bytes, at + 4, header, f);
  r.size = u32At(bytes, at + 4 + header);
  r.data = at + 8 + header;
  if (r.size > bytes.size() - r.data) f.fail("is cut short");
  r.next = r.data + r.size;
  return r;
}

template <typename T>
T field(const Fields& h, const char* name, const BagFile& f) {
  const auto it = h.find(name);
  if (it == h.end() || it->second.size() != sizeof(T))
    f.fail(std::string("has a record without its ") + name);
  T v;
  std::memcpy(&v, it->second.data(), sizeof(T));
  return v;
}
ros::Time timeField(const Fields& h, const char* name, const BagFile& f) {
  const uint64_t v = field<uint64_t>(h, name, f);  // sec, then nsec
  return ros::Time(static_cast<uint32_t>(v), static_cast<uint32_t>(v >> 32));
}
void expectOp(const Fields& h, uint8_t op, const char* what, const BagFile& f) {
  if (field<uint8_t>(h, "op", f) != op) f.fail(std::string("has no ") + what + " where its index says");
}

struct Chunk {
  uint64_t pos = 0, end = 0;  // its chunk record and index records: [pos, end)
  ros::Time start, stop;
  std::vector<std::pair<uint32_t, uint32_t>> counts;
};
struct Layout {
  std::vector<BagWriter::ConnectionRecord> connections;  // by id
  std::vector<Chunk> chunks;                             // in file order
};

/// The connections and chunks of a bag of format 2.0, from its index section.
Layout readLayout(BagFile& f) {
  constexpr std::size_t kStart = sizeof bag_format::kVersion - 1;  // the file header record's
  if (f.read(0, kStart) != bag_format::kVersion) f.fail("is not a bag of format 2.0");
  const std::string len = f.read(kStart, 4);
  const Fields header = parseFields(f.read(kStart + 4, u32At(len, 0)), 0, u32At(len, 0), f);
  expectOp(header, bag_format::kOpFileHeader, "file header", f);
  const uint64_t index_pos = field<uint64_t>(header, "index_pos", f);
  const uint32_t n_connections = field<uint32_t>(header, "conn_count", f),
                 n_chunks = field<uint32_t>(header, "chunk_count", f);
  if (index_pos < 17 || index_pos > f.size()) f.fail("has no index (it was not closed)");
  const std::string index = f.read(index_pos, f.size() - index_pos);
  Layout layout;
  layout.connections.resize(n_connections);
  std::size_t at = 0;
  for (uint32_t k = 0; k < n_connections; ++k) {
    const Record r = parseRecord(index, at, f);
    expectOp(r.header, bag_format::kOpConnection, "connection record", f);
    const uint32_t id = field<uint32_t>(r.header, "conn", f);
    if (id >= n_connections) f.fail("has a connection id past its count");
    const Fields data = parseFields(index, r.data, r.size, f);
    BagWriter::ConnectionRecord& c = layout.connections[id];
    c.id = id;
    c.topic = r.header.count("topic") ? r.header.at("topic") : "";
    c.type = data.count("type") ? data.at("type") : "";
    c.md5sum = data.count("md5sum") ? data.at("md5sum") : "";
    c.definition = data.count("message_definition") ? data.at("message_definition") : "";
    c.record = index.substr(at, r.next - at);
    at = r.next;
  }
  for (uint32_t k = 0; k < n_chunks; ++k) {
    const Record r = parseRecord(index, at, f);
    expectOp(r.header, bag_format::kOpChunkInfo, "chunk info record", f);
    Chunk c;
    c.pos = field<uint64_t>(r.header, "chunk_pos", f);
    c.start = timeField(r.header, "start_time", f);
    c.stop = timeField(r.header, "end_time", f);
    const uint32_t count = field<uint32_t>(r.header, "count", f);
    if (r.size != 8ull * count) f.fail("has a malformed chunk info record");
    for (uint32_t i = 0; i < count; ++i)
      c.counts.emplace_back(u32At(index, r.data + 8 * i), u32At(index, r.data + 8 * i + 4));
    layout.chunks.push_back(std::move(c));
    at = r.next;
  }
  std::sort(layout.chunks.begin(), layout.chunks.end(),
            [](const Chunk& a, const Chunk& b) { return a.pos < b.pos; });
  for (std::size_t k = 0; k < layout.chunks.size(); ++k) {
    layout.chunks[k].end = k + 1 < layout.chunks.size() ? layout.chunks[k + 1].pos : index_pos;
    if (layout.chunks[k].end <= layout.chunks[k].pos) f.fail("has overlapping chunks");
  }
  return layout;
}

std::string decompress(const std::string& compression, const std::string& bytes, std::size_t at,
                       std::size_t n, uint32_t size, const BagFile& f) {
  if (compression == "none") return bytes.substr(at, n);
  std::string plain(size, '\0');
  unsigned int out = size;
  char* in = const_cast<char*>(bytes.data() + at);
  const bool ok =
      compression == "bz2"
          ? BZ2_bzBuffToBuffDecompress(plain.data(), &out, in, static_cast<unsigned int>(n), 0, 0) == BZ_OK
      : compression == "lz4"
          ? roslz4_buffToBuffDecompress(in, static_cast<unsigned int>(n), plain.data(), &out) == ROSLZ4_OK
          : (f.fail("has a chunk compressed with '" + compression + "'"), false);
  if (!ok || out != size) f.fail("has a chunk that does not decompress (" + compression + ")");
  return plain;
}

/// Writes a chunk's messages into `out` one by one, in the order the chunk holds them.
void decodeChunk(const std::string& bytes, const Record& chunk, const Layout& layout, BagWriter& out,
                 const Substitute& substitute, const BagFile& f) {
  const std::string plain =
      decompress(chunk.header.count("compression") ? chunk.header.at("compression") : "", bytes, chunk.data,
                 chunk.size, field<uint32_t>(chunk.header, "size", f), f);
  for (std::size_t at = 0; at < plain.size();) {
    const Record r = parseRecord(plain, at, f);
    at = r.next;
    if (field<uint8_t>(r.header, "op", f) != bag_format::kOpMessage)
      continue;  // a connection record: `out` writes its own
    const uint32_t id = field<uint32_t>(r.header, "conn", f);
    if (id >= layout.connections.size()) f.fail("has a message on an unknown connection");
    const BagWriter::ConnectionRecord& c = layout.connections[id];
    const ros::Time time = timeField(r.header, "time", f);
    if (!substitute.write || !substitute.write(c.topic, time, out))
      out.writeSerialized(c, time, plain.data() + r.data, static_cast<uint32_t>(r.size));
  }
}
}  // namespace

std::vector<BagWriter::ConnectionRecord> bagConnections(const std::string& file) {
  BagFile f(file);
  return readLayout(f).connections;
}

AppendCounts appendBags(const std::vector<std::string>& files, BagWriter& out, const Substitute& substitute,
                        const std::atomic<bool>* stop) {
  AppendCounts counts;
  for (const std::string& file : files) {
    BagFile f(file);
    const Layout layout = readLayout(f);
    for (const Chunk& c : layout.chunks) {
      if (stop && *stop) throw JoinInterrupted();
      const std::string bytes = f.read(c.pos, c.end - c.pos);
      const Record chunk = parseRecord(bytes, 0, f);
      expectOp(chunk.header, bag_format::kOpChunk, "chunk record", f);
      bool copy =
          chunk.header.count("compression") && chunk.header.at("compression") == out.compressionName();
      for (const auto& [id, n] : c.counts)
        copy = copy && id < layout.connections.size() &&
               std::find(substitute.topics.begin(), substitute.topics.end(), layout.connections[id].topic) ==
                   substitute.topics.end();
      if (copy && out.copyChunk(bytes, c.start, c.stop, c.counts, layout.connections)) {
        ++counts.copied;
      } else {
        decodeChunk(bytes, chunk, layout, out, substitute, f);
        ++counts.decoded;
      }
    }
  }
  return counts;
}

}  // namespace swarm_forage
