// viaduct fit: scenario parameters fitted to measured records and identified modes.
#include <chrono>
#include <cmath>
#include <cstdio>

#include "cli.hpp"
#include "viaduct/io/fit.hpp"
#include "viaduct/io/record.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/study/fit.hpp"

namespace viaduct::cli {

namespace {

std::string fit_fmt(double v) { return format_number(v, 10); }

}  // namespace

Command fit_command() {
  Command c = record_command("fit", "SCENARIO", "model updating: fit scenario parameters to measured records and identified modes");
  const auto declare = [](po::options_description& d, io::FitRequest& q) {
    d.add_options()("param", list_value(q.params),
                    "KEY=LO:HI[:log|linear]: a numeric scenario key to fit within bounds, starting from its scenario value (repeatable; replaces [[fit.params]])")(
        "record", list_value(q.records),
        "record (CSV, UFF or .mat) to fit (repeatable; replaces [[fit.records]]); every --map applies to every --record")(
        "map", list_value(q.maps),
        "CHANNEL=STATION: record channel fitted by a scenario station; also RESPONSE=STATION for identified shapes (repeatable)")(
        "speed-kmh", po::value<std::vector<double>>(&q.speeds_kmh)->composing(),
        "speed of the passages [km/h]: one for all records or one per --record (default: run.speed_kmh)")(
        "train", po::value<std::string>(&q.train), "train of the passages (default: the first of train.files)")(
        "modes", optional_value(q.modes), "identified modes for the modal and damping objectives: modal-fit output (directory or modes.csv, shapes.csv beside it) or decay output (directory or decay_summary.csv)")(
        "modes-method", optional_value(q.modes_method), "rows of modes.csv to fit: lscf (default), circle-fit or peak-picking")(
        "weight", list_value(q.weights),
        "OBJECTIVE=W with OBJECTIVE time, peak, envelope, spectrum, modal or damping (repeatable; default time=1 with records, modal=1 with --modes)")(
        "starts", optional_value(q.starts), "solver starts: the scenario's values, then quasi-random points in the bounds (default 1)")(
        "no-spectral-start", po::bool_switch(&q.no_spectral_start), "skip the spectral pre-stage of each start (fit.spectral_start = false)")(
        "max-iterations", optional_value(q.max_iterations), "iterations per start (default 50)")(
        "max-time-s", optional_value(q.max_time_s), "wall time per start [s] (default 600)");
    add_zero_option(d, q.zero);
  };
  c.usage_and_samples =
      "Fits numeric scenario keys so that the model reproduces measured accelerations (or\n"
      "deflections, or strains at stations[].fibre_m) and identified modes: Levenberg-Marquardt with bounds (Ceres), logarithmic\n"
      "coordinates for positive keys, forward-difference Jacobians in parallel (--threads), a\n"
      "time shift per record fitted with the parameters. Objectives (--weight): time = filtered,\n"
      "aligned time histories; peak = peak and RMS per channel; envelope = windowed RMS; spectrum =\n"
      "amplitude spectra over the filter band; modal = frequencies and mode shapes (MAC) from\n"
      "viaduct modal-fit. Parameters, records and weights may also be declared in the scenario's\n"
      "[fit] section (docs/fitting.md). Writes OUT/fit.csv (estimates, standard errors, flags),\n"
      "fit_correlation.csv, fit.toml, fitted.toml (the scenario with the fitted values),\n"
      "fit_trace.csv, fit_residuals.csv, fit_time.csv, fit_modes.csv and manifest.toml; plot with\n"
      "scripts/plot/plot_fit.py OUT. Exit 1 when the fit did not converge (the outputs say why).\n\n"
      "The first two samples use the outputs of the samples of viaduct run and modal-fit.\n\n"
      "Sample runs:\n"
      "  viaduct fit scenarios/hslm-simply-supported.toml --record out/a4/history.csv --map mid_acc_mps2=mid --train HSLM-A4 --speed-kmh 300 --param bridge.EI=5e9:1e10 --param bridge.damping.ratio=0.005:0.05 --set bridge.EI=7e9 --set bridge.damping.ratio=0.02 --out out/fit-hslm\n"
      "  viaduct fit scenarios/hslm-simply-supported.toml --modes out/fit-sweep --param bridge.EI=5e9:1e10 --set bridge.EI=7e9 --out out/fit-modes\n"
      "  viaduct fit scenarios/old-guadiana-talgo.toml --record data/records/og-calibration.csv --map S1_mid_acc=S1_mid --map S2_mid_acc=S2_mid --param bridge.EI=5e9:1e10 --param track.pad.k=2e7:1e9 --param bridge.damping.ratio1=0.01:0.06 --threads 2 --out out/fit-og\n";
  const auto body = [](const Common& o, const io::FitRequest& request) {
    const auto t0 = std::chrono::steady_clock::now();
    const io::FlatScenario flat = load_scenario(o);
    io::FitRequest q = request;
    q.threads = o.threads;
    q.read = o.read;
    q.on_read = [&o](const std::string& path, const io::ImportReport& rep) { print_import_report(path, rep, o); };
    auto [problem, opt] = io::fit_setup(flat, q);
    if (!o.quiet)
      opt.progress = [&problem = problem](const study::FitTracePoint& tp) {
        std::fprintf(stderr, "  start %d %s iteration %2d: cost %.6e ", tp.start + 1, tp.stage == 1 ? "spectral" : "fit     ",
                     tp.iteration, tp.cost);
        for (std::size_t i = 0; i < tp.values.size(); ++i)
          std::fprintf(stderr, " %s=%.5g", problem.params[i].key.c_str(), tp.values[i]);
        std::fprintf(stderr, "\n");
      };
    if (!o.quiet)
      std::printf("fitting %zu parameters to %zu record(s)%s (%d thread(s), %d start(s))\n", problem.params.size(),
                  problem.records.size(), problem.modal ? " and identified modes" : "", opt.threads, opt.starts);
    std::fflush(stdout);
    const study::FitResult r = study::fit(problem, opt);
    make_out_dir(o.out);
    io::write_fit_outputs(o.out, o.scenario, flat, problem, opt, r);
    io::Manifest m = start_manifest(o, "fit");
    m.inputs = q.records;
    if (q.modes) m.inputs.push_back(*q.modes);
    m.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    m.extra = {{"status", "\"" + std::string(study::to_string(r.status)) + "\""}, {"fit_wall_s", fit_fmt(r.wall_s)}};
    io::write_manifest(o.out + "/manifest.toml", m, flat);
    if (!o.quiet) {
      std::printf("\n%s after %d iterations, %d simulations, %.1f s: %s\ncost %.6e -> %.6e\n\n", study::to_string(r.status),
                  r.iterations, r.simulations, r.wall_s, r.message.c_str(), r.cost_initial, r.cost_final);
      std::printf("%-28s %13s %13s %13s %9s  %s\n", "key", "initial", "estimate", "std error", "rel [%]", "");
      for (std::size_t i = 0; i < problem.params.size() && !r.std_error.empty(); ++i) {
        const double ref = std::abs(r.estimate[i]) > 0 ? std::abs(r.estimate[i]) : 1.0;
        std::printf("%-28s %13.6g %13.6g %13.4g %9.3g  %s\n", problem.params[i].key.c_str(), problem.params[i].initial,
                    r.estimate[i], r.std_error[i], 100 * r.std_error[i] / ref, r.determined[i] ? "" : "(flagged)");
      }
      for (const auto& w : r.warnings) std::printf("warning: %s\n", w.c_str());
      for (std::size_t k = 0; k < r.modal_pairs.size(); ++k) {
        const auto& mp = r.modal_pairs[k];
        std::printf("mode %zu: identified %.4f Hz, model %.4f -> %.4f Hz, MAC %.3f -> %.3f, damping %.3f %% identified, model %.3f -> %.3f %%\n",
                    k + 1, mp.frequency_hz, mp.model_before_hz, mp.model_after_hz, mp.mac_before, mp.mac_after,
                    100 * mp.damping_ratio, 100 * mp.model_damping_before, 100 * mp.model_damping_after);
      }
      std::printf("wrote %s/fit.csv, fit.toml, fitted.toml, fit_trace.csv, fit_residuals.csv, fit_time.csv\n", o.out.c_str());
    }
    return r.status == study::FitResult::Status::converged ? ok : runtime_failure;
  };
  return bound(std::move(c), +declare, +body);
}

}  // namespace viaduct::cli
