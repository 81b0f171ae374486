// The embedded interpreter: started once, by whichever thread first needs it, and never finalised (batches
// of nodelets may outlive any owner that could end it; the process's exit ends it).
#include <dlfcn.h>

#include <filesystem>
#include <mutex>
#include <stdexcept>

#include "embedded.hpp"

namespace swarm_forage {
// Hidden, as pybind11's own namespace: these types hold Python objects.
#pragma GCC visibility push(hidden)
namespace embedded {

void ensureInterpreter() {
  static std::once_flag once;
  static std::string failure;
  std::call_once(once, [] {
#ifdef SWARM_FORAGE_LIBPYTHON
    // A nodelet manager loads libpython privately (RTLD_LOCAL) with the nodelet library; numpy's extension
    // modules then cannot see its symbols. Promote it to the global namespace before anything imports.
    dlopen(SWARM_FORAGE_LIBPYTHON, RTLD_NOW | RTLD_NOLOAD | RTLD_GLOBAL);
#endif
    if (!Py_IsInitialized()) {
      // No signal handlers of Python's: SIGINT stays the ROS node's.
      py::initialize_interpreter(false);
      PyEval_SaveThread();  // the GIL is taken by each call into Python
    }
    py::gil_scoped_acquire hold;
    try {
      py::module_::import("numpy");
    } catch (const py::error_already_set& e) {
      failure = "the embedded Python cannot import numpy: " + lastLine(e);
    }
  });
  if (!failure.empty()) throw std::runtime_error(failure);
}

std::string lastLine(const py::error_already_set& e) {
  std::string out;
  try {
    out = py::str(e.type().attr("__name__")).cast<std::string>();
    const std::string value = py::str(e.value()).cast<std::string>();
    if (!value.empty()) out += ": " + value;
    py::handle tb = e.trace();
    if (tb && !tb.is_none()) {
      while (!tb.attr("tb_next").is_none()) tb = tb.attr("tb_next");
      const auto file = py::str(tb.attr("tb_frame").attr("f_code").attr("co_filename")).cast<std::string>();
      out += " (" + std::filesystem::path(file).filename().string() + ":" +
             std::to_string(tb.attr("tb_lineno").cast<int>()) + ")";
    }
  } catch (const std::exception&) {
    if (out.empty()) out = e.what();  // an exception whose str() raises
  }
  return out;
}

PythonClass::~PythonClass() {
  if (!cls) return;
  py::gil_scoped_acquire hold;
  cls = py::object();
}

}  // namespace embedded
#pragma GCC visibility pop
}  // namespace swarm_forage
