#include "viaduct/study/sweep.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>

#include "viaduct/core/buffer.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/core/thread_pool.hpp"
#include "viaduct/study/influence.hpp"

namespace viaduct::study {

namespace {
struct Prepared {
  std::optional<PreparedModel> model;
  std::string error;  // non-empty when the model could not be built
  bool input_error = false;  // ... because the input is wrong (InputError)
  std::vector<std::vector<EffectPeak>> quasi_static;  // with load effects: per train, per quantity
  // With load effects: the model's influence lines, until every train's quasi-static extremes
  // are in (they run as tasks after the jobs: Sweep::quasi_static_task).
  std::optional<InfluenceLines> il;
  std::vector<std::string> qs_error;  // per train: why its quasi-static extremes failed (empty: none)
  std::vector<char> qs_input;         // ... because the input is wrong
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
// Inside a catch block: the exception's message and whether the input was at fault (InputError).
void describe_failure(std::string& error, bool& input_error) {
  try {
    throw;
  } catch (const InputError& e) {
    error = e.what();
    input_error = true;
  } catch (const std::exception& e) {
    error = e.what();
    input_error = false;
  } catch (...) {
    error = "unknown error";
    input_error = false;
  }
}

struct CaseOutcome {
  std::vector<StationPeaks> peaks;
  std::vector<EffectPeak> quantities;  // with load effects
  VehiclePeaks vehicle;                // with vehicle models
  std::string error;
  bool input_error = false;  // the error is the input's (InputError), not the computation's
  Index n_steps = 0;
  bool done = false;
};

// The stages of a sweep: models (and folded trains) per variant, jobs, their outcomes, rows.
class Sweep {
 public:
  Sweep(const std::vector<Variant>& variants, const SweepOptions& options)
      : variants_(variants), options_(options), prepared_(variants.size()), folded_(variants.size()) {
    std::size_t first = 0;
    first_case_.resize(variants.size());
    for (std::size_t v = 0; v < variants.size(); ++v)
      for (std::size_t t = 0; t < variants[v].scenario.trains.size(); ++t) {
        first_case_[v].push_back(first);
        first += speeds(v, t).size();
      }
    runner_ = options.runner ? options.runner
                             : CaseRunner([](const PreparedModel& m, const load::Train& t, double v, const RunSettings& rs) {
                                 return simulate(m, t, v, rs);
                               });
  }

  SweepResult run() {
    const BlockReuse reuse;  // the folded trains' tables, freed and allocated train after train
    prepare();
    plan();
    outcome_.resize(jobs_.size());
    // The jobs, then each train's quasi-static extremes (speed-independent, a few milliseconds
    // each: last, they fill the threads' ends instead of running on one thread before the jobs).
    parallel_for(jobs_.size() + qs_tasks_.size(), options_.threads, [&](std::size_t i, int) {
      if (i < jobs_.size()) run_job(i);
      else quasi_static_task(qs_tasks_[i - jobs_.size()]);
    });
    return collect();
  }

 private:
  // Each variant's model once, in parallel; modal variants fold each train once over it for the
  // peaks kernel (a custom runner opts out).
  void prepare() {
    parallel_for(variants_.size(), options_.threads, [&](std::size_t v, int) {
      if (!variant_in_range(v)) return;  // another shard's: not built
      if (!variants_[v].error.empty()) {
        prepared_[v].error = variants_[v].error;
        prepared_[v].input_error = true;  // a factor that breaks its key's rule
        return;
      }
      try {
        const Scenario& sc = variants_[v].scenario;
        prepared_[v].model = prepare_model(sc, /*rail_outputs=*/false, options_.load_effects);
        if (options_.load_effects) {
          prepared_[v].il = influence_lines(*prepared_[v].model);
          prepared_[v].quasi_static.resize(sc.trains.size());
          prepared_[v].qs_error.resize(sc.trains.size());
          prepared_[v].qs_input.resize(sc.trains.size(), 0);
        }
      } catch (...) {
        describe_failure(prepared_[v].error, prepared_[v].input_error);
        prepared_[v].error = "model: " + prepared_[v].error;
      }
    });
    // The trains to fold; each is folded by the first of its jobs to run and freed after its last
    // (a table is 4 × channels × pieces numbers: 51 MB for one train on Old Guadiana with track).
    for (std::size_t v = 0; v < variants_.size(); ++v) {
      folded_[v].resize(variants_[v].scenario.trains.size());
      if (!options_.runner && prepared_[v].model && folds_trains(*prepared_[v].model, variants_[v].scenario.settings))
        for (std::size_t t = 0; t < folded_[v].size(); ++t)
          if (train_in_range(v, t)) folded_[v][t] = std::make_unique<FoldedTrain>();
    }
  }

