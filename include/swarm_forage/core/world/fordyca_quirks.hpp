#pragma once
// FORDYCA 2019's departures from this project's model, each a switch of its own (docs/FIDELITY.md,
// "FORDYCA as it ran"). `model: fordyca_2019` turns on (1)-(8) at once; `quirks:` adds single ones on top of
// either model. This is the one list of their names.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace swarm_forage {

enum class Quirk : uint8_t {
  kTransportWander,        // (1) transport adds wander when not threatened and nearly stopped
  kAbsoluteRecoveryAngle,  // (2) a recovering DPO robot's new direction is an absolute world angle
  kFirstCollisionAtZero,   // (3) last_collision_time starts at 0
  kCompressedArrival,      // (4) the arrival heading is atan2(delta, m)
  kHeadingEstimate,        // (5) the heading is estimated from the last two positions
  kRimGroundSensors,       // (6) four ground sensors on the body's rim
  kBlockPenalties,         // (7) pick-up and drop penalties and one-per-tick deconfliction
  kLightOcclusion,         // (8) robots shadow the light sensors
  kDynamics2dContacts,     // (9) contacts closer to ARGoS dynamics2d (not part of fordyca_2019)
  kCount
};

struct QuirkInfo {
  Quirk quirk;
  const char* name;
  bool world;         // applied by the world (else by the controllers)
  bool fordyca_2019;  // part of `model: fordyca_2019`
  const char* what;
};

/// Every quirk, in the order of the enum.
const std::array<QuirkInfo, static_cast<std::size_t>(Quirk::kCount)>& quirkList();

/// Every quirk's name, comma-separated in list order (what an error message offers).
std::string quirkNames();

/// The models a run can name, the default first: "fordyca_2019" (FORDYCA's code as it ran) and
/// "swarm_forage" (its corrections, docs/FIDELITY.md).
const std::vector<std::string>& modelNames();

/// A set of quirks.
class FordycaQuirks {
 public:
  /// `model` plus the comma-separated quirk names of `extra`; throws ParameterError naming `~model` or
  /// `~quirks` and the valid names.
  static FordycaQuirks parse(const std::string& model, const std::string& extra);

  bool has(Quirk q) const { return (bits_ >> static_cast<unsigned>(q)) & 1u; }
  void set(Quirk q, bool on = true);
  bool any() const { return bits_ != 0; }
  /// The quirks one side applies: the world's, or the controllers'.
  FordycaQuirks worldSide() const;
  FordycaQuirks controllerSide() const;
  /// The names, comma-separated in list order; "" for none.
  std::string names() const;
  /// The identity word "quirks=<names>", "" for none (so a run of the default model keeps its identity).
  std::string describe() const;
  /// A short name for record names, relative to the default model: "" for fordyca_2019's quirks, else
  /// "swarm_forage"; then any other quirks ("_"-joined).
  std::string tag() const;
  bool operator==(const FordycaQuirks& o) const { return bits_ == o.bits_; }
  bool operator!=(const FordycaQuirks& o) const { return bits_ != o.bits_; }

 private:
  uint32_t bits_ = 0;
};

}  // namespace swarm_forage
