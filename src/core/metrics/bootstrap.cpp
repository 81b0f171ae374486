#include "swarm_forage/core/metrics/bootstrap.hpp"

#include <algorithm>
#include <sstream>
#include <vector>

#include "swarm_forage/core/util/worker_pool.hpp"

namespace swarm_forage {

namespace {
std::string cell(bool defined, double v) { return defined ? numberText(v, /*exact=*/true) : std::string(); }

void rows(std::ostream& out, const RunLibrary& library, uint32_t draw, Definitions defs,
          std::optional<std::size_t> band) {
  for (const auto& [key, group] : library.groups()) {
    if (!group.valid || group.mean.P.empty()) continue;
    const RunEvaluation ev = evaluateRun(library, key, group.mean, /*final=*/true, defs, band);
    const bool varied = !key.environment.ideal();
    out << draw << ',' << key.controller << ',' << key.arena << ',' << key.environment.waveform << ','
        << numberText(key.environment.beta) << ',' << csvQuoted(key.environment.label()) << ','
        << key.swarm_size << ',' << group.runs << ',' << numberText(group.mean.P.back(), true) << ','
        << cell(key.swarm_size > 1 && ev.scalability_status.valid, ev.scalability.e.value) << ','
        << cell(key.swarm_size > 1 && ev.self_organization_status.valid, ev.self_organization.z_mean.value)
        << ',' << cell(varied && ev.reactivity_status.valid, ev.reactivity.distance.value) << ','
        << cell(varied && ev.adaptability_status.valid, ev.adaptability.distance.value) << ','
        << key.setup.interval << ',' << key.identity() << '\n';
  }
}
}  // namespace

std::string bootstrapCsv(const RunLibrary& library, Definitions defs, std::optional<std::size_t> band,
                         const BootstrapOptions& options) {
  std::ostringstream out;
  out << "draw,controller,arena,waveform,beta,environment,N,runs,P,e,Z,R,A,sample_interval,identity\n";
  rows(out, library, 0, defs, band);
  // Each draw has its own counter-based stream (RunLibrary::resampled): draws run on every core, a batch
  // at a time, and are written in draw order, so the file does not depend on the thread count.
  WorkerPool pool(0);
  const uint32_t batch = 16 * pool.threads();
  std::vector<std::string> text(batch);
  for (uint32_t first = 1; first <= options.draws; first += batch) {
    const uint32_t count = std::min(batch, options.draws - first + 1);
    pool.run(count, [&](std::size_t i, unsigned) {
      std::ostringstream o;
      const uint32_t draw = first + static_cast<uint32_t>(i);
      rows(o, library.resampled(options.seed, draw), draw, defs, band);
      text[i] = o.str();
    });
    for (uint32_t i = 0; i < count; ++i) out << text[i];
  }
  return out.str();
}

}  // namespace swarm_forage
