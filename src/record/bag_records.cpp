#include "swarm_forage/record/bag_records.hpp"

#include <bzlib.h>
#include <roslz4/lz4s.h>

#include <algorithm>
#include <set>

namespace swarm_forage {
namespace bag_records {

namespace {
constexpr std::size_t kVersionLength =
    sizeof bag_format::kVersion - 1;  // where the file header record starts

std::string byteText(uint64_t pos) { return "byte " + std::to_string(pos); }

/// A time field's seconds and nanoseconds, as rosbag stores them (sec, then nsec, 32 bits each).
std::pair<uint32_t, uint32_t> secNsec(uint64_t packed) {
  return {static_cast<uint32_t>(packed), static_cast<uint32_t>(packed >> 32)};
}
}  // namespace

BagFile::BagFile(const std::string& path, std::string prefix)
    : path_(path), prefix_(std::move(prefix)), in_(path, std::ios::binary | std::ios::ate) {
  if (!in_) fail("cannot be read");
  size_ = static_cast<uint64_t>(in_.tellg());
}

std::string BagFile::read(uint64_t pos, uint64_t n) {
  if (pos > size_ || n > size_ - pos) fail("is cut short (a record ends past its end)");
  std::string bytes(n, '\0');
  in_.seekg(static_cast<std::streamoff>(pos));
  if (!in_.read(bytes.data(), static_cast<std::streamsize>(n))) fail("cannot be read");
  return bytes;
}

void BagFile::fail(const std::string& why) const {
  throw std::runtime_error(prefix_ + why + (where_.empty() ? "" : " (" + where_ + ")"));
}

uint32_t u32At(const std::string& bytes, std::size_t at) {
  uint32_t v;
  std::memcpy(&v, bytes.data() + at, 4);
  return v;
}

Fields parseFields(const std::string& bytes, std::size_t at, std::size_t n, const BagFile& f) {
  Fields fields;
  const std::size_t end = at + n;
  while (at < end) {
    if (end - at < 4) f.fail("has a malformed record header");
    const uint32_t len = u32At(bytes, at);
    at += 4;
    if (len > end - at) f.fail("has a malformed record header");
    const char* begin = bytes.data() + at;
    const auto* eq = static_cast<const char*>(std::memchr(begin, '=', len));
    if (eq == nullptr) f.fail("has a record header field without '='");
    // rosbag keeps the last of two equal names, a reader of the first would see another record: neither.
    if (!fields.emplace(std::string(begin, eq), std::string(eq + 1, begin + len)).second)
      f.fail("has a record header with the field '" + std::string(begin, eq) + "' twice");
    at += len;
  }
  return fields;
}

Record parseRecord(const std::string& bytes, std::size_t at, const BagFile& f) {
  Record r;
  if (at > bytes.size() || bytes.size() - at < 8) f.fail("is cut short");
  const uint32_t header = u32At(bytes, at);
  if (header > bytes.size() - at - 8) f.fail("is cut short");
  r.header = parseFields(bytes, at + 4, header, f);
  r.size = u32At(bytes, at + 4 + header);
  r.data = at + 8 + header;
  if (r.size > bytes.size() - r.data) f.fail("is cut short");
  r.next = r.data + r.size;
  return r;
}

ros::Time timeField(const Fields& h, const char* name, const BagFile& f) {
  const auto [sec, nsec] = secNsec(field<uint64_t>(h, name, f));
  if (nsec >= 1000000000u) f.fail(std::string("has a ") + name + " with nanoseconds past a second");
  return ros::Time(sec, nsec);
}

void expectOp(const Fields& h, uint8_t op, const char* what, const BagFile& f) {
  if (field<uint8_t>(h, "op", f) != op) f.fail(std::string("has no ") + what + " where its index says");
}

namespace {
// The file header record: where the chunks begin and the index is (into `layout`), and how many connections
// and chunks the index lists.
std::pair<uint32_t, uint32_t> readFileHeader(BagFile& f, Layout& layout) {
  f.at("");
  if (f.size() < kVersionLength || f.read(0, kVersionLength) != bag_format::kVersion)
    f.fail("is not a bag of format 2.0");
  f.at("its file header record");
  const uint32_t header_length = u32At(f.read(kVersionLength, 4), 0);
  if (header_length > f.size() - kVersionLength - 8) f.fail("is cut short");
  const std::string head = f.read(kVersionLength, 8ull + header_length);
  const Fields header = parseFields(head, 4, header_length, f);
  expectOp(header, bag_format::kOpFileHeader, "file header", f);
  if (header.count("encryptor")) f.fail("is encrypted, which no reader here decrypts");
  layout.first_chunk = kVersionLength + 8ull + header_length + u32At(head, 4 + header_length);
  layout.index_pos = field<uint64_t>(header, "index_pos", f);
  const uint32_t n_connections = field<uint32_t>(header, "conn_count", f),
                 n_chunks = field<uint32_t>(header, "chunk_count", f);
  if (layout.first_chunk > f.size()) f.fail("is cut short");
  if (layout.index_pos == 0) f.fail("has no index (it was not closed)");
  if (layout.index_pos < layout.first_chunk || layout.index_pos > f.size())
    f.fail("has its index at " + byteText(layout.index_pos) + ", outside its chunks' end [" +
           std::to_string(layout.first_chunk) + ", " + std::to_string(f.size()) + "]");
  return {n_connections, n_chunks};
}

// The index's connection records, one for each of layout.connections, from its start; returns where they end.
std::size_t readConnections(BagFile& f, const std::string& index, Layout& layout) {
  const auto n_connections = static_cast<uint32_t>(layout.connections.size());
  std::vector<bool> seen(n_connections, false);
  std::size_t at = 0;
  for (uint32_t k = 0; k < n_connections; ++k) {
    f.at("connection record " + std::to_string(k + 1) + " of " + std::to_string(n_connections) + " at " +
         byteText(layout.index_pos + at));
    const Record r = parseRecord(index, at, f);
    expectOp(r.header, bag_format::kOpConnection, "connection record", f);
    const uint32_t id = field<uint32_t>(r.header, "conn", f);
    if (id >= n_connections)
      f.fail("has connection id " + std::to_string(id) + ", past its count " + std::to_string(n_connections));
    if (seen[id]) f.fail("has connection id " + std::to_string(id) + " twice");
    seen[id] = true;
    if (!r.header.count("topic") || r.header.at("topic").empty()) f.fail("has a connection without a topic");
    const Fields data = parseFields(index, r.data, r.size, f);
    BagWriter::ConnectionRecord& c = layout.connections[id];
    c.id = id;
    c.topic = r.header.at("topic");
    c.type = data.count("type") ? data.at("type") : "";
    c.md5sum = data.count("md5sum") ? data.at("md5sum") : "";
    c.definition = data.count("message_definition") ? data.at("message_definition") : "";
    c.record = index.substr(at, r.next - at);
    at = r.next;
  }
  return at;
}

// The index's `n_chunks` chunk info records from `at` into layout.chunks; returns where they end.
std::size_t readChunkInfos(BagFile& f, const std::string& index, std::size_t at, uint32_t n_chunks,
                           Layout& layout) {
  const auto n_connections = static_cast<uint32_t>(layout.connections.size());
  for (uint32_t k = 0; k < n_chunks; ++k) {
    f.at("chunk info record " + std::to_string(k + 1) + " of " + std::to_string(n_chunks) + " at " +
         byteText(layout.index_pos + at));
    const Record r = parseRecord(index, at, f);
    expectOp(r.header, bag_format::kOpChunkInfo, "chunk info record", f);
    if (const uint32_t ver = field<uint32_t>(r.header, "ver", f); ver != 1)
      f.fail("has chunk info version " + std::to_string(ver) + " (valid: 1)");
    Chunk c;
    c.pos = field<uint64_t>(r.header, "chunk_pos", f);
    c.start = timeField(r.header, "start_time", f);
    c.stop = timeField(r.header, "end_time", f);
    if (c.stop < c.start) f.fail("has a chunk that ends before it starts");
    const uint32_t count = field<uint32_t>(r.header, "count", f);
    if (r.size != 8ull * count) f.fail("has a malformed chunk info record");
    for (uint32_t i = 0; i < count; ++i) {
      const uint32_t id = u32At(index, r.data + 8 * i);
      if (id >= n_connections)
        f.fail("has a chunk holding connection " + std::to_string(id) + ", which it lacks");
      for (const auto& [other, n] : c.counts)
        if (other == id) f.fail("has a chunk info listing connection " + std::to_string(id) + " twice");
      c.counts.emplace_back(id, u32At(index, r.data + 8 * i + 4));
    }
    layout.chunks.push_back(std::move(c));
    at = r.next;
  }
  return at;
}

// The chunks in file order, each ending where the next begins: they follow the file header one after another
// up to the index.
void placeChunks(const BagFile& f, Layout& layout) {
  std::sort(layout.chunks.begin(), layout.chunks.end(),
            [](const Chunk& a, const Chunk& b) { return a.pos < b.pos; });
  uint64_t expected = layout.first_chunk;
  for (std::size_t k = 0; k < layout.chunks.size(); ++k) {
    Chunk& c = layout.chunks[k];
    if (c.pos != expected)
      f.fail("has a chunk at " + byteText(c.pos) + " where " + byteText(expected) +
             (k == 0 ? " begins its first" : " follows the one before"));
    c.end = k + 1 < layout.chunks.size() ? layout.chunks[k + 1].pos : layout.index_pos;
    if (c.end <= c.pos) f.fail("has overlapping chunks at " + byteText(c.pos));
    expected = c.end;
  }
  if (layout.chunks.empty() && layout.index_pos != layout.first_chunk)
    f.fail("has " + std::to_string(layout.index_pos - layout.first_chunk) +
           " bytes but no chunk before its index");
}
}  // namespace

Layout readLayout(BagFile& f) {
  Layout layout;
  const auto [n_connections, n_chunks] = readFileHeader(f, layout);
  const std::string index = f.read(layout.index_pos, f.size() - layout.index_pos);
  // A record takes at least 8 bytes: counts past that are no bag's (and must not size anything).
  if (n_connections > index.size() / 8 || n_chunks > index.size() / 8 - n_connections)
    f.fail("counts " + std::to_string(n_connections) + " connections and " + std::to_string(n_chunks) +
           " chunks, more than its index of " + std::to_string(index.size()) + " bytes holds");
  layout.connections.resize(n_connections);
  std::size_t at = readConnections(f, index, layout);
  at = readChunkInfos(f, index, at, n_chunks, layout);
  f.at("");
  if (at != index.size())
    f.fail("has " + std::to_string(index.size() - at) + " bytes after its index (from " +
           byteText(layout.index_pos + at) + ")");
  placeChunks(f, layout);
  return layout;
}

std::string decompress(const std::string& compression, const std::string& bytes, std::size_t at,
                       std::size_t n, uint32_t size, const BagFile& f) {
  if (compression == "none") {
    if (n != size) f.fail("has an uncompressed chunk whose size is not its length");
    return bytes.substr(at, n);
  }
  if (compression != "bz2" && compression != "lz4")
    f.fail("has a chunk compressed with '" + compression + "' (valid: none, bz2, lz4)");
  // A flipped size must not allocate gigabytes: decompress first into what the data can fill (lz4 expands
  // at most 255 times; a bz2 chunk rarely 256 times), and into `size` only when bz2 data fills that.
  const std::size_t cap = std::min<std::size_t>(size, 256 * n + (1u << 20));
  if (compression == "lz4" && cap < size) f.fail("has a chunk whose size is more than its lz4 data can hold");
  char* in = const_cast<char*>(bytes.data() + at);
  std::string plain;
  unsigned int out = 0;
  int rc = 0;
  for (const std::size_t room : {cap, std::size_t{size}}) {
    plain.assign(room, '\0');
    out = static_cast<unsigned int>(room);
    rc = compression == "bz2"
             ? BZ2_bzBuffToBuffDecompress(plain.data(), &out, in, static_cast<unsigned int>(n), 0, 0)
             : roslz4_buffToBuffDecompress(in, static_cast<unsigned int>(n), plain.data(), &out);
    if (compression != "bz2" || rc != BZ_OUTBUFF_FULL || room == size) break;
  }
  if (rc != (compression == "bz2" ? BZ_OK : ROSLZ4_OK) || out != size)
    f.fail("has a chunk that does not decompress (" + compression + ")");
  return plain;
}

}  // namespace bag_records

namespace {
using namespace bag_records;

/// A message record in a decompressed chunk: its connection and its time field's bytes.
struct Message {
  uint32_t connection = 0;
  uint64_t time = 0;
};

/// The message records of a decompressed chunk by offset; every record whole and a message or connection.
std::map<uint32_t, Message> chunkMessages(const std::string& plain, std::size_t connections,
                                          const BagFile& f) {
  std::map<uint32_t, Message> out;
  for (std::size_t at = 0; at < plain.size();) {
    const Record r = parseRecord(plain, at, f);
    const uint8_t op = field<uint8_t>(r.header, "op", f);
    if (op == bag_format::kOpMessage) {
      Message m;
      m.connection = field<uint32_t>(r.header, "conn", f);
      m.time = field<uint64_t>(r.header, "time", f);
      if (m.connection >= connections)
        f.fail("has a message at offset " + std::to_string(at) + " of connection " +
               std::to_string(m.connection) + ", which it lacks");
      out.emplace(static_cast<uint32_t>(at), m);
    } else if (op == bag_format::kOpConnection) {
      field<uint32_t>(r.header, "conn", f);
      parseFields(plain, r.data, r.size, f);
    } else {
      f.fail("has a record of op " + std::to_string(op) + " at offset " + std::to_string(at) +
             " (valid in a chunk: messages and connections)");
    }
    at = r.next;
  }
  return out;
}
}  // namespace

Layout checkBag(const std::string& path) {
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("not a readable bag: it cannot be opened");
    char magic[kVersionLength];
    if (!in.read(magic, sizeof magic) || std::string(magic, sizeof magic) != bag_format::kVersion)
      throw std::runtime_error("not a readable bag: it is not a bag of format 2.0 (no '#ROSBAG V2.0' line)");
  }
  BagFile f(path, "not a whole bag: it ");
  const Layout layout = readLayout(f);
  for (std::size_t k = 0; k < layout.chunks.size(); ++k) {
    const Chunk& c = layout.chunks[k];
    const std::string chunk_name = "chunk " + std::to_string(k + 1) + " of " +
                                   std::to_string(layout.chunks.size()) + " at " + byteText(c.pos);
    f.at(chunk_name);
    const std::string bytes = f.read(c.pos, c.end - c.pos);
    const Record chunk = parseRecord(bytes, 0, f);
    expectOp(chunk.header, bag_format::kOpChunk, "chunk record", f);
    if (!chunk.header.count("compression")) f.fail("has a chunk without its compression");
    const uint32_t size = field<uint32_t>(chunk.header, "size", f);
    // rosbag reads as many index records after the chunk as its chunk info lists connections.
    std::map<uint32_t, std::vector<std::pair<uint64_t, uint32_t>>> entries;  // connection: (time, offset)
    std::size_t at = chunk.next;
    for (std::size_t i = 0; i < c.counts.size(); ++i) {
      f.at("index record " + std::to_string(i + 1) + " of " + std::to_string(c.counts.size()) + " after " +
           chunk_name + ", at " + byteText(c.pos + at));
      const Record r = parseRecord(bytes, at, f);
      expectOp(r.header, bag_format::kOpIndex, "index record", f);
      if (const uint32_t ver = field<uint32_t>(r.header, "ver", f); ver != 1)
        f.fail("has index version " + std::to_string(ver) + " (valid: 1)");
      const uint32_t id = field<uint32_t>(r.header, "conn", f), count = field<uint32_t>(r.header, "count", f);
      const auto listed =
          std::find_if(c.counts.begin(), c.counts.end(),
                       [id](const std::pair<uint32_t, uint32_t>& n) { return n.first == id; });
      if (listed == c.counts.end())
        f.fail("has an index of connection " + std::to_string(id) + ", which its chunk info does not list");
      if (listed->second != count)
        f.fail("has an index of " + std::to_string(count) + " messages of connection " + std::to_string(id) +
               " where its chunk info says " + std::to_string(listed->second));
      if (entries.count(id)) f.fail("has two indexes of connection " + std::to_string(id));
      if (r.size != 12ull * count) f.fail("has a malformed index record");
      auto& list = entries[id];
      for (uint32_t e = 0; e < count; ++e) {
        uint64_t time;
        std::memcpy(&time, bytes.data() + r.data + 12 * e, 8);
        list.emplace_back(time, u32At(bytes, r.data + 12 * e + 8));
      }
      at = r.next;
    }
    f.at(chunk_name);
    if (at != bytes.size())
      f.fail("has " + std::to_string(bytes.size() - at) +
             " bytes between its index records and the next chunk");
    const std::string plain =
        decompress(chunk.header.at("compression"), bytes, chunk.data, chunk.size, size, f);
    const std::map<uint32_t, Message> messages = chunkMessages(plain, layout.connections.size(), f);
    // Every index entry at a message of its connection and time, within the chunk's span; every message
    // indexed (rosbag reads only what the index lists).
    std::map<uint32_t, uint32_t> per_connection;
    for (const auto& [offset, m] : messages) ++per_connection[m.connection];
    for (const auto& [id, list] : entries) {
      if (per_connection[id] != list.size())
        f.fail("holds " + std::to_string(per_connection[id]) + " messages of connection " +
               std::to_string(id) + " where its index lists " + std::to_string(list.size()));
      for (const auto& [time, offset] : list) {
        const auto m = messages.find(offset);
        if (m == messages.end() || m->second.connection != id || m->second.time != time)
          f.fail("has an index entry of connection " + std::to_string(id) + " at offset " +
                 std::to_string(offset) + ", which is not a message of that connection and time");
        const auto [sec, nsec] = secNsec(time);
        if (nsec >= 1000000000u || ros::Time(sec, nsec) < c.start || c.stop < ros::Time(sec, nsec))
          f.fail("has a message at offset " + std::to_string(offset) + " outside its chunk's time span");
      }
    }
    for (const auto& [id, n] : per_connection)
      if (!entries.count(id))
        f.fail("holds " + std::to_string(n) + " messages of connection " + std::to_string(id) +
               " that no index lists");
  }
  return layout;
}

}  // namespace swarm_forage
