#pragma once
// What the Python controllers' files share (python_controllers.hpp): the interpreter, the class a kind
// imported, its constants. Everything of pybind11 is touched with the GIL held (gil_scoped_acquire).
#include <pybind11/embed.h>
#include <pybind11/numpy.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "swarm_forage/core/controllers/controller.hpp"
#include "swarm_forage/core/controllers/controller_constants.hpp"

namespace swarm_forage {
// Hidden, as pybind11's own namespace: these types hold Python objects.
#pragma GCC visibility push(hidden)
namespace embedded {

namespace py = pybind11;

/// Starts the interpreter once per process, from any thread, and releases the GIL: a caller holds it only
/// while it calls into Python. Throws std::runtime_error when numpy cannot be imported.
void ensureInterpreter();

/// A Python exception as the last line of its traceback and where it was raised:
/// "ValueError: bad shape (numpy_crw.py:88)".
std::string lastLine(const py::error_already_set& e);

/// The class a kind imported and what its attributes declared; shared by the kind and its batches.
struct PythonClass {
  std::string kind;    // "<package>/<name>"
  std::string target;  // "module.Class"
  py::object cls;      // with the GIL only
  std::vector<std::string> states;
  uint32_t draws = 0, normals = 0;  // uniform and normal draws per robot and tick
  bool line_of_sight = false, static_cache = false, checkpointable = false, validates = false;
  ~PythonClass();
  /// "python class module.Class (kind)": how every message names it.
  std::string named() const { return "python class " + target + " (" + kind + ")"; }
};

/// A Python kind's constants: its defaults file's keys (whole numbers as counts), then source_digest.
struct PyConstants {
  struct Entry {
    std::string name;
    bool whole = false;
    double number = 0;
    uint32_t count = 0;
  };
  std::vector<Entry> entries;
  uint32_t source_digest = 0, expected_digest = 0;
  std::shared_ptr<PythonClass> cls;
  void validate() const;  // finite numbers, the digest untouched, and the class's validate(constants)
  py::dict asDict() const;
};
void visitPyConstants(PyConstants& c, ConstantVisitor& v);

/// A batch of the class for robots [first_id, first_id + count): the class's instance, stepped on the
/// calling thread with the GIL held.
std::unique_ptr<ControllerBatch> makePythonBatch(const std::shared_ptr<PythonClass>& cls,
                                                 const ControllerConfigs& configs, uint32_t seed,
                                                 uint32_t first_id, uint32_t count);

}  // namespace embedded
#pragma GCC visibility pop
}  // namespace swarm_forage
