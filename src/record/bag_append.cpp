#include "swarm_forage/record/bag_append.hpp"

#include <algorithm>

#include "swarm_forage/record/bag_records.hpp"

namespace swarm_forage {

namespace {
using namespace bag_records;

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
  BagFile f(file, "the bag " + file + " ");
  return readLayout(f).connections;
}

AppendCounts appendBags(const std::vector<std::string>& files, BagWriter& out, const Substitute& substitute,
                        const std::atomic<bool>* stop) {
  AppendCounts counts;
  for (const std::string& file : files) {
    BagFile f(file, "the bag " + file + " ");
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
