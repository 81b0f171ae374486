// Checkpoints of a run (docs/runs-and-bags.md, Checkpoints): save after a tick, resume, fork.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "swarm_forage/core/run/checkpoint.hpp"
#include "swarm_forage/core/run/model_version.hpp"
#include "swarm_forage/core/run/run.hpp"

namespace swarm_forage {

namespace {
/// A run's checkpoint words as (name, word), in order: a name=value word by its name within its section
/// (after "world:" or "controller:"), a word without '=' by itself.
std::vector<std::pair<std::string, std::string>> namedWords(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::pair<std::string, std::string>> out;
  std::string section;
  for (std::string w; in >> w;) {
    if (w.back() == ':')
      section = w + " ";
    else
      out.emplace_back(section + w.substr(0, w.find('=')), w);
  }
  return out;
}

/// The first word in which the checkpoint (`theirs`) and the parameters (`ours`) differ, the same name
/// paired on both sides: "the checkpoint has N=64 where the parameters give N=65"; "" when they agree.
std::string firstDifference(const std::string& theirs, const std::string& ours) {
  const auto a = namedWords(theirs), b = namedWords(ours);
  const auto find = [](const auto& words, const std::string& name) {
    return std::find_if(words.begin(), words.end(), [&](const auto& w) { return w.first == name; });
  };
  std::vector<std::string> names;  // every name, in the parameters' order, then the checkpoint's
  for (const auto* words : {&b, &a})
    for (const auto& w : *words)
      if (std::find(names.begin(), names.end(), w.first) == names.end()) names.push_back(w.first);
  for (const std::string& name : names) {
    const auto t = find(a, name), o = find(b, name);
    const std::string bare = name.substr(name.find(' ') + 1);  // without its section
    const std::string tw = t == a.end() ? "no " + bare : t->second,
                      ow = o == b.end() ? "no " + bare : o->second;
    if (tw != ow) return "the checkpoint has " + tw + " where the parameters give " + ow;
  }
  return "";
}

/// "" when `a` and `b` are one condition, as the world applies it and records name it.
bool sameCondition(const std::optional<ConditionSample>& a, const std::optional<ConditionSample>& b) {
  if (!a || !b) return !a && !b;
  return a->condition.normalized() == b->condition.normalized();
}

/// What the world does with V at a tick: V, and its target only when V moves anything (V = 0 is the same
/// world for every target).
void digestTick(uint64_t& h, const std::optional<ConditionSample>& c) {
  double v = c ? c->value : 0.0;
  if (v == 0) v = 0;  // -0 is 0
  uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  const uint64_t target = v != 0 ? static_cast<uint64_t>(c->condition.throttling(v).target) + 1 : 0;
  for (const uint64_t x : {bits, target}) h = (h ^ x) * 1099511628211ULL;
}
}  // namespace

std::string Run::checkpointWords() const {
  RunDescription d = description_;
  d.controller_constants = controllers_.constants();
  d.condition.reset();
  d.fixed = true;
  return d.key().describe() + " seed=" + std::to_string(world_.config().seed) +
         " run=" + std::to_string(description_.run) +
         " record_every=" + std::to_string(schedule_.record_every);
}

uint64_t Run::conditionDigest(uint64_t ticks) {
  uint64_t h = 1469598103934665603ULL;
  for (uint64_t t = 0; t < ticks; ++t) digestTick(h, environment_.condition(t));
  return h;
}

std::string Run::checkpoint() {
  StateArchive a;
  a.section("run");
  uint32_t version = kModelVersion;
  a.io(version);
  std::string who = checkpointWords();
  a.io(who);
  persistSample(a, description_.condition);
  uint64_t digest = conditionDigest(world_.tick()), tick = world_.tick();
  a.io(digest, tick);
  world_.persist(a);
  controllers_.persist(a);
  a.section("records");
  a.io(cache_state_.first, cache_state_.second);
  persistSample(a, recorded_condition_);
  for (RunSink* s : sinks_) s->save(a);
  return a.bytes();
}

void Run::resume(const std::string& payload, const std::string& file) {
  StateArchive a(payload);
  a.section("run");
  uint32_t version = 0;
  a.io(version);
  if (version != kModelVersion)
    throw ParameterError("resume: " + file + " was written by model version " + std::to_string(version) +
                         "; this build is model version " + std::to_string(kModelVersion) +
                         ", which would not continue it bit for bit");
  std::string who;
  a.io(who);
  controllers_.begin(description_, world_);  // the batch, and the constants the run reports
  if (const std::string differs = firstDifference(who, checkpointWords()); !differs.empty())
    throw ParameterError("resume: " + file + " is another run: " + differs +
                         " (a resumed run must be the checkpointed one, but for a fork's condition)");
  std::optional<ConditionSample> parent;
  persistSample(a, parent);
  uint64_t digest = 0, tick = 0;
  a.io(digest, tick);
  const std::optional<ConditionSample> own = environment_.condition(0);
  const bool fork = !sameCondition(parent, own);
  if (fork && conditionDigest(tick) != digest) {
    std::string where;
    if (parent && parent->condition.waveform != "series")
      for (uint64_t t = 0; t < tick && where.empty(); ++t) {
        uint64_t h1 = 0, h2 = 0;
        digestTick(h1, conditionAt(parent->condition, t, description_.world.ticks_per_second));
        digestTick(h2, environment_.condition(t));
        if (h1 != h2) where = " (first at tick " + std::to_string(t) + ")";
      }
    throw ParameterError("resume: the condition " + (own ? own->condition.label() : std::string("none")) +
                         " is no fork of " + file + ": its V differs from that of the checkpointed run (" +
                         (parent ? parent->condition.label() : std::string("none")) + ") before tick " +
                         std::to_string(tick) + where +
                         "; a fork must equal it up to the checkpoint, e.g. step_up at alpha forked from the "
                         "ideal run's checkpoint at alpha");
  }
  world_.persist(a);
  if (world_.tick() != tick) throw CheckpointError("the world is at tick " + std::to_string(world_.tick()));
  controllers_.persist(a);
  a.section("records");
  a.io(cache_state_.first, cache_state_.second);
  persistSample(a, recorded_condition_);
  description_.controller_constants = controllers_.constants();
  description_.condition = own;
  description_.fixed = true;
  std::vector<ConditionSample> records;  // a fork's: what a fresh run of it recorded before `tick`
  if (fork) {
    recorded_condition_.reset();
    for (uint64_t t = 0; t < tick; ++t)
      if (const auto c = environment_.condition(t); c && conditionChanged(*c, recorded_condition_))
        records.push_back(*c);
  }
  for (RunSink* s : sinks_) s->resume(a, description_, tick, fork ? &records : nullptr);
  if (a.remaining() != 0) throw CheckpointError(std::to_string(a.remaining()) + " bytes are left over");
  resumed_ = true;
}

}  // namespace swarm_forage
