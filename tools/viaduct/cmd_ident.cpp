// viaduct frf / shaker / modal-fit / decay: forced-vibration tests and free decay, measured or
// simulated (issue #4). Parsing and output only; the numerics live in ident:: and study::.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "cli.hpp"
#include "viaduct/ident/decay.hpp"
#include "viaduct/ident/frf.hpp"
#include "viaduct/ident/modal_fit.hpp"
#include "viaduct/io/frf.hpp"
#include "viaduct/io/record.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/study/forced.hpp"

namespace viaduct::cli {

namespace {

std::string fmt(double v, const char* f = "%.8g") {
  char b[48];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

double to_number(const std::string& s, const std::string& what) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end == s.c_str() || *end != '\0' || !std::isfinite(v))
    throw InputError(what + ": '" + s + "' is not a number");
  return v;
}

// "NAME=X" or "X" (name "x<X>").
std::pair<std::string, double> named_position(const std::string& s, const std::string& option) {
  const auto eq = s.find('=');
  if (eq == std::string::npos) return {"x" + s, to_number(s, option)};
  const std::string name = s.substr(0, eq);
  if (name.empty()) throw InputError(option + ": empty name in '" + s + "'");
  return {name, to_number(s.substr(eq + 1), option)};
}

bool is_scenario_path(const std::string& p) {
  return p.size() > 5 && p.compare(p.size() - 5, 5, ".toml") == 0;
}

ident::FrfQuantity quantity_option(const std::string& q) {
  if (q == "acc") return ident::FrfQuantity::accelerance;
  if (q == "vel") return ident::FrfQuantity::mobility;
  if (q == "disp") return ident::FrfQuantity::receptance;
  throw InputError("--quantity must be acc, vel or disp, got '" + q + "'");
}

// Exciter and responses from --force-at / --response-at, or the scenario's stations.
study::ForcedSetup forced_setup(const model::Structure& s, const study::Scenario& sc, const po::variables_map& vm) {
  study::ForcedSetup setup;
  if (!vm.count("force-at")) throw InputError("--force-at X (the exciter's position on the deck [m]) is required");
  setup.force_x_m = vm["force-at"].as<double>();
  setup.quantity = quantity_option(vm["quantity"].as<std::string>());
  if (vm.count("response-at")) {
    for (const auto& r : vm["response-at"].as<std::vector<std::string>>()) {
      const auto [name, x] = named_position(r, "--response-at");
      setup.responses.push_back(study::deck_station_at(s, name, x));
    }
  } else {
    setup.responses = sc.stations;
  }
  return setup;
}

void add_forced_options(po::options_description& d) {
  d.add_options()("force-at", po::value<double>(), "exciter position: global x on the deck [m] (required)")(
      "response-at", po::value<std::vector<std::string>>()->composing(),
      "response point NAME=X or X on the deck [m] (repeatable; default: the scenario's stations)")(
      "quantity", po::value<std::string>()->default_value("acc"), "responses as acc, vel or disp");
}

io::Record load_record(const std::string& path) { return io::read_record(path); }

// FRF names and quantities from record channels: "S1_mid_acc_mps2" gives the sensor "S1_mid"
// (the quantity tag _acc, _vel or _disp goes, as the unit says it), matching station names.
void label(ident::Frf& frf, const io::Record& r, const std::vector<std::size_t>& chans, const std::string& force_unit) {
  frf.force_unit = force_unit;
  for (std::size_t c : chans) {
    std::string name = r.channels[c].substr(0, r.channels[c].size() - r.units[c].size() - 1);
    for (const char* tag : {"_acc", "_vel", "_disp"}) {
      const std::string t = tag;
      if (name.size() > t.size() && name.compare(name.size() - t.size(), t.size(), t) == 0) {
        name.resize(name.size() - t.size());
        break;
      }
    }
    frf.responses.push_back(name);
    frf.quantity.push_back(ident::quantity_of_unit(r.units[c]));
  }
}

int frf_from_scenario(const Common& o, const po::variables_map& vm) {
  const io::FlatScenario flat = io::load_flat(o.scenario, o.set);
  const study::Scenario sc = io::to_scenario(flat);
  const model::Structure s = model::build_structure(sc.bridge, sc.track);
  const study::ForcedSetup setup = forced_setup(s, sc, vm);
  const double f0 = vm.count("f-min") ? vm["f-min"].as<double>() : 1.0;
  const double f1 = vm.count("f-max") ? vm["f-max"].as<double>() : 30.0;
  const long n = vm["n-freq"].as<long>();
  if (!(f0 > 0.0) || !(f1 > f0)) throw InputError("--f-min must be > 0 and --f-max > --f-min");
  if (n < 2 || n > 1000000) throw InputError("--n-freq must be in 2..1000000");
  const Vector f = Vector::LinSpaced(n, f0, f1);
  const ident::Frf frf = study::model_frf(s, setup, f, o.threads, progress_printer("frf", o.quiet, "frequencies"));
  make_out_dir(o.out);
  io::write_frf_csv(o.out + "/frf.csv", frf);
  io::Manifest man = start_manifest(o, "frf");
  man.extra = {{"force_at_m", fmt(setup.force_x_m)}, {"n_dofs", std::to_string(s.n_dofs)}};
  io::write_manifest(o.out + "/manifest.toml", man, flat);
  if (!o.quiet)
    std::printf("model FRF: %ld DOFs, %ld frequencies %.4g-%.4g Hz, %zu responses; wrote %s/frf.csv\n",
                static_cast<long>(s.n_dofs), n, f0, f1, setup.responses.size(), o.out.c_str());
  return ok;
}

int frf_from_record(const Common& o, const po::variables_map& vm) {
  if (!o.set.empty()) throw InputError("--set applies to scenarios; " + o.scenario + " is a record");
  const io::Record rec = load_record(o.scenario);
  if (!vm.count("force")) throw InputError("missing force channel: name it with --force <channel> (e.g. force_N)");
  io::Record frec = rec;
  if (vm.count("force-record")) {
    frec = load_record(vm["force-record"].as<std::string>());
    if (std::abs(frec.fs_hz - rec.fs_hz) > 1e-9 * rec.fs_hz)
      throw InputError("mismatched sampling rates: force record at " + fmt(frec.fs_hz) + " Hz, responses at " + fmt(rec.fs_hz) +
                       " Hz (resample one with viaduct resample)");
    if (std::abs(frec.t0_s - rec.t0_s) > 0.5 / rec.fs_hz || frec.n_samples() != rec.n_samples())
      throw InputError("the force record and the response record do not cover the same samples (start or length differ)");
  }
  const std::size_t fc = frec.channel(vm["force"].as<std::string>());
  const std::string funit = frec.units[fc];
  if (funit != "N" && funit != "kN") throw InputError("force channel '" + frec.channels[fc] + "' must be in N or kN");
  std::vector<std::size_t> chans;
  if (vm.count("response")) {
    for (const auto& c : vm["response"].as<std::vector<std::string>>()) chans.push_back(rec.channel(c));
  } else {
    for (std::size_t c = 0; c < rec.channels.size(); ++c)
      if (rec.units[c] == "m" || rec.units[c] == "mps" || rec.units[c] == "mps2") chans.push_back(c);
  }
  if (chans.empty()) throw InputError("no response channel (m, mps or mps2) in " + o.scenario);
  const Vector force = frec.data.col(static_cast<Index>(fc));
  Matrix resp(rec.n_samples(), static_cast<Index>(chans.size()));
  for (std::size_t j = 0; j < chans.size(); ++j) resp.col(static_cast<Index>(j)) = rec.data.col(static_cast<Index>(chans[j]));
  const std::string method = vm["method"].as<std::string>();
  ident::Frf frf;
  make_out_dir(o.out);
  if (method == "welch") {
    const std::string estimator = vm["estimator"].as<std::string>();
    if (estimator != "h1" && estimator != "h2") throw InputError("--estimator must be h1 or h2, got '" + estimator + "'");
    signal::WelchOptions wo;
    wo.nperseg = vm["nperseg"].as<long>();
    const std::string win = vm["window"].as<std::string>();
    if (win == "rectangular") wo.window = signal::Window::rectangular;
    else if (win != "hann") throw InputError("--window must be hann or rectangular, got '" + win + "'");
    const ident::WelchFrf w = ident::welch_frf(force, resp, rec.fs_hz, wo);
    const double fmin = vm.count("f-min") ? vm["f-min"].as<double>() : 0.0;
    const double fmax = vm.count("f-max") ? vm["f-max"].as<double>() : 0.5 * rec.fs_hz;
    std::vector<Index> keep;
    for (Index k = 0; k < w.frequency_hz.size(); ++k)
      if (w.frequency_hz[k] > 0.0 && w.frequency_hz[k] >= fmin && w.frequency_hz[k] <= fmax) keep.push_back(k);
    if (keep.size() < 2) throw InputError("fewer than 2 Welch lines in [--f-min, --f-max]");
    frf.frequency_hz.resize(static_cast<Index>(keep.size()));
    frf.h.resize(static_cast<Index>(keep.size()), resp.cols());
    frf.coherence.resize(static_cast<Index>(keep.size()), resp.cols());
    for (std::size_t j = 0; j < keep.size(); ++j) {
      frf.frequency_hz[static_cast<Index>(j)] = w.frequency_hz[keep[j]];
      frf.h.row(static_cast<Index>(j)) = (estimator == "h2" ? w.h2 : w.h1).row(keep[j]);
      frf.coherence.row(static_cast<Index>(j)) = w.coherence.row(keep[j]);
    }
    if (!o.quiet) std::printf("Welch: %ld segments of %ld samples\n", static_cast<long>(w.n_segments), wo.nperseg);
  } else if (method == "stepped") {
    std::vector<ident::SineStep> steps;
    if (vm.count("steps")) {
      steps = io::read_steps_csv(vm["steps"].as<std::string>());
    } else {
      steps = ident::detect_steps(force, rec.fs_hz, rec.t0_s);
      io::write_steps_csv(o.out + "/steps-detected.csv", steps);
      if (!o.quiet)
        std::printf("no --steps: detected %zu steps from the force (%.4g to %.4g Hz); wrote %s/steps-detected.csv\n", steps.size(),
                    steps.front().frequency_hz, steps.back().frequency_hz, o.out.c_str());
    }
    ident::SteppedSineOptions so;
    so.settle_cycles = vm["settle-cycles"].as<double>();
    so.settle_s = vm["settle-s"].as<double>();
    const auto pts = ident::stepped_sine(force, resp, rec.fs_hz, rec.t0_s, steps, so);
    const Index n = static_cast<Index>(pts.size());
    // One FRF point per step, sorted by frequency (schedules may go down or repeat).
    std::vector<std::size_t> order(pts.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return pts[a].frequency_hz < pts[b].frequency_hz; });
    frf.frequency_hz.resize(n);
    frf.h.resize(n, resp.cols());
    std::vector<std::vector<std::string>> rows;
    for (Index j = 0; j < n; ++j) {
      const auto& p = pts[order[static_cast<std::size_t>(j)]];
      frf.frequency_hz[j] = p.frequency_hz;
      frf.h.row(j) = p.h.transpose();
      for (Index c = 0; c < resp.cols(); ++c)
        rows.push_back({std::to_string(order[static_cast<std::size_t>(j)] + 1), fmt(p.frequency_hz), fmt(p.t_from_s), fmt(p.t_to_s),
                        fmt(p.n_cycles, "%.1f"), rec.channels[chans[static_cast<std::size_t>(c)]], fmt(std::abs(p.force)),
                        fmt(p.force_distortion, "%.3e"), fmt(p.response_distortion[c], "%.3e"), fmt(p.settle_change[c], "%.3e")});
    }
    io::write_table_csv(o.out + "/stepped.csv",
                        {"step", "frequency_hz", "t_from_s", "t_to_s", "n_cycles", "channel", "force_amplitude",
                         "force_distortion", "response_distortion", "settle_change"},
                        rows);
    double worst_settle = 0.0, worst_dist = 0.0;
    for (const auto& p : pts) {
      worst_settle = std::max(worst_settle, p.settle_change.maxCoeff());
      worst_dist = std::max({worst_dist, p.force_distortion, p.response_distortion.maxCoeff()});
    }
    if (!o.quiet) {
      std::printf("stepped sine: %ld steps; worst settle change %.2e, worst distortion (THD+N) %.2e; wrote %s/stepped.csv\n",
                  static_cast<long>(n), worst_settle, worst_dist, o.out.c_str());
      if (worst_settle > 0.05)
        std::fprintf(stderr, "viaduct frf: warning: a step's FRF changed by %.0f %% between the halves of its dwell (transient left, "
                     "or noise on a small response): see settle_change in stepped.csv; raise --settle-cycles if it is the transient\n",
                     100 * worst_settle);
    }
  } else if (method == "swept") {
    ident::SweptSineOptions so;
    if (!vm.count("f-min") || !vm.count("f-max")) throw InputError("--method swept needs --f-min and --f-max (the swept band)");
    so.f_min_hz = vm["f-min"].as<double>();
    so.f_max_hz = vm["f-max"].as<double>();
    frf = ident::swept_sine(force, resp, rec.fs_hz, so);
  } else {
    throw InputError("--method must be welch, stepped or swept, got '" + method + "'");
  }
  label(frf, rec, chans, funit);
  io::write_frf_csv(o.out + "/frf.csv", frf);
  io::write_manifest(o.out + "/manifest.toml", start_manifest(o, "frf", {o.scenario}), nullptr);
  if (!o.quiet)
    std::printf("%s FRF: %ld frequencies, %zu responses to %s; wrote %s/frf.csv\n", method.c_str(),
                static_cast<long>(frf.frequency_hz.size()), chans.size(), frec.channels[fc].c_str(), o.out.c_str());
  return ok;
}

}  // namespace

