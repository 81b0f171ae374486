#include "swarm_forage/core/run/checkpoint.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace swarm_forage {

uint64_t fnv1a64(const char* p, std::size_t n, uint64_t h) {
  for (std::size_t i = 0; i < n; ++i) h = (h ^ static_cast<unsigned char>(p[i])) * 1099511628211ULL;
  return h;
}

uint64_t fileChecksum(const std::string& path, uint64_t& size) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CheckpointError("cannot read " + path);
  std::string block(1 << 20, '\0');
  uint64_t h = fnv1a64(nullptr, 0);
  size = 0;
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    h = fnv1a64(block.data(), n, h);
    size += n;
  }
  if (in.bad()) throw CheckpointError("cannot read " + path);
  return h;
}

void syncFile(const std::string& path) {
  for (const std::string& p : {path, std::filesystem::path(path).parent_path().string()}) {
    const int fd = ::open(p.empty() ? "." : p.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0 || ::fsync(fd) != 0) {
      const std::string why = std::strerror(errno);
      if (fd >= 0) ::close(fd);
      throw std::runtime_error("cannot sync " + (p.empty() ? std::string(".") : p) + ": " + why);
    }
    ::close(fd);
  }
}

namespace {
constexpr char kMagic[8] = {'S', 'F', 'C', 'K', 'P', 'T', '\r', '\n'};  // \r\n: a text-mode copy shows

uint64_t checksum(const std::string& bytes) { return fnv1a64(bytes.data(), bytes.size()); }

template <typename T>
void append(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

void writeAll(int fd, const char* p, std::size_t n, const std::string& path) {
  static int writes = 0;  // the test hook's count of checkpoint files written by this process
  const char* die = ++writes >= 2 ? std::getenv("SWARM_FORAGE_CHECKPOINT_DIE_AFTER") : nullptr;
  if (die && std::strtoull(die, nullptr, 10) < n) {
    const std::size_t part = std::strtoull(die, nullptr, 10);
    if (::write(fd, p, part) == static_cast<ssize_t>(part)) ::fsync(fd);
    std::raise(SIGKILL);  // a kill in the middle of the write, at a byte the test chose
  }
  while (n > 0) {
    const ssize_t k = ::write(fd, p, n);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) throw std::runtime_error("cannot write the checkpoint " + path + ": " + std::strerror(errno));
    p += k;
    n -= static_cast<std::size_t>(k);
  }
}
}  // namespace

void writeCheckpointFile(const std::string& path, const std::string& payload) {
  std::string head(kMagic, sizeof kMagic);
  append(head, kCheckpointFormat);
  append(head, static_cast<uint64_t>(payload.size()));
  std::string tail;
  append(tail, checksum(payload));
  const std::string tmp = path + ".tmp";
  const auto dir = std::filesystem::path(path).parent_path();
  if (!dir.empty()) std::filesystem::create_directories(dir);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("cannot write the checkpoint " + tmp + ": " + std::strerror(errno));
  try {
    const std::string whole = head + payload + tail;
    writeAll(fd, whole.data(), whole.size(), tmp);
    if (::fsync(fd) != 0)
      throw std::runtime_error("cannot sync the checkpoint " + tmp + ": " + std::strerror(errno));
  } catch (...) {
    ::close(fd);
    ::unlink(tmp.c_str());
    throw;
  }
  ::close(fd);
  if (::rename(tmp.c_str(), path.c_str()) != 0)
    throw std::runtime_error("cannot name the checkpoint " + path + ": " + std::strerror(errno));
  // The rename itself must reach the disk before the run goes on as if the checkpoint existed.
  const int dfd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

std::string readCheckpointFile(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw CheckpointError(path + " is a directory, not a checkpoint");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CheckpointError("cannot read " + path);
  const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t head = sizeof kMagic + sizeof(uint32_t) + sizeof(uint64_t), tail = sizeof(uint64_t);
  if (all.size() < sizeof kMagic || all.compare(0, sizeof kMagic, kMagic, sizeof kMagic) != 0)
    throw CheckpointError(path + " is not a swarm_forage checkpoint");
  if (all.size() < head + tail) throw CheckpointError(path + " is truncated");
  uint32_t format = 0;
  uint64_t length = 0, sum = 0;
  std::memcpy(&format, all.data() + sizeof kMagic, sizeof format);
  std::memcpy(&length, all.data() + sizeof kMagic + sizeof format, sizeof length);
  if (format != kCheckpointFormat)
    throw CheckpointError(path + " has checkpoint format " + std::to_string(format) + "; this build reads " +
                          std::to_string(kCheckpointFormat));
  if (all.size() - head - tail != length)
    throw CheckpointError(
        path + (all.size() - head - tail < length ? " is truncated" : " has bytes past its end") + " (" +
        std::to_string(all.size()) + " bytes, the header says " + std::to_string(length + head + tail) + ")");
  std::string payload = all.substr(head, length);
  std::memcpy(&sum, all.data() + head + length, sizeof sum);
  if (sum != checksum(payload)) throw CheckpointError(path + " is corrupted (its checksum does not match)");
  return payload;
}

void persistCondition(StateArchive& a, Condition& c) {
  a.io(c.waveform, c.beta, c.alpha, c.frequency, c.phase, c.offset, c.target, c.series, c.series_digest);
}

void persistSample(StateArchive& a, std::optional<ConditionSample>& s) {
  bool has = s.has_value();
  a.io(has);
  if (!has) return s.reset();
  if (a.loading()) s.emplace();
  a.io(s->tick, s->value);
  persistCondition(a, s->condition);
  a.io(s->seq);
}

}  // namespace swarm_forage