  // The folded table of job c's train (null: not folded, or its folding failed: the cases then run
  // the general path, which reports their own errors). The first job to need it starts the fold;
  // every job that needs it before it is done fills chunks of it too (TrainFold), then waits for
  // the last chunk: two threads starting on one train fold it together (on Old Guadiana one
  // thread waited 1.1 s for the 22 folds).
  std::shared_ptr<const solve::MovingChannels> folded_table(const Job& c) const {
    FoldedTrain* f = c.train == kAllTrains ? nullptr : folded_[c.variant][c.train].get();
    if (!f) return nullptr;
    std::unique_lock<std::mutex> lock(f->m);
    if (!f->tried) {
      f->tried = true;
      const Scenario& sc = variants_[c.variant].scenario;
      try {
        f->fold = std::make_unique<TrainFold>(*prepared_[c.variant].model, sc.trains[c.train], sc.settings.load_factor);
      } catch (const std::exception&) {
        f->fold.reset();
      }
    }
    if (!f->fold) return f->table;
    TrainFold* fold = f->fold.get();  // alive while a thread fills chunks of it (`filling`)
    const std::size_t n = fold->n_chunks();
    ++f->filling;
    lock.unlock();
    std::size_t mine = 0;
    for (std::size_t k = f->next.fetch_add(1); k < n; k = f->next.fetch_add(1), ++mine) fold->fill(k);
    lock.lock();
    f->filled += mine;
    // The last thread out, once every chunk is in, hands the table over and frees the fold.
    if (--f->filling == 0 && f->filled == n) {
      f->table = fold->table();
      f->fold.reset();
      f->filled_all.notify_all();
    } else {
      f->filled_all.wait(lock, [f] { return !f->fold; });
    }
    return f->table;
  }
  // Job c is done with its train's table: the last of them frees it.
  void release_table(const Job& c) {
    FoldedTrain* f = c.batched && c.train != kAllTrains ? folded_[c.variant][c.train].get() : nullptr;
    if (!f) return;
    std::lock_guard<std::mutex> lock(f->m);
    if (f->jobs_left > 0 && --f->jobs_left == 0) f->table.reset();
  }

  // Jobs: single cases, blocks of speeds of one train (peaks kernel, batched Newmark), or a
  // speed with every train (unit-response superposition).
  void plan() {
    for (std::size_t v = 0; v < variants_.size(); ++v) {
      const Scenario& sc = variants_[v].scenario;
      summary_.n_dofs.push_back(prepared_[v].model ? prepared_[v].model->structure.n_dofs : 0);
      summary_.n_modes.push_back(prepared_[v].model && prepared_[v].model->modal ? prepared_[v].model->modal->n_modes() : 0);
      // Unit-response runs record no load effects: a sweep that keeps them runs every case.
      // Nor does it take a speed list per train.
      const bool unit = sc.settings.superposition == Superposition::unit_response && !options_.load_effects &&
                        variants_[v].train_speeds.empty();
      // Newmark cases of one train run in batches of speeds (a custom runner opts out).
      const bool newmark_batched = !options_.runner && !unit && solve::method_traits(sc.settings.method).batches_histories;
      if (unit) {
        for (std::size_t s = 0; s < sc.sweep_speeds.size(); ++s) {
          const std::size_t in = kept_in_job({v, kAllTrains, s});
          if (in > 0) jobs_.push_back({v, kAllTrains, s});
          n_cases_ += in;
        }
        continue;
      }
      for (std::size_t t = 0; t < sc.trains.size(); ++t) {
        const std::size_t n = speeds(v, t).size();
        for (std::size_t s = 0; s < n; ++s) {
          Job job{v, t, s};
          if (folded_[v][t] || newmark_batched) {
            if (s % kSpeedBlock != 0) continue;
            job = {v, t, s, std::min(kSpeedBlock, n - s), true};
          }
          const std::size_t in = kept_in_job(job);
          if (in > 0) jobs_.push_back(job);
          if (in > 0 && job.batched && folded_[v][t]) ++folded_[v][t]->jobs_left;
          n_cases_ += in;
        }
      }
    }
    // Each train's quasi-static extremes, for the variants with load effects (a train of another
    // shard's: not needed).
    qs_left_.assign(variants_.size(), 0);
    for (std::size_t v = 0; v < variants_.size(); ++v)
      if (prepared_[v].il)
        for (std::size_t t = 0; t < variants_[v].scenario.trains.size(); ++t)
          if (train_in_range(v, t)) qs_tasks_.emplace_back(v, t), ++qs_left_[v];
    for (std::size_t v = 0; v < variants_.size(); ++v)
      if (qs_left_[v] == 0) prepared_[v].il.reset();
  }

