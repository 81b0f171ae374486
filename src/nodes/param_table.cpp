// param_table [--yaml | --help]: the parameter table (param_table.hpp) as YAML, what tools that make or check
// its other forms read: scripts/param_docs writes docs/nodes-and-parameters.md's tables from it and checks
// the launch files' argument docs against it.
#include "swarm_forage/ros/params/param_table.hpp"

#include <cstdio>
#include <string>

#include "swarm_forage/ros/params/params.hpp"

namespace {
using namespace swarm_forage;

/// A YAML double-quoted scalar.
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) out += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
  return out + "\"";
}

const char* typeName(ParamType t) {
  switch (t) {
    case ParamType::kBool:
      return "bool";
    case ParamType::kInt:
      return "int";
    case ParamType::kNumber:
      return "number";
    case ParamType::kText:
      return "text";
    case ParamType::kChoice:
      return "choice";
    case ParamType::kCondition:
      return "condition";
    case ParamType::kSection:
      return "section";
  }
  return "";
}

void printYaml() {
  std::printf("readers: [");
  for (unsigned r = 1; *readerName(static_cast<ParamReader>(r)); r <<= 1)
    std::printf("%s%s", r == 1 ? "" : ", ", readerName(static_cast<ParamReader>(r)));
  std::printf("]\nparameters:\n");
  for (const ParamSpec& s : paramTable()) {
    std::printf("  - name: %s\n    type: %s\n    default: %s\n    valid: %s\n    doc: %s\n    readers: [",
                quoted(s.name).c_str(), typeName(s.type), quoted(s.fallback).c_str(),
                quoted(validText(s)).c_str(), quoted(s.doc).c_str());
    bool first = true;
    for (unsigned r = 1; *readerName(static_cast<ParamReader>(r)); r <<= 1)
      if (s.readers & r) {
        std::printf("%s%s", first ? "" : ", ", readerName(static_cast<ParamReader>(r)));
        first = false;
      }
    std::printf("]\n");
    if (s.type == ParamType::kInt || s.type == ParamType::kNumber)
      std::printf("    range: [%.17g, %.17g]\n", s.lo, s.hi);
    if (s.type == ParamType::kChoice) {
      std::printf("    choices: [");
      first = true;
      for (const std::string& c : s.choices()) {
        std::printf("%s%s", first ? "" : ", ", quoted(c).c_str());
        first = false;
      }
      std::printf("]\n");
    }
  }
}
}  // namespace

int main(int argc, char** argv) {
  const std::string word = argc == 2 ? argv[1] : "";
  if (word == "--yaml") {
    printYaml();
    return 0;
  }
  std::fprintf(word == "--help" || word == "-h" ? stdout : stderr,
               "usage: param_table --yaml\n"
               "Every parameter of the nodes, run_experiment, run_tables and read_run as YAML: name, type, "
               "default,\nvalid, doc, readers, and range or choices (src/ros/params/param_table.cpp, the one "
               "place they are\ndeclared). scripts/param_docs makes and checks their other forms from it.\n");
  return word == "--help" || word == "-h" ? 0 : 2;
}
