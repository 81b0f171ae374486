// What a record's compression costs: the chunks of one uncompressed record compressed by each encoder a
// record can be written with (bzip2Compress, libbz2 itself, roslz4), alternating on the same bytes so that
// a change of the host's speed reaches all of them (docs/performance-records.md, Choosing the compression).
//   bench_compression RECORD.bag [repeats]   (a record of any compression: its chunks are decoded first)
#include <bzlib.h>
#include <roslz4/lz4s.h>

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "swarm_forage/record/bag_records.hpp"
#include "swarm_forage/record/bzip2_encoder.hpp"

namespace {
using namespace swarm_forage;

/// The uncompressed chunks of the bag at `path`.
std::vector<std::string> chunksOf(const std::string& path) {
  bag_records::BagFile f(path, path + ": ");
  const bag_records::Layout layout = bag_records::readLayout(f);
  std::vector<std::string> chunks;
  for (const bag_records::Chunk& c : layout.chunks) {
    const std::string bytes = f.read(c.pos, c.end - c.pos);
    const bag_records::Record r = bag_records::parseRecord(bytes, 0, f);
    const std::string compression = r.header.count("compression") ? r.header.at("compression") : "none";
    const uint32_t size = bag_records::field<uint32_t>(r.header, "size", f);
    chunks.push_back(bag_records::decompress(compression, bytes, r.data, r.size, size, f));
  }
  return chunks;
}

void libbz2(const std::string& in, std::string& out) {
  unsigned int n = static_cast<unsigned int>(in.size() + in.size() / 100 + 600);
  out.resize(n);
  if (BZ2_bzBuffToBuffCompress(out.data(), &n, const_cast<char*>(in.data()),
                               static_cast<unsigned int>(in.size()), 9, 0, 30) != BZ_OK)
    throw std::runtime_error("libbz2 failed");
  out.resize(n);
}

void lz4(const std::string& in, std::string& out) {
  unsigned int n = static_cast<unsigned int>(in.size() + in.size() / 64 + 4096);
  out.resize(n);
  if (roslz4_buffToBuffCompress(const_cast<char*>(in.data()), static_cast<unsigned int>(in.size()),
                                out.data(), &n, 6) != ROSLZ4_OK)
    throw std::runtime_error("lz4 failed");
  out.resize(n);
}

/// CPU seconds of this process (the encoders run on one thread).
double cpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

void unbz2(const std::string& in, std::string& out) {
  unsigned int n = static_cast<unsigned int>(out.size());
  if (BZ2_bzBuffToBuffDecompress(out.data(), &n, const_cast<char*>(in.data()),
                                 static_cast<unsigned int>(in.size()), 0, 0) != BZ_OK)
    throw std::runtime_error("libbz2 could not decode");
}

void unlz4(const std::string& in, std::string& out) {
  unsigned int n = static_cast<unsigned int>(out.size());
  if (roslz4_buffToBuffDecompress(const_cast<char*>(in.data()), static_cast<unsigned int>(in.size()),
                                  out.data(), &n) != ROSLZ4_OK)
    throw std::runtime_error("roslz4 could not decode");
}

using Coder = std::function<void(const std::string&, std::string&)>;
struct Encoder {
  const char* name;
  Coder encode, decode;  // decode: what a reader of the record pays (run_tables, read_run)
  double seconds = 0, decode_seconds = 0;
  std::size_t bytes = 0;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_compression RECORD.bag [repeats]\n");
    return 2;
  }
  try {
    const std::vector<std::string> chunks = chunksOf(argv[1]);
    const int repeats = argc > 2 ? std::atoi(argv[2]) : 3;
    const Coder ours = [](const std::string& in, std::string& out) {
      bzip2Compress(in.data(), in.size(), out);
    };
    std::vector<Encoder> encoders{
        {"bz2 (bzip2Compress)", ours, unbz2}, {"bz2 (libbz2)", libbz2, unbz2}, {"lz4 (roslz4)", lz4, unlz4}};
    std::size_t plain = 0, differ = 0;
    std::string out, reference, back;
    for (const std::string& chunk : chunks) plain += chunk.size();
    for (int r = 0; r < repeats; ++r)
      for (const std::string& chunk : chunks)
        for (std::size_t e = 0; e < encoders.size(); ++e) {
          const double t0 = cpuSeconds();
          encoders[e].encode(chunk, out);
          encoders[e].seconds += cpuSeconds() - t0;
          if (r == 0) encoders[e].bytes += out.size();
          if (e == 0) reference = out;
          if (e == 1 && out != reference) ++differ;
          back.assign(chunk.size(), '\0');
          const double t1 = cpuSeconds();
          encoders[e].decode(out, back);
          encoders[e].decode_seconds += cpuSeconds() - t1;
          if (back != chunk)
            throw std::runtime_error(std::string(encoders[e].name) + " does not decode to its input");
        }
    std::printf("%s: %zu chunks, %zu bytes uncompressed, %d repeats\n", argv[1], chunks.size(), plain,
                repeats);
    for (const Encoder& e : encoders)
      std::printf("%-22s %10zu bytes  encode %8.4f s CPU (%6.2f ns a byte)  decode %8.4f s CPU\n", e.name,
                  e.bytes, e.seconds / repeats, 1e9 * e.seconds / repeats / static_cast<double>(plain),
                  e.decode_seconds / repeats);
    std::printf("bz2 chunks that differ between bzip2Compress and libbz2: %zu\n", differ);
    return differ == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_compression: %s\n", e.what());
    return 1;
  }
}
