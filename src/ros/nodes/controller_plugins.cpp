// Controller kinds from pluginlib (docs/controller-plugins.md): every process that links the ROS layer
// (the nodes, the nodelets, run_experiment, the tools) finds a kind the core does not know among the
// classes exported for swarm_forage::ControllerPlugin, and registers it as a built-in registers itself.
#include "swarm_forage/ros/nodes/controller_plugins.hpp"

#include <ros/package.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <ostream>
#include <pluginlib/class_loader.hpp>

#include "swarm_forage/controller_plugin.hpp"

namespace {
// The plugin ABI each exported class noted as its library was loaded (SWARM_FORAGE_EXPORT_CONTROLLER).
std::mutex g_abi_lock;
std::map<std::string, unsigned>& noted() {
  static auto* m = new std::map<std::string, unsigned>;  // never destroyed: libraries may load at exit
  return *m;
}
}  // namespace

extern "C" void swarm_forage_plugin_abi(const char* class_type, unsigned abi) {
  std::lock_guard<std::mutex> hold(g_abi_lock);
  noted()[class_type] = abi;
}

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
    std::string library;
    try {
      library = std::filesystem::path(loader().getClassLibraryPath(name)).lexically_normal().string();
      loader().loadLibraryForClass(name);  // runs only the library's registrations
    } catch (const std::exception& e) {
      throw ParameterError(where + " failed to load: " + e.what());
    }
    checkAbi(name, library);
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
    if (!kind.builds_on.empty()) try {
        controllerKind(kind.builds_on);
      } catch (const ParameterError& e) {
        throw ParameterError(where + " builds on another kind: " + e.what());
      }
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

  /// The plugin's library file, or its XML when the library is not found.
  static std::string file(const std::string& name) {
    try {
      return std::filesystem::path(loader().getClassLibraryPath(name)).lexically_normal().string();
    } catch (const std::exception&) {
      return loader().getPluginManifestPath(name);
    }
  }

 private:
  // Before the plugin's first call: code built against other headers may read every struct it is given
  // otherwise, so it must not run at all.
  static void checkAbi(const std::string& name, const std::string& library) {
    const std::string type = loader().getClassType(name);
    std::lock_guard<std::mutex> hold(g_abi_lock);
    const auto it = noted().find(type);
    const std::string here = std::to_string(SWARM_FORAGE_PLUGIN_ABI);
    if (it == noted().end())
      throw ParameterError("controller plugin '" + name + "' (" + library +
                           ") carries no plugin ABI version (exported with PLUGINLIB_EXPORT_CLASS, not "
                           "SWARM_FORAGE_EXPORT_CONTROLLER): export it with SWARM_FORAGE_EXPORT_CONTROLLER(" +
                           type + ") and rebuild it against this swarm_forage (plugin ABI " + here + ")");
    if (it->second != SWARM_FORAGE_PLUGIN_ABI)
      throw ParameterError("controller plugin '" + name + "' (" + library +
                           ") was built against plugin ABI " + std::to_string(it->second) +
                           "; this swarm_forage has plugin ABI " + here +
                           ": rebuild the plugin against its headers");
  }

  // Made on first use (it reads every package's exports) and never destroyed (see load).
  static pluginlib::ClassLoader<ControllerPlugin>& loader() {
    static auto* l =
        new pluginlib::ClassLoader<ControllerPlugin>("swarm_forage", "swarm_forage::ControllerPlugin");
    return *l;
  }
};

const auto g_plugins = std::make_shared<PluginControllers>();
const bool installed = [] {
  addControllerSource(g_plugins);
  return true;
}();

std::string packagePath(const std::string& package) { return ros::package::getPath(package); }

// Loads and describes plugin `name` in a child process: its YAML entry, or what went wrong.
bool listInChild(const std::string& name, std::string& text, std::string& why) {
  int fds[2];
  if (pipe(fds) != 0) {
    why = "cannot list controller plugin '" + name + "': pipe: " + std::strerror(errno);
    return false;
  }
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    why = "cannot list controller plugin '" + name + "': fork: " + std::strerror(errno);
    return false;
  }
  if (pid == 0) {  // the child: no destructors at its end (_exit), the plugin's library stays as it is
    close(fds[0]);
    std::string out;
    int code = 0;
    try {
      out = describeControllerKind(name, packagePath);
    } catch (const std::exception& e) {
      out = e.what();
      code = 3;
    }
    for (std::size_t at = 0; at < out.size();) {
      const ssize_t n = write(fds[1], out.data() + at, out.size() - at);
      if (n <= 0) _exit(4);
      at += static_cast<std::size_t>(n);
    }
    _exit(code);
  }
  close(fds[1]);
  std::string got;
  char buffer[4096];
  for (ssize_t n; (n = read(fds[0], buffer, sizeof buffer)) != 0;) {
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) break;
    got.append(buffer, static_cast<std::size_t>(n));
  }
  close(fds[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  const auto plugins = g_plugins->names();
  const std::string plugin = std::find(plugins.begin(), plugins.end(), name) != plugins.end()
                                 ? "controller plugin '" + name + "' (" + PluginControllers::file(name) + ")"
                                 : "python controller '" + name + "'";
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    text = got;
    return true;
  }
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    why = plugin + " crashed while being listed (signal " + std::to_string(sig) + ", " + strsignal(sig) + ")";
  } else if (WEXITSTATUS(status) == 3) {
    why = got.find("'" + name + "'") != std::string::npos ? got : plugin + ": " + got;
  } else {
    why = plugin + " ended the process with exit status " + std::to_string(WEXITSTATUS(status)) +
          " while being listed";
  }
  return false;
}

}  // namespace

int listControllerKinds(std::ostream& out, std::ostream& err) {
  std::map<std::string, std::string> entries;  // by name: the built-ins' and the plugins' in one order
  for (const std::string& name : controllerNames())
    if (name.find('/') == std::string::npos) entries[name] = describeControllerKind(name, packagePath);
  int left_out = 0;
  // Plugins and Python kinds alike: each one loaded in a child of its own.
  for (const std::string& name : availableControllers()) {
    if (name.find('/') == std::string::npos) continue;
    std::string text, why;
    if (listInChild(name, text, why)) {
      entries[name] = text;
    } else {
      err << why << "; left out\n";
      ++left_out;
    }
  }
  for (const auto& [name, text] : entries) out << text;
  return left_out;
}

}  // namespace swarm_forage
