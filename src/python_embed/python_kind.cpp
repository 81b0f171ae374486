// A Python controller kind: the class imported once, its attributes read and checked, its constants from
// its defaults file (docs/python-controllers.md).
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "embedded.hpp"
#include "swarm_forage/core/world/config.hpp"
#include "swarm_forage/python/python_controllers.hpp"

namespace swarm_forage {

// Hidden, as pybind11's own namespace: these types hold Python objects.
#pragma GCC visibility push(hidden)
namespace embedded {

void visitPyConstants(PyConstants& c, ConstantVisitor& v) {
  for (auto& e : c.entries) {
    if (e.whole)
      v.count(e.name.c_str(), e.count);
    else
      v.number(e.name.c_str(), e.number);
  }
  v.count("source_digest", c.source_digest);
}

py::dict PyConstants::asDict() const {
  py::dict d;
  for (const auto& e : entries) {
    if (e.whole)
      d[py::str(e.name)] = py::int_(e.count);
    else
      d[py::str(e.name)] = py::float_(e.number);
  }
  return d;
}

void PyConstants::validate() const {
  const std::string kind = cls ? cls->kind : "python";
  for (const auto& e : entries)
    if (!e.whole && !std::isfinite(e.number))
      throw ParameterError(kind + "/" + e.name + " must be a finite number (got " +
                           canonicalNumber(e.number) + ")");
  if (source_digest != expected_digest)
    throw ParameterError(kind + "/source_digest is the digest of " + (cls ? cls->target : kind) +
                         " and its module's source (" + std::to_string(expected_digest) +
                         "), set by swarm_forage, not a constant (got " + std::to_string(source_digest) +
                         ")");
  if (!cls || !cls->validates) return;
  py::gil_scoped_acquire hold;
  try {
    cls->cls.attr("validate")(asDict());
  } catch (const py::error_already_set& e) {
    throw ParameterError(kind + ": " + cls->named() + " refused its constants: " + lastLine(e));
  }
}

}  // namespace embedded
#pragma GCC visibility pop

namespace {

using namespace embedded;

uint32_t fnv1a(const std::string& text, uint32_t h = 2166136261u) {
  for (const unsigned char c : text) h = (h ^ c) * 16777619u;
  return h;
}

// The class's attributes, each checked with its valid values.
struct Attributes {
  const py::object& cls;
  const std::function<void(const std::string&)>& fail;

  bool flag(const char* name) const {
    if (!py::hasattr(cls, name)) return false;
    const py::object v = cls.attr(name);
    if (!py::isinstance<py::bool_>(v))
      fail(std::string("its attribute ") + name + " must be True or False (got " +
           py::repr(v).cast<std::string>() + ")");
    return v.cast<bool>();
  }
  std::string text(const char* name, const std::string& otherwise) const {
    if (!py::hasattr(cls, name)) return otherwise;
    const py::object v = cls.attr(name);
    if (!py::isinstance<py::str>(v) || v.cast<std::string>().empty())
      fail(std::string("its attribute ") + name + " must be a non-empty string (got " +
           py::repr(v).cast<std::string>() + ")");
    return v.cast<std::string>();
  }
  uint32_t whole(const char* name, long long high) const {
    if (!py::hasattr(cls, name)) return 0;
    const py::object v = cls.attr(name);
    const bool ok = py::isinstance<py::int_>(v) && !py::isinstance<py::bool_>(v) &&
                    v.cast<long long>() >= 0 && v.cast<long long>() <= high;
    if (!ok)
      fail(std::string("its attribute ") + name + " must be a whole number in [0, " + std::to_string(high) +
           "] (got " + py::repr(v).cast<std::string>() + ")");
    return static_cast<uint32_t>(v.cast<long long>());
  }
  bool callable(const char* name) const {
    return py::hasattr(cls, name) && PyCallable_Check(cls.attr(name).ptr());
  }
};

std::vector<PyConstants::Entry> readDefaults(const std::string& kind, const std::string& path,
                                             const std::function<void(const std::string&)>& fail) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const std::exception& e) {
    fail("its defaults " + path + " cannot be read: " + e.what());
  }
  const YAML::Node section = root.IsMap() ? root[kind] : YAML::Node();
  if (!section.IsMap()) fail("its defaults " + path + " must hold the map '" + kind + ":' of its constants");
  std::vector<PyConstants::Entry> entries;
  for (const auto& item : section) {
    PyConstants::Entry e;
    e.name = item.first.as<std::string>();
    const bool plain = e.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") == std::string::npos;
    if (e.name.empty() || !plain || e.name == "source_digest")
      fail(path + ": '" + e.name +
           "' is not a constant's name (lower-case letters, digits and _; not source_digest)");
    long long whole = 0;
    double number = 0;
    const YAML::Node& v = item.second;
    if (v.IsScalar() && YAML::convert<long long>::decode(v, whole) && whole >= 0 && whole <= 2147483647) {
      e.whole = true;
      e.count = static_cast<uint32_t>(whole);
    } else if (v.IsScalar() && YAML::convert<double>::decode(v, number) && std::isfinite(number)) {
      e.number = number;
    } else {
      fail(path + ": " + kind + "/" + e.name +
           " must be a finite number or a whole number in [0, 2147483647]");
    }
    entries.push_back(e);
  }
  return entries;
}

}  // namespace

