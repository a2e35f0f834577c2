// viaduct fit: scenario parameters fitted to measured records and identified modes.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "cli.hpp"
#include "viaduct/io/fit.hpp"
#include "viaduct/io/record.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/study/fit.hpp"

namespace viaduct::cli {

namespace {

std::string fmt(double v) { return format_number(v, 10); }

std::pair<std::string, std::string> split_pair(const std::string& s, const std::string& option) {
  const auto eq = s.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == s.size())
    throw InputError(option + " needs NAME=VALUE, got '" + s + "'");
  return {s.substr(0, eq), s.substr(eq + 1)};
}

// A record's mapped channels as the fit sees them.
study::FitRecord load_fit_record(const std::string& file, const std::vector<std::string>& maps, double speed_kmh,
                                 const std::string& train, const std::string& where) {
  if (maps.empty()) throw InputError(where + ": record " + file + " maps no channel (--map CHANNEL=STATION)");
  const io::Record rec = io::read_record(file);
  study::FitRecord fr;
  fr.name = file;
  fr.fs_hz = rec.fs_hz;
  fr.t0_s = rec.t0_s;
  fr.train = train;
  fr.speed = speed_kmh / 3.6;
  for (const auto& m : maps) {
    const auto [channel, station] = split_pair(m, where + " map");
    study::FitChannel ch;
    const std::size_t c = rec.channel(channel);
    ch.name = rec.channels[c];
    ch.station = station;
    const ChannelQuantity q = channel_quantity(rec.units[c], ch.name, where);
    ch.acceleration = q.acceleration;
    ch.scale = q.scale;
    ch.samples = rec.data.col(static_cast<Index>(c));
    fr.channels.push_back(std::move(ch));
  }
  return fr;
}

}  // namespace