Command frf_command() {
  Command c;
  c.name = "frf";
  c.positional = "SCENARIO|RECORD";
  c.summary = "FRFs: the model's by a direct frequency solve, or estimated from force and response records (frf.csv)";
  c.add_options = [](po::options_description& d) {
    add_forced_options(d);
    d.add_options()("f-min", po::value<double>(), "[Hz] lowest frequency (scenario: default 1; swept: band)")(
        "f-max", po::value<double>(), "[Hz] highest frequency (scenario: default 30; swept: band)")(
        "n-freq", po::value<long>()->default_value(1161), "scenario: frequencies, evenly spaced")(
        "force", po::value<std::string>(), "record: the force channel (N or kN)")(
        "force-record", po::value<std::string>(), "record: the force in another record (same rate and samples)")(
        "response", po::value<std::vector<std::string>>()->composing(),
        "record: response channel (repeatable; default: every m, mps, mps2 channel)")(
        "method", po::value<std::string>()->default_value("welch"), "record: welch, stepped or swept")(
        "estimator", po::value<std::string>()->default_value("h1"), "welch: h1 or h2")(
        "nperseg", po::value<long>()->default_value(4096), "welch: samples per segment")(
        "window", po::value<std::string>()->default_value("hann"), "welch: hann or rectangular (half-overlapping segments)")(
        "steps", po::value<std::string>(), "stepped: the schedule CSV (t_start_s,t_end_s,frequency_hz); default: detected from the force")(
        "settle-cycles", po::value<double>()->default_value(30.0), "stepped: drive cycles discarded per step")(
        "settle-s", po::value<double>()->default_value(0.0), "stepped: at least this long discarded [s]");
  };
  c.usage_and_samples =
      "With a SCENARIO (.toml): solves (K - w^2 M + i w C) x = F on the assembled structure (track\n"
      "included) for a unit force at --force-at, and writes the responses per newton.\n"
      "With a RECORD (CSV or UFF): estimates the FRF of every response to --force: Welch H1 (or H2)\n"
      "and coherence, stepped sine (one point per dwell of --steps, or of the dwells detected from the\n"
      "force, with settle and distortion checks in stepped.csv) or swept sine (ratio of transforms on\n"
      "--f-min..--f-max).\n"
      "Phase convention e^{i w t}: a response lagging the force has a negative phase.\n\n"
      "Sample runs:\n"
      "  viaduct frf scenarios/old-guadiana-talgo.toml --force-at 6 --f-min 5 --f-max 15 --n-freq 201 --out out/frf-model\n"
      "  viaduct shaker scenarios/old-guadiana-talgo.toml --force-at 6 --stepped 9:11:0.5 --dwell-s 6 --out out/shaker\n"
      "  viaduct frf out/shaker/record.csv --force force_N --method stepped --steps out/shaker/steps.csv --out out/frf-test\n"
      "  viaduct frf out/shaker/record.csv --force force_N --method stepped --out out/frf-detected\n"
      "  viaduct frf out/shaker/record.csv --force force_N --method welch --nperseg 1024 --f-min 2 --f-max 40 --out out/frf-welch\n";
  c.run = [](const Common& o, const po::variables_map& vm) {
    return is_scenario_path(o.scenario) ? frf_from_scenario(o, vm) : frf_from_record(o, vm);
  };
  return c;
}