ControllerKind pythonKind(const PythonControllerSpec& spec) {
  const std::string where =
      "python class " + spec.target + " (" + spec.name + ", declared in " + spec.declared_in + ")";
  const std::function<void(const std::string&)> fail = [&](const std::string& why) {
    throw ParameterError(where + ": " + why);
  };
  const auto dot = spec.target.rfind('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == spec.target.size())
    fail("'" + spec.target + "' must be module.Class (e.g. my_pkg.my_module.MyController)");
  const std::string module = spec.target.substr(0, dot), class_name = spec.target.substr(dot + 1);
  try {
    ensureInterpreter();
  } catch (const std::exception& e) {
    fail(e.what());
  }
  auto cls = std::make_shared<PythonClass>();
  cls->kind = spec.name;
  cls->target = spec.target;
  ControllerKind k;
  k.name = spec.name;
  k.one_thread = true;
  std::string module_file, defaults;
  {
    py::gil_scoped_acquire hold;
    try {
      // The package's src/ after everything else: an installed or devel module of that name comes first.
      const std::string src = spec.package_dir + "/src";
      py::list path = py::module_::import("sys").attr("path");
      if (std::filesystem::is_directory(src) && !path.contains(py::str(src))) path.append(src);
      const py::module_ m = py::module_::import(module.c_str());
      if (!py::hasattr(m, class_name.c_str())) fail("module " + module + " has no class " + class_name);
      cls->cls = m.attr(class_name.c_str());
      if (!PyType_Check(cls->cls.ptr())) fail(spec.target + " is not a class");
      module_file = py::str(m.attr("__file__")).cast<std::string>();
    } catch (const py::error_already_set& e) {
      fail("cannot be imported: " + lastLine(e));
    }
    const Attributes a{cls->cls, fail};
    if (!a.callable("step")) fail("it has no method step(self, tick, sensors, out)");
    k.display_name = a.text("display_name", class_name);
    k.colour = a.text("colour", "tab:gray");
    k.line_of_sight = cls->line_of_sight = a.flag("line_of_sight");
    k.static_cache = cls->static_cache = a.flag("static_cache");
    k.light_only_carrying = a.flag("light_only_carrying");
    cls->draws = a.whole("draws", 64);
    cls->normals = a.whole("normals", 64);
    defaults = a.text("defaults", "");
    if (defaults.empty())
      fail("it declares no defaults file (its attribute defaults: e.g. 'config/<name>.yaml')");
    cls->checkpointable = a.callable("save") && a.callable("load");
    cls->validates = a.callable("validate");
    const py::object states =
        py::hasattr(cls->cls, "states") ? cls->cls.attr("states") : py::object(py::none());
    if (py::isinstance<py::list>(states) || py::isinstance<py::tuple>(states))
      for (const py::handle s : states)
        if (py::isinstance<py::str>(s) && !s.cast<std::string>().empty())
          cls->states.push_back(s.cast<std::string>());
    if (cls->states.empty() || cls->states.size() != py::len(states) || cls->states.size() > 255)
      fail(
          "its attribute states must list its states' names (1 to 255 non-empty strings; out.state indexes "
          "it)");
  }
  std::ifstream in(module_file, std::ios::binary);
  const std::string source((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in && !in.eof()) fail("its module's source " + module_file + " cannot be read");
  PyConstants constants;
  constants.entries = readDefaults(spec.name, spec.package_dir + "/" + defaults, fail);
  // 31 bits: a count constant, as the ROS layer reads it (a whole number in [0, 2147483647]).
  constants.source_digest = constants.expected_digest =
      fnv1a(source, fnv1a(spec.target + "\n")) & 0x7fffffffu;
  constants.cls = cls;
  constants.validate();  // the defaults: the class's validate() must take them
  k.defaults = defaults;
  k.constants = [constants] {
    auto s = std::make_unique<SectionOf<PyConstants>>(visitPyConstants);
    s->config = constants;
    return s;
  };
  k.make = [cls](const ControllerConfigs& c, uint32_t seed, uint32_t first, uint32_t n) {
    return makePythonBatch(cls, c, seed, first, n);
  };
  return k;
}

}  // namespace swarm_forage
