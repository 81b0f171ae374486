#include "swarm_forage/core/run/condition_series.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

namespace {
/// The line's fields, split at commas, spaces and tabs.
std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : line) {
    if (c == ',' || c == ' ' || c == '\t' || c == '\r') {
      if (!cur.empty() || c == ',') out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

/// The documented header line, t,V (either case).
bool isHeader(const std::vector<std::string>& f) {
  return f.size() == 2 && (f[0] == "t" || f[0] == "T") && (f[1] == "V" || f[1] == "v");
}

/// The whole of `s` as a number (strtod: "nan" and "inf" parse, and are refused as not finite later).
bool number(const std::string& s, double& out) {
  if (s.empty()) return false;
  errno = 0;
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && errno != ERANGE;
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}
}  // namespace

std::string contentDigest(const std::string& bytes) {
  uint64_t h = 14695981039346656037ull;
  for (const unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

double ConditionSeries::at(double time) const {
  if (t.empty()) return 0.0;
  if (!(time > t.front())) return v.front();
  if (time >= t.back()) return v.back();
  const std::size_t k = std::upper_bound(t.begin(), t.end(), time) - t.begin();  // t[k-1] <= time < t[k]
  const double u = (time - t[k - 1]) / (t[k] - t[k - 1]);
  return v[k - 1] + u * (v[k] - v[k - 1]);
}

std::shared_ptr<const ConditionSeries> ConditionSeries::read(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw ParameterError("series file '" + path + "' is a directory; valid: a CSV file of rows t [s], V");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw ParameterError("series file '" + path + "' cannot be read (" + std::strerror(errno) +
                         "); valid: a CSV file of rows t [s], V");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return parse(bytes.str(), path);
}

std::shared_ptr<const ConditionSeries> ConditionSeries::parse(const std::string& bytes,
                                                              const std::string& name) {
  auto s = std::make_shared<ConditionSeries>();
  s->digest = contentDigest(bytes);
  // A spreadsheet's UTF-8 byte order mark is not part of the first field.
  std::istringstream in(bytes.compare(0, 3, "\xEF\xBB\xBF") == 0 ? bytes.substr(3) : bytes);
  bool first = true;
  int n = 0;
  for (std::string line; std::getline(in, line);) {
    ++n;
    const std::string at = "series file '" + name + "' line " + std::to_string(n) + ": ";
    const std::vector<std::string> f = fields(line);
    if (f.empty() || f[0].rfind('#', 0) == 0) continue;
    double t = 0, v = 0;
    const bool numbers = f.size() == 2 && number(f[0], t) && number(f[1], v);
    // Only the documented header is one: a mistyped first row ("1O,0.9") is an error, never dropped.
    if (first && isHeader(f)) {
      first = false;
      continue;
    }
    if (!numbers) {
      const std::string valid = " (valid: a row \"t,V\" of two numbers, t in s" +
                                std::string(first ? ", or the header t,V" : "") + ")";
      if (f.size() != 2) throw ParameterError(at + "'" + line + "' is not two numbers t, V" + valid);
      const int bad = number(f[0], t) ? 2 : 1;
      throw ParameterError(at + "'" + line + "' is not two numbers t, V: field " + std::to_string(bad) +
                           " '" + f[bad - 1] + "' is not a number" + valid);
    }
    first = false;
    if (!std::isfinite(t) || !std::isfinite(v))
      throw ParameterError(at + "'" + line + "' holds a number that is not finite");
    if (!(v >= -1.0 && v <= 1.0)) throw ParameterError(at + "V " + num(v) + " is not within [-1, 1]");
    if (!s->t.empty() && !(t > s->t.back()))
      throw ParameterError(at + "t " + num(t) + " s does not increase (the row before has t " +
                           num(s->t.back()) + " s); valid: times strictly increasing");
    s->t.push_back(t);
    s->v.push_back(v);
  }
  if (s->t.empty())
    throw ParameterError("series file '" + name + "' line " + std::to_string(n + 1) +
                         ": the file ends without a row; valid: at least one row t, V");
  return s;
}

}  // namespace swarm_forage
