// Controller kinds written in Python (docs/python-controllers.md): a package declares its classes in a YAML
// file it exports for swarm_forage (<swarm_forage python="${prefix}/python_controllers.yaml"/>), one line
// per kind, "<package>/<name>: module.Class"; every process of the ROS layer finds them there.
#include "swarm_forage/python/python_controllers.hpp"

#include <ros/package.h>
#include <yaml-cpp/yaml.h>

#include <map>
#include <memory>
#include <mutex>

namespace swarm_forage {

namespace {

class PythonControllers final : public ControllerSource {
 public:
  std::vector<std::string> names() const override {
    std::vector<std::string> out;
    for (const auto& [name, entry] : declared()) out.push_back(name);
    return out;
  }

  bool load(const std::string& name) override {
    const auto& all = declared();
    const auto it = all.find(name);
    if (it == all.end()) return false;
    const Entry& e = it->second;
    if (!e.problem.empty())
      throw ParameterError("python controller '" + name + "' (" + e.file + "): " + e.problem);
    registerKind(pythonKind({name, e.target, ros::package::getPath(e.package), e.file}));
    return true;
  }

 private:
  struct Entry {
    std::string package, file, target, problem;
  };

  // Read once per process: the exports of every package on the ROS package path.
  static const std::map<std::string, Entry>& declared() {
    static std::once_flag once;
    static auto* all = new std::map<std::string, Entry>;  // never destroyed, as the registry's kinds
    std::call_once(once, [] {
      std::vector<std::pair<std::string, std::string>> exports;
      ros::package::getPlugins("swarm_forage", "python", exports);
      for (const auto& [package, file] : exports) {
        YAML::Node root;
        try {
          root = YAML::LoadFile(file);
        } catch (const std::exception& e) {
          (*all)[package + "/?"] = {package, file, "", std::string("cannot be read: ") + e.what()};
          continue;
        }
        if (!root.IsMap()) continue;
        for (const auto& item : root) {
          const std::string name = item.first.as<std::string>();
          Entry e{package, file, item.second.IsScalar() ? item.second.as<std::string>() : "", ""};
          if (name.compare(0, package.size() + 1, package + "/") != 0)
            e.problem = "is declared by package " + package + "; its name must start with '" + package + "/'";
          else if (e.target.empty())
            e.problem = "must name its class as module.Class (e.g. " + package + ".my_module.MyController)";
          all->emplace(name, e);
        }
      }
    });
    return *all;
  }
};

const bool installed = [] {
  addControllerSource(std::make_shared<PythonControllers>());
  return true;
}();

}  // namespace

}  // namespace swarm_forage