  // Train t's quasi-static extremes over variant v's model (its influence lines freed after the
  // last train's).
  void quasi_static_task(const std::pair<std::size_t, std::size_t>& vt) {
    Prepared& p = prepared_[vt.first];
    const Scenario& sc = variants_[vt.first].scenario;
    try {
      p.quasi_static[vt.second] = static_extremes(*p.il, sc.trains[vt.second], sc.settings.load_factor);
    } catch (...) {  // a body must not throw: the variant's cases fail in collect(), as a model's would
      bool input = false;
      describe_failure(p.qs_error[vt.second], input);
      p.qs_input[vt.second] = input ? 1 : 0;
    }
    std::lock_guard<std::mutex> lock(progress_mutex_);
    if (--qs_left_[vt.first] == 0) p.il.reset();
  }

  void run_job(std::size_t i) {
    const Job& c = jobs_[i];
    const Scenario& sc = variants_[c.variant].scenario;
    const std::size_t n_trains = c.train == kAllTrains ? sc.trains.size() : 1;
    const std::size_t n_out = std::max(n_trains, c.n_speeds);  // outcomes of this job
    auto& o = outcome_[i];
    o.resize(n_out);
    auto fail_all = [&](const std::string& m, bool input) {
      for (auto& x : o) x.error = m, x.input_error = input;
    };
    if (options_.cancel && options_.cancel->load()) {
      fail_all("cancelled", false);
    } else if (!prepared_[c.variant].error.empty()) {
      fail_all(prepared_[c.variant].error, prepared_[c.variant].input_error);
    } else {
      const PreparedModel& pm = *prepared_[c.variant].model;
      bool retry_alone = false;
      try {
        run_cases(c, pm, o);
      } catch (...) {
        std::string why;
        bool input = false;
        describe_failure(why, input);
        fail_all(why, input);
        retry_alone = c.batched;
      }
      // A failing block: every speed again on its own, so only the failing ones are lost.
      if (retry_alone)
        for (std::size_t k = 0; k < c.n_speeds; ++k) {
          try {
            const RunResult r = runner_(pm, sc.trains[c.train], speeds(c.variant, c.train)[c.speed + k], sc.settings);
            o[k].error.clear();
            take(o[k], pm, r);
          } catch (...) {
            describe_failure(o[k].error, o[k].input_error);
          }
        }
    }
    release_table(c);
    if (options_.progress) {
      std::lock_guard<std::mutex> lock(progress_mutex_);
      for (std::size_t k = kept_in_job(c); k > 0; --k) options_.progress(++n_done_, n_cases_);  // once per kept case
    }
  }

  // The cases of one job through the engine (study/simulation.hpp).
  void run_cases(const Job& c, const PreparedModel& pm, std::vector<CaseOutcome>& o) const {
    const Scenario& sc = variants_[c.variant].scenario;
    const double speed = c.train == kAllTrains ? sc.sweep_speeds[c.speed] : speeds(c.variant, c.train)[c.speed];
    if (c.batched) {
      const auto first = speeds(c.variant, c.train).begin() + static_cast<std::ptrdiff_t>(c.speed);
      const std::vector<double> speeds(first, first + static_cast<std::ptrdiff_t>(c.n_speeds));
      const std::shared_ptr<const solve::MovingChannels> table = folded_table(c);
      const std::vector<CasePeaks> pr = simulate_peaks(pm, sc.trains[c.train], speeds, sc.settings, table.get());
      for (std::size_t k = 0; k < pr.size(); ++k) {
        take(o[k], pr[k].peaks, pr[k].n_steps);
        o[k].quantities = pr[k].quantities;
        o[k].vehicle = pr[k].vehicle;
      }
    } else if (c.train == kAllTrains) {
      const std::vector<RunResult> runs = simulate_by_unit_response(pm, sc.trains, speed, sc.settings);
      // A composed run shares one unit run: count its steps once.
      for (std::size_t k = 0; k < runs.size(); ++k) take(o[k], peaks(runs[k]), k > 0 ? 0 : runs[k].summary.n_steps);
    } else {
      take(o[0], pm, runner_(pm, sc.trains[c.train], speed, sc.settings));
    }
  }