Command fit_command() {
  Command c;
  c.name = "fit";
  c.summary = "model updating: fit scenario parameters to measured records and identified modes";
  c.add_options = [](po::options_description& d) {
    d.add_options()("param", po::value<std::vector<std::string>>()->composing(),
                    "KEY=LO:HI[:log|linear]: a numeric scenario key to fit within bounds, starting from its scenario value (repeatable; replaces [[fit.params]])")(
        "record", po::value<std::vector<std::string>>()->composing(),
        "record CSV or UFF to fit (repeatable; replaces [[fit.records]]); every --map applies to every --record")(
        "map", po::value<std::vector<std::string>>()->composing(),
        "CHANNEL=STATION: record channel fitted by a scenario station; also RESPONSE=STATION for identified shapes (repeatable)")(
        "speed-kmh", po::value<std::vector<double>>()->composing(),
        "speed of the passages [km/h]: one for all records or one per --record (default: run.speed_kmh)")(
        "train", po::value<std::string>(), "train of the passages (default: the first of train.files)")(
        "modes", po::value<std::string>(), "identified modes for the modal and damping objectives: modal-fit output (directory or modes.csv, shapes.csv beside it) or decay output (directory or decay_summary.csv)")(
        "modes-method", po::value<std::string>(), "rows of modes.csv to fit: lscf (default), circle-fit or peak-picking")(
        "weight", po::value<std::vector<std::string>>()->composing(),
        "OBJECTIVE=W with OBJECTIVE time, peak, envelope, spectrum, modal or damping (repeatable; default time=1 with records, modal=1 with --modes)")(
        "starts", po::value<int>(), "solver starts: the scenario's values, then quasi-random points in the bounds (default 1)")(
        "no-spectral-start", po::bool_switch(), "skip the spectral pre-stage of each start (fit.spectral_start = false)")(
        "max-iterations", po::value<int>(), "iterations per start (default 50)")(
        "max-time-s", po::value<double>(), "wall time per start [s] (default 600)");
  };
  c.usage_and_samples =
      "Fits numeric scenario keys so that the model reproduces measured accelerations (or\n"
      "deflections) and identified modes: Levenberg-Marquardt with bounds (Ceres), logarithmic\n"
      "coordinates for positive keys, forward-difference Jacobians in parallel (--threads), a\n"
      "time shift per record fitted with the parameters. Objectives (--weight): time = filtered,\n"
      "aligned time histories; peak = peak and RMS per channel; envelope = windowed RMS; spectrum =\n"
      "amplitude spectra over the filter band; modal = frequencies and mode shapes (MAC) from\n"
      "viaduct modal-fit. Parameters, records and weights may also be declared in the scenario's\n"
      "[fit] section (docs/fitting.md). Writes OUT/fit.csv (estimates, standard errors, flags),\n"
      "fit_correlation.csv, fit.toml, fitted.toml (the scenario with the fitted values),\n"
      "fit_trace.csv, fit_residuals.csv, fit_time.csv, fit_modes.csv and manifest.toml; plot with\n"
      "scripts/plot_fit.py OUT. Exit 1 when the fit did not converge (the outputs say why).\n\n"
      "The first two samples use the outputs of the samples of viaduct run and modal-fit.\n\n"
      "Sample runs:\n"
      "  viaduct fit scenarios/hslm-simply-supported.toml --record out/a4/history.csv --map mid_acc_mps2=mid --train HSLM-A4 --speed-kmh 300 --param bridge.EI=5e9:1e10 --param bridge.damping.ratio=0.005:0.05 --set bridge.EI=7e9 --set bridge.damping.ratio=0.02 --out out/fit-hslm\n"
      "  viaduct fit scenarios/hslm-simply-supported.toml --modes out/fit-sweep --param bridge.EI=5e9:1e10 --set bridge.EI=7e9 --out out/fit-modes\n"
      "  viaduct fit scenarios/old-guadiana-talgo.toml --record data/records/og-calibration.csv --map S1_mid_acc=S1_mid --map S2_mid_acc=S2_mid --param bridge.EI=5e9:1e10 --param track.pad.k=2e7:1e9 --param bridge.damping.ratio1=0.01:0.06 --threads 2 --out out/fit-og\n";
  c.run = [](const Common& o, const po::variables_map& vm) {
    const auto t0 = std::chrono::steady_clock::now();
    const io::FlatScenario flat = io::load_flat(o.scenario, o.set);
    io::FitDeclaration decl = io::fit_declaration(flat);
    study::FitProblem problem;
    // Parameters.
    if (vm.count("param")) {
      for (const auto& p : vm["param"].as<std::vector<std::string>>()) problem.params.push_back(io::parse_fit_parameter(flat, p));
    } else {
      problem.params = decl.params;
    }
    if (problem.params.empty()) throw InputError("no parameter to fit: give --param KEY=LO:HI or [[fit.params]] in the scenario");
    for (std::size_t i = 0; i < problem.params.size(); ++i)
      for (std::size_t j = i + 1; j < problem.params.size(); ++j)
        if (problem.params[i].key == problem.params[j].key) throw InputError("--param: " + problem.params[i].key + " is given twice");
    // Records.
    const std::vector<std::string> maps = vm.count("map") ? vm["map"].as<std::vector<std::string>>() : std::vector<std::string>{};
    std::vector<double> speeds = vm.count("speed-kmh") ? vm["speed-kmh"].as<std::vector<double>>() : std::vector<double>{};
    for (double v : speeds)
      if (!(v > 0) || !std::isfinite(v)) throw InputError("--speed-kmh must be > 0, got " + fmt(v));
    const std::string train = vm.count("train") ? vm["train"].as<std::string>() : "";
    if (vm.count("record")) {
      const auto files = vm["record"].as<std::vector<std::string>>();
      if (speeds.size() > 1 && speeds.size() != files.size())
        throw InputError("--speed-kmh: give one speed for all records or one per --record (" + std::to_string(files.size()) + ")");
      for (std::size_t i = 0; i < files.size(); ++i)
        problem.records.push_back(load_fit_record(files[i], maps, speeds.empty() ? 0.0 : speeds[speeds.size() > 1 ? i : 0], train,
                                                  "--record " + files[i]));
    } else {
      if (!speeds.empty()) throw InputError("--speed-kmh needs --record (declared records carry their own speed_kmh)");
      for (const auto& r : decl.records)
        problem.records.push_back(load_fit_record(r.file, r.map, r.speed_kmh, r.train,
                                                  r.where.file + ":" + std::to_string(r.where.line)));
    }
    // Identified modes.
    std::string modes = vm.count("modes") ? vm["modes"].as<std::string>() : decl.modes;
    const std::string method = vm.count("modes-method") ? vm["modes-method"].as<std::string>() : decl.modes_method;
    if (!modes.empty()) {
      study::ModalTarget t = io::read_identified_modes(modes, method);
      std::map<std::string, std::string> to_station;
      for (const auto& m : maps) to_station.insert(split_pair(m, "--map"));
      const study::Scenario sc = io::to_scenario(flat);
      auto is_station = [&](const std::string& n) {
        for (const auto& s : sc.stations)
          if (s.name == n) return true;
        return false;
      };
      for (auto& s : t.sensors) {
        if (to_station.count(s)) s = to_station[s];
        else if (!is_station(s)) {
          std::string base = s;
          for (const std::string suffix : {"_acc", "_disp", "_vel"})
            if (base.size() > suffix.size() && base.compare(base.size() - suffix.size(), suffix.size(), suffix) == 0)
              base = base.substr(0, base.size() - suffix.size());
          if (!is_station(base))
            throw InputError("--modes: response '" + s + "' is not a station of the scenario: add --map " + s + "=STATION");
          s = base;
        }
      }
      problem.modal = t;
    }
    // Weights and options.
    study::FitOptions opt = decl.options;
    if (vm.count("weight")) {
      opt.weights = study::FitWeights{0, 0, 0, 0, 0};
      for (const auto& w : vm["weight"].as<std::vector<std::string>>()) {
        const auto [name, value] = split_pair(w, "--weight");
        char* end = nullptr;
        const double x = std::strtod(value.c_str(), &end);
        if (*end != '\0' || !(x >= 0) || !std::isfinite(x)) throw InputError("--weight " + name + ": must be a number >= 0, got '" + value + "'");
        if (name == "time") opt.weights.time = x;
        else if (name == "peak") opt.weights.peak = x;
        else if (name == "envelope") opt.weights.envelope = x;
        else if (name == "spectrum") opt.weights.spectrum = x;
        else if (name == "modal") opt.weights.modal = x;
        else if (name == "damping") opt.weights.damping = x;
        else throw InputError("--weight: unknown objective '" + name + "' (time, peak, envelope, spectrum, modal, damping)");
      }
    } else {
      if (opt.weights.time < 0) opt.weights.time = problem.records.empty() ? 0.0 : 1.0;
      if (opt.weights.modal < 0) opt.weights.modal = problem.modal ? 1.0 : 0.0;
    }
    if (opt.weights.any_record_term() && problem.records.empty())
      throw InputError("the record objectives need a record: give --record FILE --map CHANNEL=STATION (or [[fit.records]])");
    if ((opt.weights.modal > 0 || opt.weights.damping > 0) && !problem.modal)
      throw InputError("the modal and damping objectives need --modes (or fit.modes)");
    if (opt.weights.time + opt.weights.peak + opt.weights.envelope + opt.weights.spectrum + opt.weights.modal +
            opt.weights.damping <= 0)
      throw InputError("nothing to fit against: give --record FILE --map CHANNEL=STATION and/or --modes DIR");
    if (vm.count("starts")) opt.starts = vm["starts"].as<int>();
    if (vm["no-spectral-start"].as<bool>()) opt.spectral_start = false;
    if (vm.count("max-iterations")) opt.max_iterations = vm["max-iterations"].as<int>();
    if (vm.count("max-time-s")) opt.max_time_s = vm["max-time-s"].as<double>();
    opt.threads = o.threads;
    std::string why;
    if (!opt.is_valid(&why)) throw InputError(why);
    if (!o.quiet)
      opt.progress = [&problem](const study::FitTracePoint& tp) {
        std::fprintf(stderr, "  start %d %s iteration %2d: cost %.6e ", tp.start + 1, tp.stage == 1 ? "spectral" : "fit     ",
                     tp.iteration, tp.cost);
        for (std::size_t i = 0; i < tp.values.size(); ++i)
          std::fprintf(stderr, " %s=%.5g", problem.params[i].key.c_str(), tp.values[i]);
        std::fprintf(stderr, "\n");
      };
    problem.scenario_at = io::scenario_builder(flat, problem.params);
    if (!o.quiet)
      std::printf("fitting %zu parameters to %zu record(s)%s (%d thread(s), %d start(s))\n", problem.params.size(),
                  problem.records.size(), problem.modal ? " and identified modes" : "", opt.threads, opt.starts);
    std::fflush(stdout);
    const study::FitResult r = study::fit(problem, opt);

    // Outputs.
    make_out_dir(o.out);
    const std::size_t np = problem.params.size();
    std::vector<std::vector<std::string>> rows;
    for (std::size_t i = 0; i < np; ++i) {
      const auto& p = problem.params[i];
      const double ref = std::abs(r.estimate[i]) > 0 ? std::abs(r.estimate[i]) : p.upper - p.lower;
      rows.push_back({p.key, p.unit, p.scale == study::ParameterScale::log ? "log" : "linear", fmt(p.lower), fmt(p.upper),
                      fmt(p.initial), fmt(r.estimate.empty() ? p.initial : r.estimate[i]),
                      r.std_error.empty() ? "nan" : fmt(r.std_error[i]), r.std_error.empty() ? "nan" : fmt(r.std_error[i] / ref),
                      r.sensitivity.empty() ? "nan" : fmt(r.sensitivity[i]), r.at_bound.empty() ? "" : (r.at_bound[i] ? "true" : "false"),
                      r.determined.empty() ? "" : (r.determined[i] ? "true" : "false")});
    }
    io::write_table_csv(o.out + "/fit.csv",
                        {"key", "unit", "scale", "lower", "upper", "initial", "estimate", "std_error", "relative_std_error",
                         "sensitivity", "at_bound", "determined"},
                        rows);
    {
      std::vector<std::string> head = {"key"};
      for (const auto& p : problem.params) head.push_back(p.key);
      std::vector<std::vector<std::string>> cr;
      for (std::size_t i = 0; i < np; ++i) {
        std::vector<std::string> row = {problem.params[i].key};
        for (std::size_t j = 0; j < np; ++j)
          row.push_back(r.correlation.size() ? fmt(r.correlation(static_cast<Index>(i), static_cast<Index>(j))) : "nan");
        cr.push_back(row);
      }
      io::write_table_csv(o.out + "/fit_correlation.csv", head, cr);
    }
    {
      std::vector<std::string> head = {"start", "stage", "iteration", "cost"};
      for (const auto& p : problem.params) head.push_back(p.key);
      std::vector<std::vector<std::string>> tr;
      for (const auto& tp : r.trace) {
        std::vector<std::string> row = {std::to_string(tp.start + 1), tp.stage == 1 ? "spectral" : "fit", std::to_string(tp.iteration), fmt(tp.cost)};
        for (double v : tp.values) row.push_back(fmt(v));
        tr.push_back(row);
      }
      io::write_table_csv(o.out + "/fit_trace.csv", head, tr);
    }
    {
      std::vector<std::vector<std::string>> tr;
      for (const auto& t : r.terms) tr.push_back({t.objective, t.record, t.channel, fmt(t.before), fmt(t.after)});
      io::write_table_csv(o.out + "/fit_residuals.csv", {"objective", "record", "channel", "before", "after"}, tr);
    }
    {
      std::vector<std::vector<std::string>> tr;
      for (const auto& ov : r.overlays)
        for (Index i = 0; i < ov.t.size(); ++i)
          tr.push_back({ov.record, ov.channel, fmt(ov.t[i]), fmt(ov.measured[i]), fmt(ov.initial[i]), fmt(ov.fitted[i])});
      io::write_table_csv(o.out + "/fit_time.csv", {"record", "channel", "t_s", "measured", "initial", "fitted"}, tr);
    }
    {
      std::vector<std::vector<std::string>> tr;
      for (std::size_t k = 0; k < r.modal_pairs.size(); ++k) {
        const auto& mp = r.modal_pairs[k];
        tr.push_back({std::to_string(k + 1), fmt(mp.frequency_hz), fmt(mp.model_before_hz), fmt(mp.model_after_hz),
                      fmt(mp.mac_before), fmt(mp.mac_after), fmt(mp.damping_ratio), fmt(mp.model_damping_before),
                      fmt(mp.model_damping_after)});
      }
      io::write_table_csv(o.out + "/fit_modes.csv",
                          {"mode", "identified_hz", "model_before_hz", "model_after_hz", "mac_before", "mac_after",
                           "identified_damping_ratio", "model_damping_before", "model_damping_after"},
                          tr);
    }
    // fit.toml: the summary.
    {
      auto q = [](const std::string& s) {
        io::Value v;
        v.type = io::ValueType::string;
        v.s = s;
        return v.to_toml();
      };
      std::ostringstream t;
      t << "# viaduct fit: " << o.scenario << "\n[fit]\n";
      t << "status = " << q(study::to_string(r.status)) << "\nmessage = " << q(r.message) << "\n";
      t << "cost_initial = " << fmt(r.cost_initial) << "\ncost_final = " << fmt(r.cost_final) << "\n";
      t << "n_residuals = " << r.n_residuals << "\niterations = " << r.iterations << "\nevaluations = " << r.evaluations
        << "\nsimulations = " << r.simulations << "\nstarts = " << opt.starts << "\nbest_start = " << r.best_start + 1 << "\n";
      t << "wall_s = " << fmt(r.wall_s) << "\nthreads = " << opt.threads << "\n";
      t << "weights = { time = " << fmt(opt.weights.time) << ", peak = " << fmt(opt.weights.peak) << ", envelope = "
        << fmt(opt.weights.envelope) << ", spectrum = " << fmt(opt.weights.spectrum) << ", modal = " << fmt(opt.weights.modal)
        << ", damping = " << fmt(opt.weights.damping) << " }\n";
      t << "warnings = [";
      for (std::size_t i = 0; i < r.warnings.size(); ++i) t << (i ? ", " : "") << q(r.warnings[i]);
      t << "]\n";
      t << "start_costs = [";
      for (std::size_t i = 0; i < r.start_costs.size(); ++i) t << (i ? ", " : "") << (std::isfinite(r.start_costs[i]) ? fmt(r.start_costs[i]) : "inf");
      t << "]\n";
      t << "record_shifts_s = [";
      for (std::size_t i = 0; i < r.shift_s.size(); ++i) t << (i ? ", " : "") << (std::isfinite(r.shift_s[i]) ? fmt(r.shift_s[i]) : "nan");
      t << "]\n";
      for (std::size_t i = 0; i < np && !r.std_error.empty(); ++i) {
        t << "\n[[fit.params]]\nkey = " << q(problem.params[i].key) << "\nunit = " << q(problem.params[i].unit)
          << "\ninitial = " << fmt(problem.params[i].initial) << "\nestimate = " << fmt(r.estimate[i])
          << "\nstd_error = " << (std::isfinite(r.std_error[i]) ? fmt(r.std_error[i]) : "inf")
          << "\ndetermined = " << (r.determined[i] ? "true" : "false") << "\n";
      }
      std::FILE* f = std::fopen((o.out + "/fit.toml").c_str(), "w");
      if (!f) throw SolverError("cannot write " + o.out + "/fit.toml");
      std::fputs(t.str().c_str(), f);
      std::fclose(f);
    }
    // The scenario with the fitted values.
    io::FlatScenario fitted = flat;
    for (std::size_t i = 0; i < np && !r.estimate.empty(); ++i) io::set_number(fitted, problem.params[i].key, r.estimate[i]);
    io::write_scenario_toml(o.out + "/fitted.toml", fitted,
                            "Written by viaduct fit from " + o.scenario + " (" + study::to_string(r.status) +
                                "): the fitted keys hold their estimates; see fit.csv for standard errors.");
    io::Manifest m = start_manifest(o, "fit");
    if (vm.count("record")) m.inputs = vm["record"].as<std::vector<std::string>>();
    if (vm.count("modes")) m.inputs.push_back(vm["modes"].as<std::string>());
    m.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    m.extra = {{"status", "\"" + std::string(study::to_string(r.status)) + "\""}, {"fit_wall_s", fmt(r.wall_s)}};
    io::write_manifest(o.out + "/manifest.toml", m, flat);
    if (!o.quiet) {
      std::printf("\n%s after %d iterations, %d simulations, %.1f s: %s\ncost %.6e -> %.6e\n\n", study::to_string(r.status),
                  r.iterations, r.simulations, r.wall_s, r.message.c_str(), r.cost_initial, r.cost_final);
      std::printf("%-28s %13s %13s %13s %9s  %s\n", "key", "initial", "estimate", "std error", "rel [%]", "");
      for (std::size_t i = 0; i < np && !r.std_error.empty(); ++i) {
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
  return c;
}

}  // namespace viaduct::cli
