// Controller kinds from pluginlib (docs/controller-plugins.md): every process that links the ROS layer
// (the nodes, the nodelets, run_experiment, the tools) finds a kind the core does not know among the
// classes exported for swarm_forage::ControllerPlugin, and registers it as a built-in registers itself.
#include <ros/package.h>

#include <algorithm>
#include <memory>
#include <pluginlib/class_loader.hpp>

#include "swarm_forage/controller_plugin.hpp"

namespace swarm_forage {

namespace {

class PluginControllers final : public ControllerSource {
 public:
  std::vector<std::string> names() const override {
    std::vector<std::string> out;
    for (const std::string& n : loader().getDeclaredClasses())
      if (n.find('/') != std::string::npos) out.push_back(n);
    std::sort(out.begin(), out.end());
    return out;
  }

  bool load(const std::string& name) override {
    if (name.find('/') == std::string::npos || !loader().isClassAvailable(name)) return false;
    const std::string where =
        "controller plugin '" + name + "' (" + loader().getPluginManifestPath(name) + ")";
    ControllerKind kind;
    try {
      // Never deleted: its library stays loaded as long as the process, and with it the kind's make and
      // every batch it makes (nodelets included).
      const ControllerPlugin* plugin = loader().createUnmanagedInstance(name);
      kind = plugin->kind();
    } catch (const std::exception& e) {
      throw ParameterError(where + " failed to load: " + e.what());
    }
    if (kind.name != name)
      throw ParameterError(where + " declares the kind name '" + kind.name +
                           "'; it must equal the class name in its plugin XML");
    const std::string package = loader().getClassPackage(name);
    if (name.compare(0, package.size() + 1, package + "/") != 0)
      throw ParameterError(where + " is exported by package " + package + "; its name must start with '" +
                           package + "/'");
    if (!kind.builds_on.empty()) controllerKind(kind.builds_on);  // throws for an unknown base
    if (!kind.constants || !kind.make)
      throw ParameterError(where +
                           " declares no constants or no make (an empty section: sectionOf of a "
                           "visit that visits nothing)");
    if (kind.defaults.empty())
      throw ParameterError(where + " declares no defaults file (e.g. config/<name>.yaml in " + package + ")");
    try {
      kind.constants()->validate();
    } catch (const std::exception& e) {
      throw ParameterError(where + ": its code defaults are not valid: " + e.what());
    }
    checkDefaultsFile(kind, ros::package::getPath(package) + "/" + kind.defaults);
    registerKind(std::move(kind));
    return true;
  }

 private:
  // Made on first use (it reads every package's exports) and never destroyed (see load).
  static pluginlib::ClassLoader<ControllerPlugin>& loader() {
    static auto* l =
        new pluginlib::ClassLoader<ControllerPlugin>("swarm_forage", "swarm_forage::ControllerPlugin");
    return *l;
  }
};

const bool installed = [] {
  setControllerSource(std::make_shared<PluginControllers>());
  return true;
}();

}  // namespace

}  // namespace swarm_forage
