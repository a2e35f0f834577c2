#include "viaduct/study/sweep.hpp"

#include <chrono>
#include <memory>
#include <mutex>
#include <optional>

#include "viaduct/core/error.hpp"
#include "viaduct/core/thread_pool.hpp"

namespace viaduct::study {

namespace {
struct Prepared {
  std::optional<model::Structure> structure;
  std::vector<ResolvedStation> stations;
  std::string error;  // non-empty when the model could not be built
};
struct Case {
  std::size_t variant, train, speed;
};
struct CaseOutcome {
  std::vector<StationPeaks> peaks;
  std::string error;
  Index n_steps = 0;
  bool done = false;
};
}  // namespace

SweepResult run_sweep(const std::vector<Variant>& variants, const SweepOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  if (options.threads < 1) throw InputError("threads must be >= 1");
  const CaseRunner runner = options.runner ? options.runner : CaseRunner(simulate);

  SweepResult out;
  std::vector<Prepared> prepared(variants.size());
  std::vector<Case> cases;
  for (std::size_t v = 0; v < variants.size(); ++v) {
    const Scenario& sc = variants[v].scenario;
    try {
      prepared[v].structure = model::build_structure(sc.bridge, sc.track);
      prepared[v].stations = resolve_stations(*prepared[v].structure, sc.stations);
      out.summary.n_dofs.push_back(prepared[v].structure->n_dofs);
    } catch (const std::exception& e) {
      prepared[v].error = e.what();
      out.summary.n_dofs.push_back(0);
    }
    for (std::size_t t = 0; t < sc.trains.size(); ++t)
      for (std::size_t s = 0; s < sc.sweep_speeds.size(); ++s) cases.push_back({v, t, s});
  }

  std::vector<CaseOutcome> outcome(cases.size());
  std::mutex progress_mutex;
  std::size_t n_done = 0;
  parallel_for(cases.size(), options.threads, [&](std::size_t i, int) {
    const Case& c = cases[i];
    const Scenario& sc = variants[c.variant].scenario;
    CaseOutcome& o = outcome[i];
    if (!prepared[c.variant].error.empty()) {
      o.error = "model: " + prepared[c.variant].error;
    } else {
      try {
        const RunResult r = runner(*prepared[c.variant].structure, prepared[c.variant].stations,
                                   sc.trains[c.train], sc.sweep_speeds[c.speed], sc.settings);
        o.peaks = peaks(r);
        o.n_steps = r.summary.n_steps;
        o.done = true;
      } catch (const std::exception& e) {
        o.error = e.what();
      } catch (...) {
        o.error = "unknown error";
      }
    }
    if (options.progress) {
      std::lock_guard<std::mutex> lock(progress_mutex);
      options.progress(++n_done, cases.size());
    }
  });

  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const Scenario& sc = variants[c.variant].scenario;
    const std::string& vname = variants[c.variant].label;
    const std::string& tname = sc.trains[c.train].name;
    const double speed = sc.sweep_speeds[c.speed];
    if (!outcome[i].done) {
      out.failures.push_back({vname, tname, speed, outcome[i].error});
      continue;
    }
    out.summary.n_steps_total += outcome[i].n_steps;
    for (std::size_t s = 0; s < outcome[i].peaks.size(); ++s)
      out.rows.push_back({vname, tname, sc.stations[s].name, speed, outcome[i].peaks[s].max_abs_acc,
                          outcome[i].peaks[s].max_abs_disp});
  }
  out.summary.n_cases = cases.size();
  out.summary.n_failed = out.failures.size();
  out.summary.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace viaduct::study
