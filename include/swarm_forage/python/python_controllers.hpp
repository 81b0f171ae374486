#pragma once
// Controller kinds written as a Python class and run in process through an embedded interpreter
// (docs/python-controllers.md). A library of its own, swarm_forage_python: the core stays free of Python.
#include <string>

#include "swarm_forage/core/controllers/controller_registry.hpp"

namespace swarm_forage {

/// Where a Python kind comes from: its name as a kind ("<package>/<name>"), the class ("module.Class"),
/// its package's folder (the defaults file is relative to it; its src/ is put on sys.path) and the file
/// that declared it (for messages).
struct PythonControllerSpec {
  std::string name;
  std::string target;
  std::string package_dir;
  std::string declared_in;
};

/// Imports the class and makes its kind: the class's attributes declare its look, world features, states
/// and random draws; its defaults file its constants, to which the kind adds `source_digest` (the class's
/// name and its module's source), so that an edited controller is another run. Throws ParameterError
/// naming the class and what is wrong (an import that fails: the Python traceback's last line).
ControllerKind pythonKind(const PythonControllerSpec& spec);

}  // namespace swarm_forage