  // A case run with histories: its peaks, and its quantities' extremes when the model has load effects.
  static void take(CaseOutcome& o, const PreparedModel& pm, const RunResult& r) {
    take(o, peaks(r), r.summary.n_steps);
    if (!pm.effects.empty()) o.quantities = quantity_peaks(pm, r);
    o.vehicle = vehicle_peaks(r);
  }

  // Whether case s of train t of variant v is in the range the sweep reports (a shard's part).
  bool in_range(std::size_t v, std::size_t t, std::size_t s) const {
    const std::size_t i = first_case_[v][t] + s;
    return i >= options_.case_begin && i < options_.case_end;
  }
  bool train_in_range(std::size_t v, std::size_t t) const {
    const std::size_t n = speeds(v, t).size();
    return n > 0 && first_case_[v][t] < options_.case_end && first_case_[v][t] + n > options_.case_begin;
  }
  bool variant_in_range(std::size_t v) const {
    for (std::size_t t = 0; t < variants_[v].scenario.trains.size(); ++t)
      if (train_in_range(v, t)) return true;
    return false;
  }
  // The cases of a job that the sweep reports.
  std::size_t kept_in_job(const Job& c) const {
    std::size_t n = 0;
    if (c.train == kAllTrains) {
      for (std::size_t t = 0; t < variants_[c.variant].scenario.trains.size(); ++t) n += in_range(c.variant, t, c.speed);
    } else {
      for (std::size_t k = 0; k < c.n_speeds; ++k) n += in_range(c.variant, c.train, c.speed + k);
    }
    return n;
  }

  // The speeds of train t of variant v: its own list, or the scenario's.
  const std::vector<double>& speeds(std::size_t v, std::size_t t) const {
    const Variant& x = variants_[v];
    return x.train_speeds.empty() ? x.scenario.sweep_speeds : x.train_speeds[t];
  }

  static void take(CaseOutcome& o, const std::vector<StationPeaks>& p, Index n_steps) {
    o.peaks = p;
    o.n_steps = n_steps;
    o.done = true;
  }

  // Rows in (variant, train, speed, station) order whatever the job layout.
  SweepResult collect() {
    SweepResult out;
    out.summary = summary_;
    std::vector<std::vector<std::vector<const CaseOutcome*>>> at(variants_.size());  // null: not run
    for (std::size_t v = 0; v < variants_.size(); ++v)
      for (std::size_t t = 0; t < variants_[v].scenario.trains.size(); ++t)
        at[v].emplace_back(speeds(v, t).size(), nullptr);
    for (std::size_t i = 0; i < jobs_.size(); ++i) {
      const Job& c = jobs_[i];
      if (c.train == kAllTrains)
        for (std::size_t k = 0; k < outcome_[i].size(); ++k) at[c.variant][k][c.speed] = &outcome_[i][k];
      else
        for (std::size_t k = 0; k < c.n_speeds; ++k) at[c.variant][c.train][c.speed + k] = &outcome_[i][k];
    }
    // The tables' rows reserved at once (281 000 quantity rows for 31 stations' load effects:
    // their growth's copies were 2 % of that sweep).
    std::size_t n_rows = 0, n_quantities = 0;
    for (const auto& job : outcome_)
      for (const CaseOutcome& o : job) n_rows += o.peaks.size(), n_quantities += o.quantities.size();
    out.rows.reserve(n_rows);
    out.quantities.reserve(n_quantities);
    for (std::size_t v = 0; v < variants_.size(); ++v) {
      const Scenario& sc = variants_[v].scenario;
      const std::string& vname = variants_[v].label;
      const Prepared& p = prepared_[v];
      const std::vector<std::string> names = p.quasi_static.empty() ? std::vector<std::string>{} : quantity_names(*p.model);
      // A train's quasi-static extremes that failed fail the variant's every case, as its model's
      // failure does (the first such train's reason).
      std::size_t qs_failed = p.qs_error.size();
      for (std::size_t t = 0; t < p.qs_error.size() && qs_failed == p.qs_error.size(); ++t)
        if (!p.qs_error[t].empty()) qs_failed = t;
      for (std::size_t t = 0; t < sc.trains.size(); ++t)
        for (std::size_t s = 0; s < speeds(v, t).size(); ++s) {
          if (!in_range(v, t, s)) continue;
          const CaseOutcome& o = *at[v][t][s];
          const std::string& tname = sc.trains[t].name;
          const double speed = speeds(v, t)[s];
          if (qs_failed < p.qs_error.size()) {
            out.failures.push_back({vname, tname, speed, "model: " + p.qs_error[qs_failed], p.qs_input[qs_failed] != 0});
            continue;
          }
          if (!o.done) {
            out.failures.push_back({vname, tname, speed, o.error, o.input_error});
            out.summary.cancelled = out.summary.cancelled || o.error == "cancelled";
            continue;
          }
          out.summary.n_steps_total += o.n_steps;
          for (std::size_t k = 0; k < o.peaks.size(); ++k)
            out.rows.push_back({vname, tname, sc.stations[k].name, speed, o.peaks[k].max_abs_acc, o.peaks[k].max_abs_disp});
          for (std::size_t q = 0; q < o.quantities.size() && q < names.size(); ++q)
            out.quantities.push_back({vname, tname, names[q], speed, o.quantities[q], p.quasi_static[t][q]});
          if (o.vehicle.present) out.vehicles.push_back({vname, tname, speed, o.vehicle});
        }
    }
    out.summary.n_cases = n_cases_;
    out.summary.n_failed = out.failures.size();
    return out;
  }

