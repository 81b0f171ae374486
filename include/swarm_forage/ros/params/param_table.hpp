#pragma once
// Every private parameter of the nodes and the headless tools, declared once: name, type, default, valid
// range and one line of what it does (src/ros/params/param_table.cpp). The readers take defaults and ranges
// from here; the known-parameter lists, every --help, docs/nodes-and-parameters.md's tables and the launch
// files' argument docs are made or checked from it (`param_table`, param_docs.test).
#include <string>
#include <vector>

namespace swarm_forage {

enum class ParamType {
  kBool,
  kInt,     // a whole number in [lo, hi]
  kNumber,  // a number in [lo, hi]
  kText,
  kChoice,     // one of choices()
  kCondition,  // the condition's: the core says what it accepts and checks it (conditionParameters)
  kSection,  // a group of keys, e.g. a controller's constants: choices() lists the keys or prefixes admitted
};

/// Who reads a parameter (a bit each).
enum ParamReader : unsigned {
  kWorldNode = 1,
  kControllerNode = 2,
  kEnvironmentNode = 4,
  kMetricsNode = 8,
  kRunExperiment = 16,
  kRunTables = 32,
  kReadRun = 64,
};

struct ParamSpec {
  const char* name;
  ParamType type;
  const char* fallback;  // the default, as a value is written (kText: "" for empty)
  double lo, hi;         // kInt, kNumber
  const char* note;      // what the type, range or list does not say; kText and kSection: what is valid
  std::vector<std::string> (*choices)();  // kChoice: the values; kSection: the keys; kText: listed after note
  const char* doc;                        // one line: what it does
  unsigned readers;                       // ParamReader bits
};

/// Every row, in the order --help and the docs list them.
const std::vector<ParamSpec>& paramTable();
/// The rows `reader` reads.
std::vector<ParamSpec> paramTable(ParamReader reader);
/// The row named `name` (read by `reader`, when given); throws std::logic_error when there is none, which
/// is a reader asking for an undeclared parameter.
const ParamSpec& paramSpec(const std::string& name, unsigned reader = 0);

/// What `s` accepts, as --help and the messages say it: "a whole number in [1, 10000000]", "one of ...".
std::string validText(const ParamSpec& s);
/// The default as --help shows it ('' for empty text).
std::string fallbackText(const ParamSpec& s);
/// The names `reader` knows, sections expanded (a name ending in '/' admits every key below it).
std::vector<std::string> knownParams(ParamReader reader);
/// The reader's name: world_node, run_experiment, ...; and the reader of that name (0: none).
const char* readerName(ParamReader reader);
unsigned readerNamed(const std::string& name);

}  // namespace swarm_forage
