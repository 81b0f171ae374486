#include "swarm_forage/ros/messages/condition_ros.hpp"

#include <istream>
#include <ostream>
#include <sstream>

#include "swarm_forage/ros/params/known_params.hpp"
#include "swarm_forage/ros/params/params.hpp"

namespace swarm_forage {

int checkConditions(const std::vector<std::string>& run_words, std::istream& in, std::ostream& out) {
  std::vector<std::string> valid = conditionParams();
  valid.insert(valid.end(), {"ticks", "ticks_per_second"});
  int status = 0;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> words = run_words;
    std::istringstream fields(line);
    for (std::string w; std::getline(fields, w, '\t');)
      if (!w.empty()) words.push_back(w);
    try {
      const WordParams p(words);
      for (const std::string& name : p.unknown(valid))
        throw ParameterError(name + " is not a condition parameter; valid: " + joinNames(conditionParams()));
      // As run_experiment reads them (HeadlessRun, readWorldConfig).
      const int ticks = readParam<int>(p, "ticks");
      const double tps = readParam<double>(p, "ticks_per_second");
      const std::string tag = readCondition(p, static_cast<uint64_t>(ticks), tps).tag();
      out << "ok\t" << tag << "\n";
    } catch (const ParameterError& e) {
      std::string why = e.what();
      if (why.rfind('~', 0) == 0) why.erase(0, 1);  // an experiment file's key, not a node's ~parameter
      out << "error\t" << why << "\n";
      status = 2;
    }
  }
  return status;
}

}  // namespace swarm_forage