Command shaker_command() {
  Command c;
  c.name = "shaker";
  c.summary = "simulated forced-vibration test (stepped or swept sine, Newmark): a synthetic record";
  c.add_options = [](po::options_description& d) {
    add_forced_options(d);
    d.add_options()("stepped", po::value<std::string>(), "stepped sine F0:F1:DF [Hz] (first, last, step)")(
        "steps", po::value<std::string>(), "stepped sine from a schedule CSV instead (contiguous from t = 0)")(
        "dwell-s", po::value<double>()->default_value(10.0), "stepped: dwell per frequency [s]")(
        "swept", po::value<std::string>(), "linear sweep F0:F1 [Hz]")(
        "sweep-s", po::value<double>()->default_value(120.0), "swept: sweep duration [s]")(
        "tail-s", po::value<double>()->default_value(0.0), "recording after the force stops [s] (swept: default 20)")(
        "amplitude-kN", po::value<double>()->default_value(10.0), "force amplitude [kN]")(
        "fs-hz", po::value<double>()->default_value(200.0), "sampling rate of the record [Hz]")(
        "substeps", po::value<int>()->default_value(0), "Newmark steps per sample (0: period error below 1e-4)")(
        "snr-db", po::value<double>()->default_value(-1.0), "add Gaussian noise at this SNR to every channel (< 0: none)")(
        "seed", po::value<unsigned>()->default_value(1), "noise seed");
  };
  c.usage_and_samples =
      "Integrates the structure from rest under a sine force at --force-at (Newmark, fine enough\n"
      "steps that the drive frequencies are exact to 1e-4) and writes OUT/record.csv (t_s, force_N,\n"
      "<response>_acc_mps2, or _vel_mps / _disp_m) and, for stepped sine, OUT/steps.csv: the inputs of viaduct frf.\n\n"
      "Sample runs:\n"
      "  viaduct shaker scenarios/old-guadiana-talgo.toml --force-at 6 --stepped 9:11:0.5 --dwell-s 6 --out out/shaker\n"
      "  viaduct shaker scenarios/hslm-simply-supported.toml --force-at 5 --swept 2:30 --sweep-s 60 --snr-db 40 --out out/sweep\n";
  c.run = [](const Common& o, const po::variables_map& vm) {
    const io::FlatScenario flat = io::load_flat(o.scenario, o.set);
    const study::Scenario sc = io::to_scenario(flat);
    const model::Structure s = model::build_structure(sc.bridge, sc.track);
    const study::ForcedSetup setup = forced_setup(s, sc, vm);
    study::ShakerTest t;
    t.amplitude_N = vm["amplitude-kN"].as<double>() * 1e3;
    t.fs_hz = vm["fs-hz"].as<double>();
    t.substeps = vm["substeps"].as<int>();
    t.noise_snr_db = vm["snr-db"].as<double>();
    t.seed = vm["seed"].as<unsigned>();
    t.tail_s = vm["tail-s"].as<double>();
    const int n_kinds = static_cast<int>(vm.count("stepped") + vm.count("steps") + vm.count("swept"));
    if (n_kinds != 1) throw InputError("give exactly one of --stepped F0:F1:DF, --steps FILE or --swept F0:F1");
    auto split = [](const std::string& text) {
      std::vector<std::string> p;
      std::stringstream ss(text);
      std::string x;
      while (std::getline(ss, x, ':')) p.push_back(x);
      return p;
    };
    if (vm.count("stepped")) {
      const auto p = split(vm["stepped"].as<std::string>());
      if (p.size() != 3) throw InputError("--stepped takes F0:F1:DF, got '" + vm["stepped"].as<std::string>() + "'");
      const double f0 = to_number(p[0], "--stepped"), f1 = to_number(p[1], "--stepped"), df = to_number(p[2], "--stepped");
      if (!(df > 0.0) || !(f1 >= f0)) throw InputError("--stepped needs F1 >= F0 and DF > 0");
      const Index n = static_cast<Index>(std::floor((f1 - f0) / df + 1e-9)) + 1;
      t.steps = ident::regular_schedule(f0, f0 + df * static_cast<double>(n - 1), n, vm["dwell-s"].as<double>());
    } else if (vm.count("steps")) {
      t.steps = io::read_steps_csv(vm["steps"].as<std::string>());
    } else {
      t.kind = study::ShakerTest::Kind::swept;
      const auto p = split(vm["swept"].as<std::string>());
      if (p.size() != 2) throw InputError("--swept takes F0:F1, got '" + vm["swept"].as<std::string>() + "'");
      t.sweep_f_start_hz = to_number(p[0], "--swept");
      t.sweep_f_end_hz = to_number(p[1], "--swept");
      t.sweep_s = vm["sweep-s"].as<double>();
      if (vm["tail-s"].defaulted()) t.tail_s = 20.0;
    }
    const study::ShakerRecord r = study::simulate_shaker_test(s, setup, t, progress_printer("shaker", o.quiet, "steps"));
    io::Record rec;
    rec.fs_hz = r.fs_hz;
    rec.channels.push_back("force_N");
    rec.units.push_back("N");
    const std::string unit = ident::unit_of_quantity(setup.quantity);
    const std::string what = setup.quantity == ident::FrfQuantity::accelerance ? "_acc_"
                             : setup.quantity == ident::FrfQuantity::mobility  ? "_vel_"
                                                                               : "_disp_";
    for (const auto& n : r.names) {
      rec.channels.push_back(n + what + unit);
      rec.units.push_back(unit);
    }
    rec.data.resize(r.force.size(), 1 + r.responses.cols());
    rec.data.col(0) = r.force;
    rec.data.rightCols(r.responses.cols()) = r.responses;
    make_out_dir(o.out);
    io::write_record_csv(o.out + "/record.csv", rec);
    if (t.kind == study::ShakerTest::Kind::stepped) io::write_steps_csv(o.out + "/steps.csv", t.steps);
    io::Manifest man = start_manifest(o, "shaker");
    man.wall_s = r.wall_s;
    man.extra = {{"force_at_m", fmt(setup.force_x_m)},
                 {"newmark_steps", std::to_string(r.n_steps)},
                 {"fs_hz", fmt(r.fs_hz)},
                 {"snr_db", fmt(t.noise_snr_db)}};
    io::write_manifest(o.out + "/manifest.toml", man, flat);
    if (!o.quiet)
      std::printf("shaker: %.1f s of record at %.6g Hz (%ld Newmark steps, %.1f s); wrote %s/record.csv%s\n",
                  t.duration_s(), r.fs_hz, static_cast<long>(r.n_steps), r.wall_s, o.out.c_str(),
                  t.kind == study::ShakerTest::Kind::stepped ? " and steps.csv" : "");
    return ok;
  };
  return c;
}

