#include "swarm_forage/core/world/fordyca_quirks.hpp"

#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

const std::array<QuirkInfo, static_cast<std::size_t>(Quirk::kCount)>& quirkList() {
  static const std::array<QuirkInfo, static_cast<std::size_t>(Quirk::kCount)> list{{
      {Quirk::kTransportWander, "transport_wander", false, true,
       "transport adds the wander force when not threatened and nearly stopped"},
      {Quirk::kAbsoluteRecoveryAngle, "absolute_recovery_angle", false, true,
       "a recovering DPO robot's new direction is an absolute world angle U[0, 1] rad"},
      {Quirk::kFirstCollisionAtZero, "first_collision_at_zero", false, true,
       "last_collision_time starts at 0: a collision in the first 300 ticks counts as a second one"},
      {Quirk::kCompressedArrival, "compressed_arrival", false, true,
       "the arrival heading is atan2(delta, m)"},
      {Quirk::kHeadingEstimate, "heading_estimate", false, true,
       "the heading is estimated from the last two positions"},
      {Quirk::kRimGroundSensors, "rim_ground_sensors", true, true,
       "four ground sensors on the rim: a block when 4 read black, the nest when 3 of 4 read grey"},
      {Quirk::kBlockPenalties, "block_penalties", true, true,
       "block pick-up and drop penalties and one-per-tick deconfliction"},
      {Quirk::kLightOcclusion, "light_occlusion", true, true, "robots shadow the light sensors"},
      {Quirk::kDynamics2dContacts, "dynamics2d_contacts", true, false,
       "contacts closer to ARGoS dynamics2d: a robot driven into a crowd moves it"},
  }};
  return list;
}

std::string quirkNames() {
  std::string s;
  for (const QuirkInfo& i : quirkList()) s += (s.empty() ? "" : ", ") + std::string(i.name);
  return s;
}

const std::vector<std::string>& modelNames() {
  // The first is the default: FORDYCA's code as it ran, the reference for reproducing the paper.
  static const std::vector<std::string> names{"fordyca_2019", "swarm_forage"};
  return names;
}

void FordycaQuirks::set(Quirk q, bool on) {
  const uint32_t bit = 1u << static_cast<unsigned>(q);
  bits_ = on ? (bits_ | bit) : (bits_ & ~bit);
}

FordycaQuirks FordycaQuirks::parse(const std::string& model, const std::string& extra) {
  FordycaQuirks q;
  if (model == "fordyca_2019") {
    for (const QuirkInfo& i : quirkList())
      if (i.fordyca_2019) q.set(i.quirk);
  } else if (model != "swarm_forage") {
    throw ParameterError("~model '" + model + "' is unknown; valid: fordyca_2019 (the default), swarm_forage");
  }
  const std::string valid = quirkNames();
  std::size_t start = 0;
  while (start <= extra.size()) {
    std::size_t end = extra.find(',', start);
    if (end == std::string::npos) end = extra.size();
    std::string word = extra.substr(start, end - start);
    const auto first = word.find_first_not_of(" \t"), last = word.find_last_not_of(" \t");
    word = first == std::string::npos ? "" : word.substr(first, last - first + 1);
    if (!word.empty()) {
      bool found = false;
      for (const QuirkInfo& i : quirkList())
        if (word == i.name) {
          q.set(i.quirk);
          found = true;
        }
      if (!found)
        throw ParameterError("~quirks: '" + word + "' is not a quirk; valid (comma-separated): " + valid);
    }
    start = end + 1;
  }
  return q;
}

FordycaQuirks FordycaQuirks::worldSide() const {
  FordycaQuirks q;
  for (const QuirkInfo& i : quirkList())
    if (i.world && has(i.quirk)) q.set(i.quirk);
  return q;
}

FordycaQuirks FordycaQuirks::controllerSide() const {
  FordycaQuirks q;
  for (const QuirkInfo& i : quirkList())
    if (!i.world && has(i.quirk)) q.set(i.quirk);
  return q;
}

std::string FordycaQuirks::names() const {
  std::string s;
  for (const QuirkInfo& i : quirkList())
    if (has(i.quirk)) s += (s.empty() ? "" : ",") + std::string(i.name);
  return s;
}

std::string FordycaQuirks::tag() const {
  // Relative to the default model: its runs' names carry no model word, swarm_forage's say so.
  FordycaQuirks model = parse("fordyca_2019", ""), rest = *this;
  const bool whole = (bits_ & model.bits_) == model.bits_;
  if (whole) rest.bits_ &= ~model.bits_;
  std::string s = whole ? "" : "swarm_forage";
  for (const QuirkInfo& i : quirkList())
    if (rest.has(i.quirk)) s += (s.empty() ? "" : "_") + std::string(i.name);
  return s;
}

std::string FordycaQuirks::describe() const { return any() ? "quirks=" + names() : ""; }

}  // namespace swarm_forage
