// Reading a parameter as the table declares it (param_table.hpp): its default, range or list come from its
// row, so that they are written once.
#include <cstdlib>
#include <stdexcept>
#include <type_traits>

#include "swarm_forage/ros/params/params.hpp"

namespace swarm_forage {

template <typename T>
T fallbackOf(const ParamSpec& s) {
  const std::string text = s.fallback;
  if constexpr (std::is_same_v<T, bool>)
    return text == "true";
  else if constexpr (std::is_same_v<T, int>)
    return std::stoi(text);
  else if constexpr (std::is_same_v<T, double>)
    return std::strtod(text.c_str(), nullptr);
  else
    return text;
}
template bool fallbackOf<bool>(const ParamSpec&);
template int fallbackOf<int>(const ParamSpec&);
template double fallbackOf<double>(const ParamSpec&);
template std::string fallbackOf<std::string>(const ParamSpec&);

namespace {
void expect(const ParamSpec& s, bool ok, const char* as) {
  if (!ok) throw std::logic_error(std::string("parameter ") + s.name + " is not declared as " + as);
}
}  // namespace

template <typename T>
T readParam(const ParamSource& p, const std::string& name, unsigned reader) {
  const ParamSpec& s = paramSpec(name, reader);
  p.accepts({name, fallbackText(s), validText(s), s.doc});  // the first to tell is what --help shows
  const T fallback = fallbackOf<T>(s);
  if constexpr (std::is_same_v<T, bool>) {
    expect(s, s.type == ParamType::kBool, "true or false");
    return param<bool>(p, name, fallback);
  } else if constexpr (std::is_same_v<T, int>) {
    expect(s, s.type == ParamType::kInt, "a whole number");
    return paramInRange(p, name, fallback, static_cast<int>(s.lo), static_cast<int>(s.hi));
  } else if constexpr (std::is_same_v<T, double>) {
    expect(s, s.type == ParamType::kNumber, "a number");
    return paramInRange(p, name, fallback, s.lo, s.hi);
  } else {
    static_assert(std::is_same_v<T, std::string>);
    if (s.type == ParamType::kChoice) return paramOneOf(p, name, fallback, s.choices());
    expect(s, s.type == ParamType::kText, "text");
    return param<std::string>(p, name, fallback);
  }
}
template bool readParam<bool>(const ParamSource&, const std::string&, unsigned);
template int readParam<int>(const ParamSource&, const std::string&, unsigned);
template double readParam<double>(const ParamSource&, const std::string&, unsigned);
template std::string readParam<std::string>(const ParamSource&, const std::string&, unsigned);

std::vector<ParamUsage> tableUsage(ParamReader reader) {
  std::vector<ParamUsage> rows;
  for (const ParamSpec& s : paramTable(reader))
    rows.push_back({s.name, fallbackText(s), validText(s), s.doc});
  return rows;
}

}  // namespace swarm_forage
