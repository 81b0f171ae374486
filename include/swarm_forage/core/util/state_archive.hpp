#pragma once
// A run's persistent state as bytes (checkpoints, docs/runs-and-bags.md): one archive type serves saving and
// loading, so each class lists its persistent fields once, in one persist(StateArchive&) function, and the
// two directions cannot drift apart. Derived caches (grids, slots, bands, scratch) are never archived.
#include <cstdint>
#include <cstring>
#include <deque>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace swarm_forage {

/// A checkpoint that cannot be read: truncated, corrupted, of another format, or of another state layout.
struct CheckpointError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class StateArchive {
 public:
  /// An empty archive to save into.
  StateArchive() = default;
  /// An archive to load from `bytes`.
  explicit StateArchive(std::string bytes) : bytes_(std::move(bytes)), loading_(true) {}

  bool loading() const { return loading_; }
  const std::string& bytes() const { return bytes_; }
  /// Loading: the bytes not read yet.
  std::size_t remaining() const { return bytes_.size() - at_; }

  /// A number, a bool or an enum, as its bytes; a struct by persistValue(a, v), an overload next to the
  /// persist() that uses it, which lists its fields (never padding bytes: equal states, equal files).
  template <typename T>
  void io(T& v) {
    if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>)
      raw(&v, sizeof v);
    else
      persistValue(*this, v);
  }
  /// Several values in order.
  template <typename T, typename... More>
  void io(T& first, More&... more) {
    io(first);
    (io(more), ...);
  }
  void io(std::string& s) {
    uint64_t n = s.size();
    io(n);
    if (!loading_) {
      bytes_ += s;
      return;
    }
    need(n);
    s.assign(bytes_, at_, n);
    at_ += n;
  }
  template <typename T>
  void io(std::vector<T>& v) {
    uint64_t n = v.size();
    io(n);
    if constexpr ((std::is_arithmetic_v<T> || std::is_enum_v<T>)&&!std::is_same_v<T, bool>) {
      if (loading_) {
        need(n * sizeof(T));
        v.resize(n);
      }
      raw(v.data(), n * sizeof(T));
    } else {
      if (loading_) {
        need(n);  // every element takes a byte at least: a corrupt count cannot allocate the world
        v.resize(n);
      }
      for (T& e : v) io(e);
    }
  }
  template <typename T>
  void io(std::deque<T>& d) {
    std::vector<T> v(d.begin(), d.end());
    io(v);
    if (loading_) d.assign(v.begin(), v.end());
  }

  /// A named mark: loading checks it is there, so a layout mismatch says where it is.
  void section(const char* name) {
    std::string s = name;
    if (!loading_) return io(s);
    std::string found;
    io(found);
    if (found != s)
      throw CheckpointError("expected section '" + s + "', found '" + found.substr(0, 40) + "'");
  }

 private:
  void need(uint64_t n) const {
    if (loading_ && n > remaining()) throw CheckpointError("truncated");
  }
  void raw(void* p, std::size_t n) {
    if (!loading_) {
      bytes_.append(static_cast<const char*>(p), n);
      return;
    }
    need(n);
    std::memcpy(p, bytes_.data() + at_, n);
    at_ += n;
  }

  std::string bytes_;
  bool loading_ = false;
  std::size_t at_ = 0;
};

}  // namespace swarm_forage
