#pragma once
// A measured condition (waveform `series`, docs/nodes-and-parameters.md, Environment): V(t) read from a
// CSV file of two columns, t [s] and V, linearly interpolated; before the first time the first V holds,
// after the last time the last V holds. The file is part of a run's identity by the hash of its bytes.
#include <cstdint>
#include <istream>
#include <memory>
#include <string>
#include <vector>

namespace swarm_forage {

struct ConditionSeries {
  std::vector<double> t, v;  // times strictly increase; V in [-1, 1]; at least one row
  std::string digest;        // 16 hex digits: FNV-1a 64 of the file's bytes

  /// V at t seconds: linear between rows, the first V before the first time, the last V after the last.
  double at(double t) const;

  /// Reads the file: one row per line, "t,V" (commas, or spaces/tabs); a first line that is not two
  /// numbers is a header; blank lines and lines starting with '#' are skipped. Throws ParameterError
  /// naming the file and the line: not two numbers, a number not finite, V outside [-1, 1], a time not
  /// above the previous one, no row at all, or the file cannot be read.
  static std::shared_ptr<const ConditionSeries> read(const std::string& path);
  /// As read(), from the file's bytes; `name` is the file named in errors.
  static std::shared_ptr<const ConditionSeries> parse(const std::string& bytes, const std::string& name);
};

/// 16 hex digits of FNV-1a 64 over `bytes` (stable across builds and platforms, like RunKey::identity).
std::string contentDigest(const std::string& bytes);

}  // namespace swarm_forage
