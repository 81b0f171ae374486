#pragma once
// Joins the parts of one run's record: bags written in order by one run (its segments), appended to the
// BagWriter that continues the record. A chunk is copied as it is, compressed, unless a message in it is
// to be replaced; those chunks are decoded and their messages written again, in the order the bag holds
// them, so that every topic keeps its connection id and the record reads as one written without a break.
#include <ros/time.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "swarm_forage/record/bag_writer.hpp"

namespace swarm_forage {

/// Replacements of a record's messages (a resumed or forked run's tick-0 records).
struct Substitute {
  std::vector<std::string> topics;  // the topics it may replace: chunks holding none of them are copied
  /// write(topic, time, out): writes the replacement of the message into `out` and returns true, or false
  /// to keep the message.
  std::function<bool(const std::string&, const ros::Time&, BagWriter&)> write;
};

/// A join stopped by its stop flag (a signal).
struct JoinInterrupted : std::runtime_error {
  JoinInterrupted() : std::runtime_error("interrupted (signal)") {}
};

struct AppendCounts {
  uint64_t copied = 0, decoded = 0;  // chunks
};

/// Appends the messages of the bags `files`, in order, to `out`. Throws std::runtime_error naming a file
/// that is not a bag of format 2.0, and JoinInterrupted when `stop` is set (checked between chunks).
AppendCounts appendBags(const std::vector<std::string>& files, BagWriter& out, const Substitute& substitute,
                        const std::atomic<bool>* stop = nullptr);

/// The connections of a bag of format 2.0, by id: what a writer that continues its record adopts.
std::vector<BagWriter::ConnectionRecord> bagConnections(const std::string& file);

}  // namespace swarm_forage