Command modal_fit_command() {
  Command c;
  c.name = "modal-fit";
  c.positional = "FRF";
  c.summary = "modal parameters from an FRF file: peak picking, circle fit, LSCF + stabilization, MAC";
  c.add_options = [](po::options_description& d) {
    d.add_options()("no-refine", po::bool_switch(), "LSCF: keep the stabilization diagram's values (no refinement, no split test)")(
        "f-min", po::value<double>()->default_value(0.0), "[Hz] band fitted")(
        "f-max", po::value<double>()->default_value(1e9), "[Hz] band fitted")(
        "max-order", po::value<int>()->default_value(40), "LSCF: largest model order (even)")(
        "cluster-tol", po::value<double>()->default_value(0.005), "LSCF: relative frequency spread of one mode's stable poles")(
        "min-prominence", po::value<double>()->default_value(0.05), "peak picking: peaks below this share of the largest are ignored")(
        "model", po::value<std::string>(), "scenario whose modes are compared (MAC) with the identified ones")(
        "sensor", po::value<std::vector<std::string>>()->composing(),
        "with --model: response NAME=X on the deck [m] (default: the scenario's station of that name)");
  };
  c.usage_and_samples =
      "FRF is a frf.csv written by viaduct frf (measured or model). Writes OUT/modes.csv\n"
      "(method,mode,frequency_hz,damping_ratio,response,note for peak picking, circle fit, the LSCF\n"
      "stabilization diagram's modes (lscf-diagram) and the final LSCF modes (lscf: poles refined by\n"
      "nonlinear least squares on the FRFs, clusters hiding two modes split by a residual test)),\n"
      "OUT/shapes.csv, OUT/stabilization.csv (every physical pole of every order, with its status)\n"
      "and, with --model, OUT/mac.csv (identified LSCF modes against the model's modes).\n"
      "Plot with scripts/plot_stabilization.py OUT.\n\n"
      "Sample runs:\n"
      "  viaduct frf scenarios/old-guadiana-talgo.toml --force-at 6 --f-min 5 --f-max 15 --n-freq 201 --out out/frf-model\n"
      "  viaduct modal-fit out/frf-model/frf.csv --f-min 7 --f-max 13 --max-order 20 --model scenarios/old-guadiana-talgo.toml --out out/fit\n"
      "  viaduct shaker scenarios/hslm-simply-supported.toml --force-at 7 --swept 2:30 --sweep-s 60 --snr-db 40 --out out/sweep\n"
      "  viaduct frf out/sweep/record.csv --force force_N --method swept --f-min 3 --f-max 28 --out out/frf-sweep\n"
      "  viaduct modal-fit out/frf-sweep/frf.csv --f-min 3 --f-max 28 --max-order 30 --out out/fit-sweep\n";
  c.run = [](const Common& o, const po::variables_map& vm) {
    const ident::Frf frf = io::read_frf_csv(o.scenario);
    const double f0 = vm["f-min"].as<double>(), f1 = vm["f-max"].as<double>();
    std::vector<std::vector<std::string>> mode_rows, shape_rows;
    auto add_mode = [&](const std::string& method, std::size_t k, const ident::IdentifiedMode& m) {
      mode_rows.push_back({method, std::to_string(k + 1), fmt(m.frequency_hz), fmt(m.damping_ratio),
                           m.response >= 0 ? frf.responses[static_cast<std::size_t>(m.response)] : "all", m.note});
      for (Index r = 0; r < m.shape.size(); ++r)
        shape_rows.push_back({method, std::to_string(k + 1), frf.responses[static_cast<std::size_t>(r)], fmt(m.shape[r].real()),
                              fmt(m.shape[r].imag())});
    };
    ident::PeakPickingOptions po;
    po.f_min_hz = f0;
    po.f_max_hz = f1;
    po.min_relative_prominence = vm["min-prominence"].as<double>();
    const auto pp = ident::peak_picking(frf, po);
    for (std::size_t k = 0; k < pp.size(); ++k) add_mode("peak-picking", k, pp[k]);
    std::size_t k_cf = 0;
    for (const auto& p : pp) {
      if (!std::isfinite(p.damping_ratio)) continue;
      try {
        add_mode("circle-fit", k_cf++, ident::circle_fit(frf, p.response, p.frequency_hz, p.damping_ratio));
      } catch (const InputError& e) {
        if (!o.quiet) std::fprintf(stderr, "viaduct modal-fit: warning: circle fit at %.4g Hz: %s\n", p.frequency_hz, e.what());
      }
    }
    ident::LscfOptions lo;
    lo.f_min_hz = f0;
    lo.f_max_hz = f1;
    lo.max_order = vm["max-order"].as<int>();
    lo.cluster_tol = vm["cluster-tol"].as<double>();
    lo.refine = !vm["no-refine"].as<bool>();
    const ident::LscfResult ls = ident::lscf(frf, lo);
    for (std::size_t k = 0; k < ls.diagram_modes.size(); ++k) add_mode("lscf-diagram", k, ls.diagram_modes[k]);
    for (std::size_t k = 0; k < ls.modes.size(); ++k) add_mode("lscf", k, ls.modes[k]);
    make_out_dir(o.out);
    io::write_table_csv(o.out + "/modes.csv", {"method", "mode", "frequency_hz", "damping_ratio", "response", "note"}, mode_rows);
    io::write_table_csv(o.out + "/shapes.csv", {"method", "mode", "response", "re", "im"}, shape_rows);
    std::vector<std::vector<std::string>> stab;
    for (const auto& p : ls.poles)
      stab.push_back({std::to_string(p.order), fmt(p.frequency_hz), fmt(p.damping_ratio),
                      p.status == ident::PoleStatus::stable ? "stable" : p.status == ident::PoleStatus::stable_frequency ? "frequency" : "new"});
    io::write_table_csv(o.out + "/stabilization.csv", {"order", "frequency_hz", "damping_ratio", "status"}, stab);
    if (!o.quiet) {
      std::printf("%-13s %4s %12s %10s  %s\n", "method", "mode", "f [Hz]", "zeta [%]", "note");
      for (const auto& r : mode_rows)
        std::printf("%-13s %4s %12.5f %10.3f  %s\n", r[0].c_str(), r[1].c_str(), std::stod(r[2]), 100 * std::stod(r[3]), r[5].c_str());
    }
    if (vm.count("model")) {
      const std::string model_file = vm["model"].as<std::string>();
      std::vector<std::pair<std::string, double>> sensors;
      if (vm.count("sensor"))
        for (const auto& sx : vm["sensor"].as<std::vector<std::string>>()) sensors.push_back(named_position(sx, "--sensor"));
      study::ModelModesAtResponses md;
      try {
        md = study::model_modes_at(io::to_scenario(io::load_flat(model_file, {})), frf.responses, sensors,
                                   1.5 * ls.f_max_hz);
      } catch (const InputError& e) {
        throw InputError("--model " + model_file + ": " + e.what());
      }
      ident::ComplexMatrix id_shapes(static_cast<Index>(frf.responses.size()), static_cast<Index>(ls.modes.size()));
      for (std::size_t k = 0; k < ls.modes.size(); ++k) id_shapes.col(static_cast<Index>(k)) = ls.modes[k].shape;
      const Matrix m = ident::mac(id_shapes, md.shape);
      std::vector<std::vector<std::string>> rows;
      for (Index i = 0; i < m.rows(); ++i)
        for (Index j = 0; j < m.cols(); ++j)
          rows.push_back({std::to_string(i + 1), fmt(ls.modes[static_cast<std::size_t>(i)].frequency_hz), std::to_string(j + 1),
                          fmt(md.frequency_hz[j]), fmt(m(i, j), "%.4f")});
      io::write_table_csv(o.out + "/mac.csv", {"mode", "frequency_hz", "model_mode", "model_frequency_hz", "mac"}, rows);
      if (!o.quiet && m.cols() > 0) {
        std::printf("\nLSCF modes against the model (best MAC):\n");
        for (Index i = 0; i < m.rows(); ++i) {
          Index j = 0;
          m.row(i).maxCoeff(&j);
          std::printf("  mode %ld %.4f Hz ~ model mode %ld %.4f Hz (%+.2f %%), MAC %.3f\n", static_cast<long>(i + 1),
                      ls.modes[static_cast<std::size_t>(i)].frequency_hz, static_cast<long>(j + 1), md.frequency_hz[j],
                      100 * (ls.modes[static_cast<std::size_t>(i)].frequency_hz / md.frequency_hz[j] - 1), m(i, j));
        }
      }
    }
    std::vector<std::string> inputs = {o.scenario};
    if (vm.count("model")) inputs.push_back(vm["model"].as<std::string>());
    io::write_manifest(o.out + "/manifest.toml", start_manifest(o, "modal-fit", inputs), nullptr);
    if (!o.quiet) std::printf("wrote %s/modes.csv, shapes.csv, stabilization.csv%s\n", o.out.c_str(), vm.count("model") ? ", mac.csv" : "");
    return ok;
  };
  return c;
}

