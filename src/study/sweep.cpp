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
  std::optional<PreparedModel> model;
  std::string error;  // non-empty when the model could not be built
};
// One job: a (variant, train, speed) case, or with unit-response superposition a (variant,
// speed) pair covering every train (train = kAllTrains).
constexpr std::size_t kAllTrains = static_cast<std::size_t>(-1);
// Peaks-kernel and Newmark variants take a block of kSpeedBlock speeds of one train per job
// (both kernels advance four cases in lock-step; two groups per job keep the jobs few but many
// enough to share between threads).
struct Job {
  std::size_t variant, train, speed, n_speeds = 1;
  bool batched = false;  // a block for the peaks kernel or batched Newmark
};
constexpr std::size_t kSpeedBlock = 8;
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
  const CaseRunner runner =
      options.runner ? options.runner
                     : CaseRunner([](const PreparedModel& m, const load::Train& t, double v, const RunSettings& rs) {
                         return simulate(m, t, v, rs);
                       });

  SweepResult out;
  std::vector<Prepared> prepared(variants.size());
  parallel_for(variants.size(), options.threads, [&](std::size_t v, int) {
    try {
      prepared[v].model = prepare_model(variants[v].scenario, /*rail_outputs=*/false);
    } catch (const std::exception& e) {
      prepared[v].error = e.what();
    }
  });
  // Modal variants run the fused peaks kernel on each train folded once over the model (a custom
  // runner opts out).
  std::vector<std::vector<std::shared_ptr<const solve::MovingChannels>>> folded(variants.size());
  std::vector<std::pair<std::size_t, std::size_t>> to_fold;
  for (std::size_t v = 0; v < variants.size(); ++v) {
    folded[v].resize(variants[v].scenario.trains.size());
    if (!options.runner && prepared[v].model && folds_trains(*prepared[v].model, variants[v].scenario.settings))
      for (std::size_t t = 0; t < folded[v].size(); ++t) to_fold.emplace_back(v, t);
  }
  parallel_for(to_fold.size(), options.threads, [&](std::size_t i, int) {
    const auto [v, t] = to_fold[i];
    const Scenario& sc = variants[v].scenario;
    try {
      folded[v][t] = fold_train(*prepared[v].model, sc.trains[t], sc.settings.load_factor);
    } catch (const std::exception&) {
      folded[v][t].reset();  // the case runs the general path and reports its own error
    }
  });

  std::vector<Job> jobs;
  std::size_t n_cases = 0;
  for (std::size_t v = 0; v < variants.size(); ++v) {
    const Scenario& sc = variants[v].scenario;
    out.summary.n_dofs.push_back(prepared[v].model ? prepared[v].model->structure.n_dofs : 0);
    out.summary.n_modes.push_back(prepared[v].model && prepared[v].model->modal ? prepared[v].model->modal->n_modes() : 0);
    const bool unit = sc.settings.superposition == Superposition::unit_response;
    // Newmark cases of one train run in batches of kNewmarkBatch speeds (a custom runner opts out).
    const bool newmark_batched = !options.runner && !unit && sc.settings.method == Method::newmark;
    for (std::size_t s = 0; s < sc.sweep_speeds.size(); ++s) {
      if (unit) jobs.push_back({v, kAllTrains, s});
      else
        for (std::size_t t = 0; t < sc.trains.size(); ++t) {
          if (!folded[v][t] && !newmark_batched) jobs.push_back({v, t, s});
          else if (s % kSpeedBlock == 0)
            jobs.push_back({v, t, s, std::min(kSpeedBlock, sc.sweep_speeds.size() - s), true});
        }
    }
    n_cases += sc.trains.size() * sc.sweep_speeds.size();
  }

  // outcome[job][train in job]
  std::vector<std::vector<CaseOutcome>> outcome(jobs.size());
  std::mutex progress_mutex;
  std::size_t n_done = 0;
  parallel_for(jobs.size(), options.threads, [&](std::size_t i, int) {
    const Job& c = jobs[i];
    const Scenario& sc = variants[c.variant].scenario;
    const std::size_t n_trains = c.train == kAllTrains ? sc.trains.size() : 1;
    const std::size_t n_out = std::max(n_trains, c.n_speeds);  // outcomes of this job
    auto& o = outcome[i];
    o.resize(n_out);
    auto fail_all = [&](const std::string& m) {
      for (auto& x : o) x.error = m;
    };
    if (!prepared[c.variant].error.empty()) {
      fail_all("model: " + prepared[c.variant].error);
    } else {
      const PreparedModel& pm = *prepared[c.variant].model;
      const double speed = sc.sweep_speeds[c.speed];
      auto take = [&](std::size_t k, const std::vector<StationPeaks>& p, Index n_steps) {
        o[k].peaks = p;
        o[k].n_steps = n_steps;
        o[k].done = true;
      };
      bool retry_alone = false;
      try {
        if (c.batched) {
          const auto first = sc.sweep_speeds.begin() + static_cast<std::ptrdiff_t>(c.speed);
          const std::vector<double> speeds(first, first + static_cast<std::ptrdiff_t>(c.n_speeds));
          const std::vector<CasePeaks> pr =
              simulate_peaks(pm, sc.trains[c.train], speeds, sc.settings, folded[c.variant][c.train].get());
          for (std::size_t k = 0; k < pr.size(); ++k) take(k, pr[k].peaks, pr[k].n_steps);
        } else if (c.train == kAllTrains) {
          const std::vector<RunResult> runs = simulate_by_unit_response(pm, sc.trains, speed, sc.settings);
          // A composed run shares one unit run: count its steps once.
          for (std::size_t k = 0; k < runs.size(); ++k) take(k, peaks(runs[k]), k > 0 ? 0 : runs[k].summary.n_steps);
        } else {
          const RunResult r = runner(pm, sc.trains[c.train], speed, sc.settings);
          take(0, peaks(r), r.summary.n_steps);
        }
      } catch (const std::exception& e) {
        fail_all(e.what());
        retry_alone = c.batched;
      } catch (...) {
        fail_all("unknown error");
        retry_alone = c.batched;
      }
      // A failing block: every speed again on its own, so only the failing ones are lost.
      if (retry_alone)
        for (std::size_t k = 0; k < c.n_speeds; ++k) {
          try {
            const RunResult r = runner(pm, sc.trains[c.train], sc.sweep_speeds[c.speed + k], sc.settings);
            o[k].error.clear();
            take(k, peaks(r), r.summary.n_steps);
          } catch (const std::exception& e) {
            o[k].error = e.what();
          } catch (...) {
            o[k].error = "unknown error";
          }
        }
    }
    if (options.progress) {
      std::lock_guard<std::mutex> lock(progress_mutex);
      for (std::size_t k = 0; k < n_out; ++k) options.progress(++n_done, n_cases);  // once per case
    }
  });

  // Rows in (variant, train, speed, station) order whatever the job layout.
  std::vector<std::vector<std::vector<const CaseOutcome*>>> at(variants.size());
  for (std::size_t v = 0; v < variants.size(); ++v)
    at[v].assign(variants[v].scenario.trains.size(),
                 std::vector<const CaseOutcome*>(variants[v].scenario.sweep_speeds.size(), nullptr));
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const Job& c = jobs[i];
    if (c.train == kAllTrains)
      for (std::size_t k = 0; k < outcome[i].size(); ++k) at[c.variant][k][c.speed] = &outcome[i][k];
    else
      for (std::size_t k = 0; k < c.n_speeds; ++k) at[c.variant][c.train][c.speed + k] = &outcome[i][k];
  }
  for (std::size_t v = 0; v < variants.size(); ++v) {
    const Scenario& sc = variants[v].scenario;
    const std::string& vname = variants[v].label;
    for (std::size_t t = 0; t < sc.trains.size(); ++t)
      for (std::size_t s = 0; s < sc.sweep_speeds.size(); ++s) {
        const CaseOutcome& o = *at[v][t][s];
        const std::string& tname = sc.trains[t].name;
        const double speed = sc.sweep_speeds[s];
        if (!o.done) {
          out.failures.push_back({vname, tname, speed, o.error});
          continue;
        }
        out.summary.n_steps_total += o.n_steps;
        for (std::size_t k = 0; k < o.peaks.size(); ++k)
          out.rows.push_back({vname, tname, sc.stations[k].name, speed, o.peaks[k].max_abs_acc, o.peaks[k].max_abs_disp});
      }
  }
  out.summary.n_cases = n_cases;
  out.summary.n_failed = out.failures.size();
  out.summary.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace viaduct::study
