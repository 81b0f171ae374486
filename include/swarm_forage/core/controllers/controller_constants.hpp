#pragma once
// Controller constants under their YAML names: one section per controller kind (its
// config/controllers/<kind>.yaml). The ROS layer reads them with these names, refuses keys that are not
// among them, and a run's identity lists them with the same names, so the three cannot disagree.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "swarm_forage/core/util/geometry.hpp"
#include "swarm_forage/core/world/fordyca_quirks.hpp"
#include "swarm_forage/core/world/sensing.hpp"

namespace swarm_forage {

/// Visits a section's constants, each under its YAML name, by kind of value.
class ConstantVisitor {
 public:
  virtual ~ConstantVisitor() = default;
  virtual void number(const char* name, double& v) = 0;
  virtual void count(const char* name, uint32_t& v) = 0;
  /// An angle held in radians and written in degrees.
  virtual void degrees(const char* name, double& radians) = 0;
  /// A two-valued string (off | on) held as a flag.
  virtual void choice(const char* name, bool& flag, const char* off, const char* on) = 0;
};

/// One kind's own constants, type-erased so that a new kind brings its own without edits here.
class ConstantSection {
 public:
  virtual ~ConstantSection() = default;
  virtual std::unique_ptr<ConstantSection> clone() const = 0;
  virtual void visit(ConstantVisitor& v) = 0;
  virtual void validate() const = 0;  // throws ParameterError naming "<kind>/<key>" and its range
};

/// A section held as the kind's Config (with validate()), visited by `visit`.
template <class Config>
class SectionOf final : public ConstantSection {
 public:
  using Visit = void (*)(Config&, ConstantVisitor&);
  explicit SectionOf(Visit visit) : visit_(visit) {}
  std::unique_ptr<ConstantSection> clone() const override { return std::make_unique<SectionOf>(*this); }
  void visit(ConstantVisitor& v) override { visit_(config, v); }
  void validate() const override { config.validate(); }
  Config config;

 private:
  Visit visit_;
};

/// A kind's section maker: its Config at the defaults, visited by `visit`.
template <class Config>
std::function<std::unique_ptr<ConstantSection>()> sectionOf(void (*visit)(Config&, ConstantVisitor&)) {
  return [visit] { return std::make_unique<SectionOf<Config>>(visit); };
}

/// What a run's world tells its controllers at the start: the nest centre and the line-of-sight geometry.
struct WorldFacts {
  Vec2 nest_center;
  LineOfSight sight;
};

/// Every registered kind's constants (defaults: the core's, which equal config/controllers/*.yaml) and,
/// once sharingWorld() has set them, the world facts a batch starts from.
class ControllerConfigs {
 public:
  ControllerConfigs();
  ControllerConfigs(const ControllerConfigs& other) { *this = other; }
  ControllerConfigs& operator=(const ControllerConfigs& other);
  ControllerConfigs(ControllerConfigs&&) = default;
  ControllerConfigs& operator=(ControllerConfigs&&) = default;

  /// Kind `kind`'s own section; throws ParameterError for an unknown kind, std::logic_error for a wrong
  /// Config.
  template <class Config>
  Config& of(const std::string& kind) {
    auto* s = dynamic_cast<SectionOf<Config>*>(&section(kind));
    if (s == nullptr) wrongType(kind);
    return s->config;
  }
  template <class Config>
  const Config& of(const std::string& kind) const {
    return const_cast<ControllerConfigs*>(this)->of<Config>(kind);
  }
  void visit(const std::string& kind, ConstantVisitor& v) { section(kind).visit(v); }
  /// Every section, in the order of controllerNames(); throws the first ParameterError.
  void validate() const;

  std::optional<WorldFacts> world;  // unset: each kind's own defaults
  FordycaQuirks quirks;             // FORDYCA 2019's quirks; the controllers apply controllerSide()

 private:
  ConstantSection& section(const std::string& kind) const;
  [[noreturn]] static void wrongType(const std::string& kind);
  mutable std::map<std::string, std::unique_ptr<ConstantSection>> sections_;  // plugins' added on first use
};

/// The keys of kind `kind`'s section, in YAML order; empty for an unknown kind.
std::vector<std::string> parameterNames(const std::string& kind);
struct ControllerKind;
/// Throws ParameterError naming the file and the keys unless the YAML file `path` holds, under the key
/// `kind.name`, exactly the kind's own constants (in order) at their code defaults.
void checkDefaultsFile(const ControllerKind& kind, const std::string& path);
/// The constants kind `kind` runs with as canonical "section/name=value" words: its own section and
/// those it builds on, base first (crw's for crw; crw's and dpo's for dpo; ...), then the controllers'
/// quirks if any. Equal text means equal behaviour.
std::string describeConstants(const std::string& kind, ControllerConfigs configs);

}  // namespace swarm_forage
