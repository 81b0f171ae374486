#pragma once
// The controller kinds of this process and of every plugin found (pluginlib), listed for scripts.
#include <iosfwd>

namespace swarm_forage {

/// Every controller kind as YAML (run_experiment --controllers; describeControllerKind's entries, sorted
/// by name): the built-ins, then each plugin found, loaded and described in a child process of its own,
/// so that one that is refused, throws or crashes is named on `err` ("controller plugin 'x' (its library)
/// crashed while being listed (signal 11, ...); left out") while the others are listed. Returns how
/// many were left out.
int listControllerKinds(std::ostream& out, std::ostream& err);

}  // namespace swarm_forage
