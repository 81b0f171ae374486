#pragma once
// Every controller constant under its YAML name (config/controllers/*.yaml), one list per section. The
// ROS layer reads the constants with these lists, rejects keys that are not in them, and names a run's
// constants with them, so the three can never disagree.
#include <string>
#include <vector>

#include "swarm_forage/core/controllers/controller_factory.hpp"

namespace swarm_forage {

/// A visitor has number(name, double&), count(name, uint32_t&), degrees(name, double& radians) and
/// choice(name, bool& flag, off, on) for a two-valued string.
template <typename V>
void visitCrwParameters(CrwConfig& c, V&& v) {
  v.degrees("wander_step_deg", c.wander_step);
  v.degrees("wander_limit_deg", c.wander_limit);
  v.number("wander_circle_distance", c.wander_circle_distance);
  v.number("wander_circle_radius", c.wander_circle_radius);
  v.number("wander_force", c.wander_force);
  v.number("wander_free_scale", c.wander_free_scale);
  v.number("avoidance_force", c.avoidance_force);
  v.number("phototaxis_force", c.phototaxis_force);
  v.count("nest_wander_ticks", c.nest_wander_ticks);
  v.count("min_explore_ticks", c.min_explore_ticks);
  v.number("max_speed", c.drive.max_speed);
  v.degrees("soft_turn_max_deg", c.drive.soft_turn_max);
  v.number("hard_turn_speed", c.drive.hard_turn_speed);
}

/// DPO's own constants (its exploration is CRW's: visitCrwParameters).
template <typename V>
void visitDpoParameters(DpoConfig& c, V&& v) {
  v.number("pheromone_initial", c.pheromone_initial);
  v.number("pheromone_decay", c.pheromone_decay);
  v.number("new_place_distance", c.new_place_distance);
  v.number("exclusion_radius", c.exclusion_radius);
  v.number("arrival_tolerance", c.arrival_tolerance);
  v.number("slowing_radius", c.slowing_radius);
  v.number("vector_force", c.vector_force);
  v.number("slowing_speed_min", c.slowing_speed_min);
  v.count("collision_window", c.collision_window);
  v.number("recovery_max_offset", c.recovery_max_offset);
  v.number("recovery_heading_tolerance", c.recovery_heading_tolerance);
  v.count("recovery_spin_ticks", c.recovery_spin_ticks);
  v.number("recovery_spin_speed", c.recovery_spin_speed);
  v.count("recovery_straight_ticks", c.recovery_straight_ticks);
  v.number("recovery_straight_speed", c.recovery_straight_speed);
}

/// GP-DPO's task-allocation constants (its tasks behave like DPO: visitDpoParameters).
template <typename V>
void visitGpDpoParameters(GpDpoConfig& c, V&& v) {
  v.choice("estimates", c.time_varying, "ideal", "time_varying");
  v.number("ideal_generalist_min", c.ideal_generalist_min);
  v.number("ideal_generalist_max", c.ideal_generalist_max);
  v.number("ideal_subtask_min", c.ideal_subtask_min);
  v.number("ideal_subtask_max", c.ideal_subtask_max);
  v.number("ideal_partition_reactivity", c.ideal_partition_reactivity);
  v.number("varying_generalist_min", c.varying_generalist_min);
  v.number("varying_generalist_max", c.varying_generalist_max);
  v.number("varying_subtask_min", c.varying_subtask_min);
  v.number("varying_subtask_max", c.varying_subtask_max);
  v.number("varying_partition_reactivity", c.varying_partition_reactivity);
  v.number("ema_weight", c.ema_weight);
  v.number("partition_initial", c.partition_initial);
  v.number("subtask_reactivity", c.subtask_reactivity);
  v.number("subtask_offset", c.subtask_offset);
  v.number("abort_reactivity", c.abort_reactivity);
  v.number("abort_offset", c.abort_offset);
}

/// The sections of controller constants: "crw", "dpo", "gp_dpo".
const std::vector<std::string>& parameterSections();
/// The keys valid in one section; empty for an unknown section.
std::vector<std::string> parameterNames(const std::string& section);
/// The constants a kind runs with as canonical "section/name=value" words: crw's for crw, crw's and
/// dpo's for dpo, all three sections for gp_dpo. Equal text means equal behaviour.
std::string describeConstants(const std::string& kind, ControllerConfigs configs);

}  // namespace swarm_forage
