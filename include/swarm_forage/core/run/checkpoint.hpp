#pragma once
// Checkpoint files (docs/runs-and-bags.md, Checkpoints): a run's whole state after a tick, as written by
// Run::checkpoint(), in a versioned file with a magic header and a checksum, written atomically.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "swarm_forage/core/run/condition.hpp"
#include "swarm_forage/core/run/run_records.hpp"
#include "swarm_forage/core/util/state_archive.hpp"

namespace swarm_forage {

/// The layout of the state inside a checkpoint; a file of another layout is refused.
/// 2: the bag as a list of segment files (BagSink::save), no longer the whole bag's bytes.
constexpr uint32_t kCheckpointFormat = 2;

/// FNV-1a 64 of `n` bytes at `p`, continuing from `h`: the checksum of checkpoint files and of the bag
/// segments they name.
uint64_t fnv1a64(const char* p, std::size_t n, uint64_t h = 1469598103934665603ULL);
/// fnv1a64 of a file's bytes; `size` gets their count. Throws CheckpointError when it cannot be read.
uint64_t fileChecksum(const std::string& path, uint64_t& size);
/// fsync of a file and of its folder (a checkpoint may name it only once both are on disk); throws
/// std::runtime_error naming the path.
void syncFile(const std::string& path);

/// Writes `payload` to `path` atomically: PATH.tmp, fsync, rename, fsync of the folder, so that a crash or
/// a kill while writing leaves the previous file whole. Throws std::runtime_error naming the path.
/// Test hook (test/graph/check_checkpoint.py): with SWARM_FORAGE_CHECKPOINT_DIE_AFTER=N in the environment,
/// the process kills itself (SIGKILL) after N bytes of the temporary file are on disk, on its second write.
void writeCheckpointFile(const std::string& path, const std::string& payload);
/// The payload of a checkpoint file, its magic, format, length and checksum verified; throws
/// CheckpointError saying what is wrong ("PATH is truncated", "... checksum ...").
std::string readCheckpointFile(const std::string& path);

/// Saves or loads a condition (its fields; a series by its digest, without its rows).
void persistCondition(StateArchive& a, Condition& c);
/// Saves or loads an optional condition sample.
void persistSample(StateArchive& a, std::optional<ConditionSample>& s);

}  // namespace swarm_forage
