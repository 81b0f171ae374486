#pragma once
// The public base class of a controller plugin: a pluginlib class, found by its name in the plugin XML
// ("my_pkg/MyController"), that declares one controller kind in the same form as a built-in's
// registration line (ControllerKind, controller_registry.hpp). Reference: docs/controller-plugins.md.
//
//   class MyController : public swarm_forage::ControllerPlugin {
//    public:
//     swarm_forage::ControllerKind kind() const override;  // name, look, features, constants, make
//   };
//   PLUGINLIB_EXPORT_CLASS(my_pkg::MyController, swarm_forage::ControllerPlugin)  // in the .cpp
//
// Nothing here needs ROS: pluginlib only needs the class to be default-constructible.
#include "swarm_forage/core/controllers/controller.hpp"
#include "swarm_forage/core/controllers/controller_constants.hpp"
#include "swarm_forage/core/controllers/controller_registry.hpp"

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