  const std::vector<Variant>& variants_;
  const SweepOptions& options_;
  CaseRunner runner_;
  std::vector<Prepared> prepared_;
  // One train folded over one variant's model: built by its first job, freed after its last.
  struct FoldedTrain {
    std::mutex m;
    std::condition_variable filled_all;  // the fold's last chunk is in: `table` is set
    bool tried = false;
    std::unique_ptr<TrainFold> fold;     // while its chunks are being filled
    std::atomic<std::size_t> next{0};    // the next chunk a thread takes
    std::size_t filled = 0;              // chunks filled (under m)
    std::size_t filling = 0;             // threads filling chunks (under m)
    std::shared_ptr<const solve::MovingChannels> table;
    std::size_t jobs_left = 0;  // batched jobs not yet done
  };
  std::vector<std::vector<std::unique_ptr<FoldedTrain>>> folded_;  // [variant][train], null: not folded
  std::vector<std::vector<std::size_t>> first_case_;  // [variant][train]: its first case's index in the sweep
  std::vector<Job> jobs_;
  std::vector<std::pair<std::size_t, std::size_t>> qs_tasks_;  // (variant, train) quasi-static extremes to compute
  std::vector<std::size_t> qs_left_;  // per variant: its trains' quasi-static tasks not yet done (under progress_mutex_)
  std::vector<std::vector<CaseOutcome>> outcome_;  // [job][case in job]
  SweepSummary summary_;
  std::size_t n_cases_ = 0, n_done_ = 0;
  std::mutex progress_mutex_;
};

}  // namespace

SweepResult run_sweep(const std::vector<Variant>& variants, const SweepOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  if (options.threads < 1) throw InputError("threads must be >= 1");
  for (const auto& v : variants)
    if (!v.train_speeds.empty() && v.train_speeds.size() != v.scenario.trains.size())
      throw InputError("variant '" + v.label + "': " + std::to_string(v.train_speeds.size()) + " speed lists for " +
                       std::to_string(v.scenario.trains.size()) + " trains");
  SweepResult out = Sweep(variants, options).run();
  out.summary.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

std::size_t count_cases(const std::vector<Variant>& variants) {
  std::size_t n = 0;
  for (const auto& v : variants)
    for (std::size_t t = 0; t < v.scenario.trains.size(); ++t)
      n += (v.train_speeds.empty() ? v.scenario.sweep_speeds : v.train_speeds[t]).size();
  return n;
}

double QuantityRow::phi_dyn() const {
  const double st = quasi_static.max_abs();
  return st > 0.0 ? dynamic.max_abs() / st - 1.0 : std::numeric_limits<double>::quiet_NaN();
}

std::vector<GoverningRow> governing(const std::vector<EnvelopeRow>& rows) {
  std::vector<GoverningRow> out;
  auto take = [](GoverningCase& g, double v, const EnvelopeRow& r, bool first) {
    if (first || v > g.value) g = {v, r.variant, r.train, r.speed};
  };
  for (const auto& r : rows) {
    auto it = std::find_if(out.begin(), out.end(), [&](const GoverningRow& g) { return g.station == r.station; });
    const bool first = it == out.end();
    if (first) {
      out.push_back({r.station, {}, {}});
      it = out.end() - 1;
    }
    take(it->acc, r.max_abs_acc, r, first);
    take(it->disp, r.max_abs_disp, r, first);
  }
  return out;
}

}  // namespace viaduct::study
