// The environmental condition's parameters: declared in the parameter table, checked by the core's one rule
// (Condition::forRun).
#include <ros/package.h>

#include <filesystem>

#include "swarm_forage/ros/params/params.hpp"

namespace swarm_forage {

Condition readCondition(const ParamSource& p, uint64_t ticks, double tps) {
  // The core says what each accepts (--help); the values are checked once, by Condition::validate.
  const auto read = [&p](const std::string& name, auto as) {
    const ParamSpec& s = paramSpec(name);
    p.accepts({name, fallbackText(s), validText(s), s.doc});
    return param<decltype(as)>(p, name, fallbackOf<decltype(as)>(s));
  };
  Condition c;
  c.waveform = read("waveform", std::string());
  c.beta = read("beta", 0.0);
  c.alpha = read("alpha", 0.0);  // default -1: half the run
  c.frequency = read("frequency", 0.0);
  c.phase = read("phase", 0.0);
  c.offset = read("offset", 0.0);
  c.target = read("target", std::string());
  c.series = read("series", std::string());
  return conditionForRun(c, ticks, tps);
}

std::string seriesPath(const std::string& series) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (series.empty() || series.find('/') != std::string::npos || fs::exists(series, ec)) return series;
  const fs::path packaged =
      fs::path(ros::package::getPath("swarm_forage")) / "config" / "conditions" / series;
  return fs::exists(packaged, ec) ? packaged.string() : series;
}

Condition conditionForRun(const Condition& requested, uint64_t ticks, double tps) {
  Condition c = requested;
  if (c.waveform == "series") c.series = seriesPath(c.series);
  try {
    return c.forRun(ticks, tps);
  } catch (const ParameterError& e) {
    throw ParameterError("~" + std::string(e.what()));  // the core names the parameter
  }
}

}  // namespace swarm_forage