Command decay_command() {
  Command c;
  c.name = "decay";
  c.positional = "RECORD...";
  c.many_positionals = true;
  c.summary = "frequency and damping from free decays after train passages, against amplitude";
  c.add_options = [](po::options_description& d) {
    d.add_options()("channel", po::value<std::string>(), "the response channel (required)")(
        "frequency-hz", po::value<double>(), "the mode to isolate [Hz] (required)")(
        "band-ratio", po::value<double>()->default_value(0.15), "band-pass f(1 -/+ r)")(
        "order", po::value<int>()->default_value(2), "band-pass Chebyshev I order (0: no filter)")(
        "start-s", po::value<double>(), "start of the free decay [s] (default: detected)")(
        "entry-s", po::value<double>(), "or: time the first axle enters the bridge [s] ...")(
        "speed-kmh", po::value<double>(), "... the train speed [km/h] ...")(
        "train-length-m", po::value<double>(), "... its length [m] ...")(
        "bridge-length-m", po::value<double>(), "... and the bridge length [m]: start when the last axle leaves")(
        "window-cycles", po::value<double>()->default_value(4.0), "cycles per amplitude window")(
        "min-cycles", po::value<double>()->default_value(5.0), "shortest decay accepted [cycles]");
  };
  c.usage_and_samples =
      "One or more records of passages. For each: band-pass around --frequency-hz, find the start of\n"
      "the free decay (given, from the train, or detected), estimate f and damping by logarithmic\n"
      "decrement, exponential fit of the cycle peaks and Hilbert envelope, and f and damping in\n"
      "windows along the decay. Writes OUT/decay.csv (one row per record), OUT/decay_amplitude.csv\n"
      "(record,t_s,amplitude,frequency_hz,damping_ratio) and OUT/decay_summary.csv (mean, std over\n"
      "records). Records that fail are named on stderr (exit 2) after the others are written.\n"
      "Plot with scripts/plot_decay.py OUT.\n\n"
      "Sample runs:\n"
      "  viaduct run scenarios/old-guadiana-talgo.toml --set analysis.free_vibration_s=5 --out out/passage\n"
      "  viaduct decay out/passage/history.csv --channel S1_mid_acc --frequency-hz 10 --out out/decay\n";
  c.run = [](const Common& o, const po::variables_map& vm) {
    if (!vm.count("channel")) throw InputError("--channel is required");
    if (!vm.count("frequency-hz")) throw InputError("--frequency-hz (the mode to isolate) is required");
    ident::DecayOptions d;
    d.frequency_hz = vm["frequency-hz"].as<double>();
    d.band_ratio = vm["band-ratio"].as<double>();
    d.filter_order = vm["order"].as<int>();
    d.window_cycles = vm["window-cycles"].as<double>();
    d.min_cycles = vm["min-cycles"].as<double>();
    const int n_train = static_cast<int>(vm.count("entry-s") + vm.count("speed-kmh") + vm.count("train-length-m") + vm.count("bridge-length-m"));
    if (n_train != 0 && n_train != 4) throw InputError("--entry-s, --speed-kmh, --train-length-m and --bridge-length-m go together");
    if (n_train == 4 && vm.count("start-s")) throw InputError("give --start-s or the train's passage, not both");
    if (vm.count("start-s")) d.start_s = vm["start-s"].as<double>();
    if (n_train == 4)
      d.start_s = ident::passage_end_time(vm["entry-s"].as<double>(), vm["train-length-m"].as<double>(),
                                          vm["bridge-length-m"].as<double>(), vm["speed-kmh"].as<double>() / 3.6);
    std::vector<std::string> files{o.scenario};
    files.insert(files.end(), o.more.begin(), o.more.end());
    std::vector<std::vector<std::string>> rows, amp_rows;
    std::vector<std::string> failures;
    std::vector<double> f, zl, ze, zh;
    for (const auto& path : files) {
      try {
        const io::Record rec = io::read_record(path);
        const std::size_t ch = rec.channel(vm["channel"].as<std::string>());
        const ident::DecayResult r = ident::analyse_decay(rec.data.col(static_cast<Index>(ch)), rec.fs_hz, rec.t0_s, d);
        rows.push_back({path, rec.channels[ch], fmt(r.start_s), r.start_detected ? "detected" : "given", fmt(r.end_s),
                        fmt(r.n_cycles, "%.1f"), fmt(r.frequency_hz), fmt(r.zeta_log_decrement), fmt(r.zeta_envelope_fit),
                        fmt(r.envelope_residual, "%.4f"),
                        fmt(r.zeta_hilbert), fmt(r.frequency_hilbert_hz), fmt(r.amplitude_start), fmt(r.amplitude_end),
                        fmt(r.law_zeta0), fmt(r.law_zeta_slope), fmt(r.law_f0_hz), fmt(r.law_f_slope_hz)});
        for (const auto& p : r.by_amplitude)
          amp_rows.push_back({path, fmt(p.t_s), fmt(p.amplitude), fmt(p.frequency_hz), fmt(p.damping_ratio)});
        f.push_back(r.frequency_hz);
        zl.push_back(r.zeta_log_decrement);
        ze.push_back(r.zeta_envelope_fit);
        zh.push_back(r.zeta_hilbert);
        if (!o.quiet)
          std::printf("%s: decay from %.3f s (%s), %.1f cycles: f = %.4f Hz, zeta = %.3f %% (log dec), %.3f %% (envelope), %.3f %% (Hilbert)\n",
                      path.c_str(), r.start_s, r.start_detected ? "detected" : "given", r.n_cycles, r.frequency_hz,
                      100 * r.zeta_log_decrement, 100 * r.zeta_envelope_fit, 100 * r.zeta_hilbert);
      } catch (const InputError& e) {
        failures.push_back(path + ": " + e.what());
      }
    }
    make_out_dir(o.out);
    io::write_table_csv(o.out + "/decay.csv",
                        {"record", "channel", "start_s", "start", "end_s", "n_cycles", "frequency_hz", "zeta_log_decrement",
                         "zeta_envelope_fit", "envelope_residual", "zeta_hilbert", "frequency_hilbert_hz", "amplitude_start", "amplitude_end",
                         "law_zeta0", "law_zeta_per_amplitude", "law_f0_hz", "law_f_hz_per_amplitude"},
                        rows);
    io::write_table_csv(o.out + "/decay_amplitude.csv", {"record", "t_s", "amplitude", "frequency_hz", "damping_ratio"}, amp_rows);
    std::vector<std::vector<std::string>> summary;
    for (const auto& [name, v] : std::vector<std::pair<std::string, std::vector<double>*>>{
             {"frequency_hz", &f}, {"zeta_log_decrement", &zl}, {"zeta_envelope_fit", &ze}, {"zeta_hilbert", &zh}}) {
      const ident::Statistic s = ident::statistic(*v);
      summary.push_back({name, fmt(s.mean), fmt(s.std), std::to_string(s.n)});
    }
    io::write_table_csv(o.out + "/decay_summary.csv", {"estimate", "mean", "std", "n"}, summary);
    std::vector<std::string> inputs = {o.scenario};
    inputs.insert(inputs.end(), o.more.begin(), o.more.end());
    io::write_manifest(o.out + "/manifest.toml", start_manifest(o, "decay", inputs), nullptr);
    if (!failures.empty()) {
      for (const auto& e : failures) std::fprintf(stderr, "viaduct decay: error: %s\n", e.c_str());
      return usage_error;
    }
    if (!o.quiet) std::printf("wrote %s/decay.csv, decay_amplitude.csv, decay_summary.csv\n", o.out.c_str());
    return ok;
  };
  return c;
}

}  // namespace viaduct::cli
