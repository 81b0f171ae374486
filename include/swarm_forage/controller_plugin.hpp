#pragma once
// The public base class of a controller plugin: a pluginlib class, found by its name in the plugin XML
// ("my_pkg/MyController"), that declares one controller kind in the same form as a built-in's
// registration line (ControllerKind, controller_registry.hpp). Reference: docs/controller-plugins.md.
//
//   class MyController : public swarm_forage::ControllerPlugin {
//    public:
//     swarm_forage::ControllerKind kind() const override;  // name, look, features, constants, make
//   };
//   SWARM_FORAGE_EXPORT_CONTROLLER(my_pkg::MyController)  // in the .cpp
//
// pluginlib only needs the class to be default-constructible; the ROS-free core never includes this.
#include <pluginlib/class_list_macros.hpp>

#include "swarm_forage/core/controllers/controller.hpp"
#include "swarm_forage/core/controllers/controller_constants.hpp"
#include "swarm_forage/core/controllers/controller_registry.hpp"

/// The plugin interface's version: what a plugin's compiled code assumes of these headers (ControllerKind,
/// ControllerBatch, the sensor, command and status batches, the constants). It goes up with every change
/// of them that a plugin built before would misread; a plugin built against another version is refused
/// before any of its code is called, naming it, its library and both versions.
#define SWARM_FORAGE_PLUGIN_ABI 1

extern "C" {
/// Notes that the plugin class `class_type` (as the plugin XML's `type` names it) was built against plugin
/// ABI `abi`; SWARM_FORAGE_EXPORT_CONTROLLER calls it as the plugin's library is loaded. Its signature is
/// the one part of the interface that never changes.
void swarm_forage_plugin_abi(const char* class_type, unsigned abi);
}

/// Exports controller plugin `Class` (its full name, as in the plugin XML's `type`): pluginlib's
/// registration, and the plugin ABI it is compiled against. Once per class, in its .cpp.
#define SWARM_FORAGE_EXPORT_CONTROLLER(Class)                   \
  PLUGINLIB_EXPORT_CLASS(Class, swarm_forage::ControllerPlugin) \
  SWARM_FORAGE_PLUGIN_ABI_NOTE_(Class, __COUNTER__)
#define SWARM_FORAGE_PLUGIN_ABI_NOTE_(Class, n) SWARM_FORAGE_PLUGIN_ABI_NOTE2_(Class, n)
#define SWARM_FORAGE_PLUGIN_ABI_NOTE2_(Class, n)                                            \
  namespace {                                                                               \
  struct SwarmForagePluginAbi##n {                                                          \
    SwarmForagePluginAbi##n() { swarm_forage_plugin_abi(#Class, SWARM_FORAGE_PLUGIN_ABI); } \
  } const swarm_forage_plugin_abi_##n;                                                      \
  }

namespace swarm_forage {

class ControllerPlugin {
 public:
  virtual ~ControllerPlugin() = default;
  /// The kind this plugin adds, as a built-in declares its own: `name` equal to the class name in the
  /// plugin XML; `defaults` the YAML file of its constants' defaults, relative to its package (e.g.
  /// "config/my_controller.yaml", holding `my_pkg/MyController: {key: value, ...}`), which must equal
  /// the code defaults. Called once, when the name is first looked up.
  virtual ControllerKind kind() const = 0;
};

}  // namespace swarm_forage
