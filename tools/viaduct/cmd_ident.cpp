// viaduct frf / shaker / modal-fit / decay: forced-vibration tests and free decay, measured or
// simulated (issue #4). Parsing and output only; the numerics live in ident:: and study::.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>

#include "cli.hpp"
#include "viaduct/ident/decay.hpp"
#include "viaduct/ident/frf.hpp"
#include "viaduct/ident/frf_estimate.hpp"
#include "viaduct/ident/modal_fit.hpp"
#include "viaduct/io/frf.hpp"
#include "viaduct/io/record.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/study/forced.hpp"

namespace viaduct::cli {

namespace {

// "" for NaN (not known; pandas reads it as NaN): write_table_csv refuses a written "nan".
std::string ident_fmt(double v, const char* f = "%.8g") {
  if (std::isnan(v)) return "";
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

// The exciter and responses of a simulated forced test (frf SCENARIO, shaker).
struct ForcedOptions {
  std::optional<double> force_at;
  std::vector<std::string> response_at;
  std::string quantity = "acc";
};

// Exciter and responses from --force-at / --response-at, or the scenario's stations.
study::ForcedSetup forced_setup(const model::Structure& s, const study::Scenario& sc, const ForcedOptions& f) {
  study::ForcedSetup setup;
  if (!f.force_at) throw InputError("--force-at X (the exciter's position on the deck [m]) is required");
  setup.force_x_m = *f.force_at;
  setup.quantity = quantity_option(f.quantity);
  if (!f.response_at.empty()) {
    for (const auto& r : f.response_at) {
      const auto [name, x] = named_position(r, "--response-at");
      setup.responses.push_back(study::deck_station_at(s, name, x));
    }
  } else {
    setup.responses = sc.stations;
  }
  return setup;
}

void add_forced_options(po::options_description& d, ForcedOptions& f) {
  d.add_options()("force-at", optional_value(f.force_at), "exciter position: global x on the deck [m] (required)")(
      "response-at", list_value(f.response_at),
      "response point NAME=X or X on the deck [m] (repeatable; default: the scenario's stations)")(
      "quantity", value(f.quantity), "responses as acc, vel or disp");
}

struct FrfOptions {
  ForcedOptions forced;
  std::optional<double> f_min, f_max;
  long n_freq = 1161;
  std::optional<std::string> force, force_record, steps;
  std::vector<std::string> responses;
  std::string method = "welch", estimator = "h1";
  long nperseg = 4096;
  std::string window = "hann";
  double settle_cycles = 30.0, settle_s = 0.0;
};

int frf_from_scenario(const Common& o, const FrfOptions& fo) {
  const io::FlatScenario flat = load_scenario(o);
  const study::Scenario sc = io::to_scenario(flat);
  const model::Structure s = model::build_structure(sc.bridge, sc.track);
  const study::ForcedSetup setup = forced_setup(s, sc, fo.forced);
  const double f0 = fo.f_min.value_or(1.0);
  const double f1 = fo.f_max.value_or(30.0);
  const long n = fo.n_freq;
  if (!(f0 > 0.0) || !(f1 > f0)) throw InputError("--f-min must be > 0 and --f-max > --f-min");
  if (n < 2 || n > 1000000) throw InputError("--n-freq must be in 2..1000000");
  const Vector f = Vector::LinSpaced(n, f0, f1);
  const ident::Frf frf = study::model_frf(s, setup, f, o.threads, progress_printer("frf", o.quiet, "frequencies"));
  make_out_dir(o.out);
  io::write_frf_csv(o.out + "/frf.csv", frf);
  io::Manifest man = start_manifest(o, "frf");
  man.extra = {{"force_at_m", ident_fmt(setup.force_x_m)}, {"n_dofs", std::to_string(s.n_dofs)}};
  io::write_manifest(o.out + "/manifest.toml", man, flat);
  if (!o.quiet)
    std::printf("model FRF: %ld DOFs, %ld frequencies %.4g-%.4g Hz, %zu responses; wrote %s/frf.csv\n",
                static_cast<long>(s.n_dofs), n, f0, f1, setup.responses.size(), o.out.c_str());
  return ok;
}

// The stepped-sine table of an estimate: one row per step and response, in the FRF's order.
void write_stepped_table(const std::string& path, const ident::FrfEstimate& e, const io::FrfInputs& in) {
  std::vector<std::vector<std::string>> rows;
  for (std::size_t j = 0; j < e.order.size(); ++j) {
    const auto& p = e.points[e.order[j]];
    for (Index c = 0; c < in.responses.cols(); ++c)
      rows.push_back({std::to_string(e.order[j] + 1), ident_fmt(p.frequency_hz), ident_fmt(p.t_from_s), ident_fmt(p.t_to_s), ident_fmt(p.n_cycles, "%.1f"),
                      in.response_channels[static_cast<std::size_t>(c)], ident_fmt(std::abs(p.force)), ident_fmt(p.force_distortion, "%.3e"),
                      ident_fmt(p.response_distortion[c], "%.3e"), ident_fmt(p.settle_change[c], "%.3e")});
  }
  io::write_table_csv(path,
                      {"step", "frequency_hz", "t_from_s", "t_to_s", "n_cycles", "channel", "force_amplitude", "force_distortion",
                       "response_distortion", "settle_change"},
                      rows);
}

ident::FrfEstimateOptions estimate_options(const FrfOptions& fo) {
  ident::FrfEstimateOptions eo;
  eo.method = ident::frf_method(fo.method, "--method");
  if (eo.method == ident::FrfMethod::welch) {
    if (fo.estimator != "h1" && fo.estimator != "h2") throw InputError("--estimator must be h1 or h2, got '" + fo.estimator + "'");
    eo.h2 = fo.estimator == "h2";
    eo.welch.nperseg = fo.nperseg;
    eo.welch.window = signal::window_of(fo.window, "--window");
  }
  eo.f_min_hz = fo.f_min;
  eo.f_max_hz = fo.f_max;
  if (eo.method == ident::FrfMethod::stepped && fo.steps) eo.steps = io::read_steps_csv(*fo.steps);
  eo.stepped.settle_cycles = fo.settle_cycles;
  eo.stepped.settle_s = fo.settle_s;
  return eo;
}

int frf_from_record(const Common& o, const FrfOptions& fo) {
  if (!o.set.empty()) throw InputError("--set applies to scenarios; " + o.scenario + " is a record");
  const io::Record rec = read_record(o.scenario, o);
  if (!fo.force) throw InputError("missing force channel: name it with --force <channel> (e.g. force_N)");
  std::optional<io::Record> frec;
  if (fo.force_record) frec = read_record(*fo.force_record, o);
  const io::FrfInputs in = io::frf_inputs(rec, o.scenario, frec ? &*frec : nullptr, *fo.force, fo.responses);
  for (const auto& n : in.notes) std::cerr << "viaduct frf: warning: " << n << "\n";
  make_out_dir(o.out);
  ident::FrfEstimateOptions eo = estimate_options(fo);
  if (eo.method == ident::FrfMethod::stepped && eo.steps.empty()) {
    // Detected here rather than inside estimate_frf: the schedule is written before the dwells
    // are fitted, so that it is there to look at when a dwell is refused.
    eo.steps = ident::detect_steps(in.force, in.fs_hz, in.t0_s);
    io::write_steps_csv(o.out + "/steps-detected.csv", eo.steps);
    if (!o.quiet)
      std::printf("no --steps: detected %zu steps from the force (%.4g to %.4g Hz); wrote %s/steps-detected.csv\n", eo.steps.size(),
                  eo.steps.front().frequency_hz, eo.steps.back().frequency_hz, o.out.c_str());
  }
  const ident::FrfEstimate e = ident::estimate_frf(in.force, in.responses, in.fs_hz, in.t0_s, eo);
  ident::Frf frf = e.frf;
  if (!o.quiet && e.n_segments > 0) std::printf("Welch: %ld segments of %ld samples\n", static_cast<long>(e.n_segments), fo.nperseg);
  if (!e.points.empty()) {
    write_stepped_table(o.out + "/stepped.csv", e, in);
    if (!o.quiet) {
      std::printf("stepped sine: %ld steps; worst settle change %.2e, worst distortion (THD+N) %.2e; wrote %s/stepped.csv\n",
                  static_cast<long>(e.points.size()), e.worst_settle_change, e.worst_distortion, o.out.c_str());
      if (e.worst_settle_change > 0.05)
        std::fprintf(stderr, "viaduct frf: warning: a step's FRF changed by %.0f %% between the halves of its dwell (transient left, "
                     "or noise on a small response): see settle_change in stepped.csv; raise --settle-cycles if it is the transient\n",
                     100 * e.worst_settle_change);
    }
  }
  io::label_frf(frf, in);
  io::write_frf_csv(o.out + "/frf.csv", frf);
  std::vector<std::string> inputs = {o.scenario};
  if (fo.force_record) inputs.push_back(*fo.force_record);
  if (fo.steps && eo.method == ident::FrfMethod::stepped) inputs.push_back(*fo.steps);
  io::write_manifest(o.out + "/manifest.toml", start_manifest(o, "frf", inputs), nullptr);
  if (!o.quiet)
    std::printf("%s FRF: %ld frequencies, %zu responses to %s; wrote %s/frf.csv\n", fo.method.c_str(),
                static_cast<long>(frf.frequency_hz.size()), in.response_channels.size(), in.force_channel.c_str(), o.out.c_str());
  return ok;
}

struct ShakerOptions {
  ForcedOptions forced;
  std::optional<std::string> stepped, steps, swept;
  double dwell_s = 10.0, sweep_s = 120.0;
  std::optional<double> tail_s;
  double amplitude_kN = 10.0, fs_hz = 200.0;
  int substeps = 0;
  double snr_db = -1.0;
  unsigned seed = 1;
};

struct ModalFitCliOptions {
  ident::ModalFitOptions fit;
  bool no_refine = false;
  std::optional<std::string> model;
  std::vector<std::string> sensors;
};

struct DecayCliOptions {
  std::optional<std::string> channel;
  std::optional<double> frequency_hz, start_s, end_s, entry_s, speed_kmh, train_length_m, bridge_length_m;
  ident::DecayOptions decay;
};

// modes.csv, shapes.csv and stabilization.csv of a modal fit; returns the rows of modes.csv.
std::vector<std::vector<std::string>> write_modal_fit(const std::string& out, const ident::Frf& frf, const ident::ModalFitResult& fit) {
  std::vector<std::vector<std::string>> mode_rows, shape_rows;
  auto add = [&](const std::string& method, const std::vector<ident::IdentifiedMode>& modes) {
    for (std::size_t k = 0; k < modes.size(); ++k) {
      const ident::IdentifiedMode& m = modes[k];
      mode_rows.push_back({method, std::to_string(k + 1), ident_fmt(m.frequency_hz), ident_fmt(m.damping_ratio),
                           m.response >= 0 ? frf.responses[static_cast<std::size_t>(m.response)] : "all", m.note});
      for (Index r = 0; r < m.shape.size(); ++r)
        shape_rows.push_back({method, std::to_string(k + 1), frf.responses[static_cast<std::size_t>(r)], ident_fmt(m.shape[r].real()),
                              ident_fmt(m.shape[r].imag())});
    }
  };
  add("peak-picking", fit.peak_picking);
  add("circle-fit", fit.circle_fit);
  add("lscf-diagram", fit.lscf.diagram_modes);
  add("lscf", fit.lscf.modes);
  make_out_dir(out);
  io::write_table_csv(out + "/modes.csv", {"method", "mode", "frequency_hz", "damping_ratio", "response", "note"}, mode_rows);
  io::write_table_csv(out + "/shapes.csv", {"method", "mode", "response", "re", "im"}, shape_rows);
  std::vector<std::vector<std::string>> stab;
  for (const auto& p : fit.lscf.poles)
    stab.push_back({std::to_string(p.order), ident_fmt(p.frequency_hz), ident_fmt(p.damping_ratio),
                    p.status == ident::PoleStatus::stable ? "stable" : p.status == ident::PoleStatus::stable_frequency ? "frequency" : "new"});
  io::write_table_csv(out + "/stabilization.csv", {"order", "frequency_hz", "damping_ratio", "status"}, stab);
  return mode_rows;
}

// mac.csv: the LSCF modes against the model's, and the best match of each on stdout.
void write_mac(const std::string& out, const ident::LscfResult& ls, const study::ModelModesAtResponses& md, bool quiet) {
  ident::ComplexMatrix id_shapes(md.shape.rows(), static_cast<Index>(ls.modes.size()));
  for (std::size_t k = 0; k < ls.modes.size(); ++k) id_shapes.col(static_cast<Index>(k)) = ls.modes[k].shape;
  const Matrix m = ident::mac(id_shapes, md.shape);
  std::vector<std::vector<std::string>> rows;
  for (Index i = 0; i < m.rows(); ++i)
    for (Index j = 0; j < m.cols(); ++j)
      rows.push_back({std::to_string(i + 1), ident_fmt(ls.modes[static_cast<std::size_t>(i)].frequency_hz), std::to_string(j + 1),
                      ident_fmt(md.frequency_hz[j]), ident_fmt(m(i, j), "%.4f")});
  io::write_table_csv(out + "/mac.csv", {"mode", "frequency_hz", "model_mode", "model_frequency_hz", "mac"}, rows);
  if (quiet || m.cols() == 0) return;
  std::printf("\nLSCF modes against the model (best MAC):\n");
  for (Index i = 0; i < m.rows(); ++i) {
    Index j = 0;
    m.row(i).maxCoeff(&j);
    const double f = ls.modes[static_cast<std::size_t>(i)].frequency_hz;
    std::printf("  mode %ld %.4f Hz ~ model mode %ld %.4f Hz (%+.2f %%), MAC %.3f\n", static_cast<long>(i + 1), f,
                static_cast<long>(j + 1), md.frequency_hz[j], 100 * (f / md.frequency_hz[j] - 1), m(i, j));
  }
}

}  // namespace

Command frf_command() {
  Command c = record_command("frf", "SCENARIO|RECORD",
                             "FRFs: the model's by a direct frequency solve, or estimated from force and response records (frf.csv)");
  const auto declare = [](po::options_description& d, FrfOptions& f) {
    add_forced_options(d, f.forced);
    d.add_options()("f-min", optional_value(f.f_min), "[Hz] lowest frequency (scenario: default 1; swept: band)")(
        "f-max", optional_value(f.f_max), "[Hz] highest frequency (scenario: default 30; swept: band)")(
        "n-freq", value(f.n_freq), "scenario: frequencies, evenly spaced")(
        "force", optional_value(f.force), "record: the force channel (N or kN)")(
        "force-record", optional_value(f.force_record), "record: the force in another record (same rate and samples)")(
        "response", list_value(f.responses), "record: response channel (repeatable; default: every m, mps, mps2 channel)")(
        "method", value(f.method), "record: welch, stepped or swept")(
        "estimator", value(f.estimator), "welch: h1 or h2")(
        "nperseg", value(f.nperseg), "welch: samples per segment")(
        "window", value(f.window), "welch: hann or rectangular (boxcar: SciPy's name for it) (half-overlapping segments)")(
        "steps", optional_value(f.steps), "stepped: the schedule CSV (t_start_s,t_end_s,frequency_hz); default: detected from the force")(
        "settle-cycles", value(f.settle_cycles), "stepped: drive cycles discarded per step")(
        "settle-s", value(f.settle_s), "stepped: at least this long discarded [s]");
  };
  c.usage_and_samples =
      "With a SCENARIO (.toml): solves (K - w^2 M + i w C) x = F on the assembled structure (track\n"
      "included) for a unit force at --force-at, and writes the responses per newton.\n"
      "With a RECORD (CSV, UFF or .mat): estimates the FRF of every response to --force: Welch H1 (or H2)\n"
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
  const auto body = [](const Common& o, const FrfOptions& f) {
    return is_scenario_path(o.scenario) ? frf_from_scenario(o, f) : frf_from_record(o, f);
  };
  return bound(std::move(c), +declare, +body);
}

Command shaker_command() {
  Command c = command("shaker", "SCENARIO", "simulated forced-vibration test (stepped or swept sine, Newmark): a synthetic record");
  const auto declare = [](po::options_description& d, ShakerOptions& sh) {
    add_forced_options(d, sh.forced);
    d.add_options()("stepped", optional_value(sh.stepped), "stepped sine F0:F1:DF [Hz] (first, last, step)")(
        "steps", optional_value(sh.steps), "stepped sine from a schedule CSV instead (contiguous from t = 0)")(
        "dwell-s", value(sh.dwell_s), "stepped: dwell per frequency [s]")(
        "swept", optional_value(sh.swept), "linear sweep F0:F1 [Hz]")(
        "sweep-s", value(sh.sweep_s), "swept: sweep duration [s]")(
        "tail-s", optional_value(sh.tail_s), "recording after the force stops [s] (default: 0; swept: 20)")(
        "amplitude-kN", value(sh.amplitude_kN), "force amplitude [kN]")(
        "fs-hz", value(sh.fs_hz), "sampling rate of the record [Hz]")(
        "substeps", value(sh.substeps), "Newmark steps per sample (0: period error below 1e-4)")(
        "snr-db", value(sh.snr_db), "add Gaussian noise at this SNR to every channel (< 0: none)")(
        "seed", value(sh.seed), "noise seed");
  };
  c.usage_and_samples =
      "Integrates the structure from rest under a sine force at --force-at (Newmark, fine enough\n"
      "steps that the drive frequencies are exact to 1e-4) and writes OUT/record.csv (t_s, force_N,\n"
      "<response>_acc_mps2, or _vel_mps / _disp_m) and, for stepped sine, OUT/steps.csv: the inputs of viaduct frf.\n\n"
      "Sample runs:\n"
      "  viaduct shaker scenarios/old-guadiana-talgo.toml --force-at 6 --stepped 9:11:0.5 --dwell-s 6 --out out/shaker\n"
      "  viaduct shaker scenarios/hslm-simply-supported.toml --force-at 5 --swept 2:30 --sweep-s 60 --snr-db 40 --out out/sweep\n";
  const auto body = [](const Common& o, const ShakerOptions& sh) {
    const io::FlatScenario flat = load_scenario(o);
    const study::Scenario sc = io::to_scenario(flat);
    const model::Structure s = model::build_structure(sc.bridge, sc.track);
    const study::ForcedSetup setup = forced_setup(s, sc, sh.forced);
    study::ShakerTest t;
    t.amplitude_N = sh.amplitude_kN * 1e3;
    t.fs_hz = sh.fs_hz;
    t.substeps = sh.substeps;
    t.noise_snr_db = sh.snr_db;
    t.seed = sh.seed;
    t.tail_s = sh.tail_s.value_or(sh.swept ? 20.0 : 0.0);
    const int n_kinds = int{sh.stepped.has_value()} + int{sh.steps.has_value()} + int{sh.swept.has_value()};
    if (n_kinds != 1) throw InputError("give exactly one of --stepped F0:F1:DF, --steps FILE or --swept F0:F1");
    auto split = [](const std::string& text) {
      std::vector<std::string> p;
      std::stringstream ss(text);
      std::string x;
      while (std::getline(ss, x, ':')) p.push_back(x);
      return p;
    };
    if (sh.stepped) {
      const auto p = split(*sh.stepped);
      if (p.size() != 3) throw InputError("--stepped takes F0:F1:DF, got '" + *sh.stepped + "'");
      const double f0 = to_number(p[0], "--stepped"), f1 = to_number(p[1], "--stepped"), df = to_number(p[2], "--stepped");
      if (!(df > 0.0) || !(f1 >= f0)) throw InputError("--stepped needs F1 >= F0 and DF > 0");
      const Index n = static_cast<Index>(std::floor((f1 - f0) / df + 1e-9)) + 1;
      t.steps = ident::regular_schedule(f0, f0 + df * static_cast<double>(n - 1), n, sh.dwell_s);
    } else if (sh.steps) {
      t.steps = io::read_steps_csv(*sh.steps);
    } else {
      t.kind = study::ShakerTest::Kind::swept;
      const auto p = split(*sh.swept);
      if (p.size() != 2) throw InputError("--swept takes F0:F1, got '" + *sh.swept + "'");
      t.sweep_f_start_hz = to_number(p[0], "--swept");
      t.sweep_f_end_hz = to_number(p[1], "--swept");
      t.sweep_s = sh.sweep_s;
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
    if (sh.steps) man.inputs.push_back(*sh.steps);
    man.wall_s = r.wall_s;
    man.extra = {{"force_at_m", ident_fmt(setup.force_x_m)},
                 {"newmark_steps", std::to_string(r.n_steps)},
                 {"fs_hz", ident_fmt(r.fs_hz)},
                 {"snr_db", ident_fmt(t.noise_snr_db)}};
    io::write_manifest(o.out + "/manifest.toml", man, flat);
    if (!o.quiet)
      std::printf("shaker: %.1f s of record at %.6g Hz (%ld Newmark steps, %.1f s); wrote %s/record.csv%s\n",
                  t.duration_s(), r.fs_hz, static_cast<long>(r.n_steps), r.wall_s, o.out.c_str(),
                  t.kind == study::ShakerTest::Kind::stepped ? " and steps.csv" : "");
    return ok;
  };
  return bound(std::move(c), +declare, +body);
}

Command modal_fit_command() {
  Command c = command("modal-fit", "FRF", "modal parameters from an FRF file: peak picking, circle fit, LSCF + stabilization, MAC");
  const auto declare = [](po::options_description& d, ModalFitCliOptions& m) {
    d.add_options()("no-refine", po::bool_switch(&m.no_refine), "LSCF: keep the stabilization diagram's values (no refinement, no split test)")(
        "f-min", value(m.fit.f_min_hz), "[Hz] band fitted")(
        "f-max", value(m.fit.f_max_hz), "[Hz] band fitted")(
        "max-order", value(m.fit.max_order), "LSCF: largest model order (even)")(
        "cluster-tol", value(m.fit.cluster_tol), "LSCF: relative frequency spread of one mode's stable poles")(
        "min-prominence", value(m.fit.min_relative_prominence), "peak picking: peaks below this share of the largest are ignored")(
        "model", optional_value(m.model), "scenario whose modes are compared (MAC) with the identified ones")(
        "sensor", list_value(m.sensors), "with --model: response NAME=X on the deck [m] (default: the scenario's station of that name)");
  };
  c.usage_and_samples =
      "FRF is a frf.csv written by viaduct frf (measured or model). Writes OUT/modes.csv\n"
      "(method,mode,frequency_hz,damping_ratio,response,note for peak picking, circle fit, the LSCF\n"
      "stabilization diagram's modes (lscf-diagram) and the final LSCF modes (lscf: poles refined by\n"
      "nonlinear least squares on the FRFs, clusters hiding two modes split by a residual test)),\n"
      "OUT/shapes.csv, OUT/stabilization.csv (every physical pole of every order, with its status)\n"
      "and, with --model, OUT/mac.csv (identified LSCF modes against the model's modes).\n"
      "Plot with scripts/plot/plot_stabilization.py OUT.\n\n"
      "Sample runs:\n"
      "  viaduct frf scenarios/old-guadiana-talgo.toml --force-at 6 --f-min 5 --f-max 15 --n-freq 201 --out out/frf-model\n"
      "  viaduct modal-fit out/frf-model/frf.csv --f-min 7 --f-max 13 --max-order 20 --model scenarios/old-guadiana-talgo.toml --out out/fit\n"
      "  viaduct shaker scenarios/hslm-simply-supported.toml --force-at 7 --swept 2:30 --sweep-s 60 --snr-db 40 --out out/sweep\n"
      "  viaduct frf out/sweep/record.csv --force force_N --method swept --f-min 3 --f-max 28 --out out/frf-sweep\n"
      "  viaduct modal-fit out/frf-sweep/frf.csv --f-min 3 --f-max 28 --max-order 30 --out out/fit-sweep\n";
  const auto body = [](const Common& o, const ModalFitCliOptions& m) {
    const ident::Frf frf = io::read_frf_csv(o.scenario);
    ident::ModalFitOptions fo = m.fit;
    fo.refine = !m.no_refine;
    const ident::ModalFitResult fit = ident::modal_fit(frf, fo);
    if (!o.quiet)
      for (const auto& w : fit.warnings) std::fprintf(stderr, "viaduct modal-fit: warning: %s\n", w.c_str());
    const ident::LscfResult& ls = fit.lscf;
    const std::vector<std::vector<std::string>> mode_rows = write_modal_fit(o.out, frf, fit);
    if (!o.quiet) {
      std::printf("%-13s %4s %12s %10s  %s\n", "method", "mode", "f [Hz]", "zeta [%]", "note");
      for (const auto& r : mode_rows)
        std::printf("%-13s %4s %12.5f %10.3f  %s\n", r[0].c_str(), r[1].c_str(), std::stod(r[2]), 100 * std::stod(r[3]), r[5].c_str());
    }
    std::vector<std::string> inputs = {o.scenario};
    if (m.model) {
      inputs.push_back(*m.model);
      std::vector<std::pair<std::string, double>> sensors;
      for (const auto& sx : m.sensors) sensors.push_back(named_position(sx, "--sensor"));
      study::ModelModesAtResponses md;
      try {
        md = study::model_modes_at(io::to_scenario(io::load_flat(*m.model, {})), frf.responses, sensors, 1.5 * ls.f_max_hz);
      } catch (const InputError& e) {
        throw InputError("--model " + *m.model + ": " + e.what());
      }
      write_mac(o.out, ls, md, o.quiet);
    }
    io::write_manifest(o.out + "/manifest.toml", start_manifest(o, "modal-fit", inputs), nullptr);
    if (!o.quiet) std::printf("wrote %s/modes.csv, shapes.csv, stabilization.csv%s\n", o.out.c_str(), m.model ? ", mac.csv" : "");
    return ok;
  };
  return bound(std::move(c), +declare, +body);
}

Command decay_command() {
  Command c = record_command("decay", "RECORD...", "frequency and damping from free decays after train passages, against amplitude");
  c.many_positionals = true;
  const auto declare = [](po::options_description& d, DecayCliOptions& k) {
    d.add_options()("channel", optional_value(k.channel), "the response channel (required)")(
        "frequency-hz", optional_value(k.frequency_hz), "the mode to isolate [Hz] (required)")(
        "band-ratio", value(k.decay.band_ratio), "band-pass f(1 -/+ r)")(
        "order", value(k.decay.filter_order), "band-pass Chebyshev I order (0: no filter)")(
        "start-s", optional_value(k.start_s), "start of the free decay [s] (default: detected)")(
        "entry-s", optional_value(k.entry_s), "or: time the first axle enters the bridge [s] ...")(
        "speed-kmh", optional_value(k.speed_kmh), "... the train speed [km/h] ...")(
        "train-length-m", optional_value(k.train_length_m), "... its length [m] ...")(
        "bridge-length-m", optional_value(k.bridge_length_m), "... and the bridge length [m]: start when the last axle leaves")(
        "end-s", optional_value(k.end_s), "end of the free decay [s] (default: where it sinks into the noise, or the record's end)")(
        "skip-cycles", value(k.decay.skip_cycles), "cycles left out after the start (the band-pass filter's transient)")(
        "window-cycles", value(k.decay.window_cycles), "cycles per amplitude window")(
        "min-cycles", value(k.decay.min_cycles), "shortest decay accepted [cycles]");
  };
  c.usage_and_samples =
      "One or more records of passages. For each: band-pass around --frequency-hz, find the start of\n"
      "the free decay (given, from the train, or detected), estimate f and damping by logarithmic\n"
      "decrement, exponential fit of the cycle peaks and Hilbert envelope, and f and damping in\n"
      "windows along the decay. Writes OUT/decay.csv (one row per record), OUT/decay_amplitude.csv\n"
      "(record,t_s,amplitude,frequency_hz,damping_ratio) and OUT/decay_summary.csv (mean, std over\n"
      "records). Records that fail are named on stderr (exit 2) after the others are written.\n"
      "Plot with scripts/plot/plot_decay.py OUT.\n\n"
      "Sample runs:\n"
      "  viaduct run scenarios/old-guadiana-talgo.toml --set analysis.free_vibration_s=5 --out out/passage\n"
      "  viaduct decay out/passage/history.csv --channel S1_mid_acc --frequency-hz 10 --out out/decay\n";
  const auto body = [](const Common& o, const DecayCliOptions& k) {
    if (!k.channel) throw InputError("--channel is required");
    if (!k.frequency_hz) throw InputError("--frequency-hz (the mode to isolate) is required");
    ident::DecayOptions d = k.decay;
    d.frequency_hz = *k.frequency_hz;
    const int n_train = int{k.entry_s.has_value()} + int{k.speed_kmh.has_value()} + int{k.train_length_m.has_value()} +
                        int{k.bridge_length_m.has_value()};
    if (n_train != 0 && n_train != 4) throw InputError("--entry-s, --speed-kmh, --train-length-m and --bridge-length-m go together");
    if (n_train == 4 && k.start_s) throw InputError("give --start-s or the train's passage, not both");
    if (k.start_s) d.start_s = *k.start_s;
    if (k.end_s) d.end_s = *k.end_s;
    if (n_train == 4) d.start_s = ident::passage_end_time(*k.entry_s, *k.train_length_m, *k.bridge_length_m, *k.speed_kmh / 3.6);
    std::vector<std::string> files{o.scenario};
    files.insert(files.end(), o.more.begin(), o.more.end());
    std::vector<std::vector<std::string>> rows, amp_rows;
    std::vector<std::string> failures;
    std::vector<double> f, zl, ze, zh;
    for (const auto& path : files) {
      try {
        const io::Record whole = read_record(path, o);
        const std::size_t ch = whole.channel(*k.channel);
        const io::Record rec = usable(whole, {ch}, o);
        const ident::DecayResult r = ident::analyse_decay(rec.data.col(static_cast<Index>(ch)), rec.fs_hz, rec.t0_s, d);
        rows.push_back({path, rec.channels[ch], ident_fmt(r.start_s), r.start_detected ? "detected" : "given", ident_fmt(r.end_s),
                        ident_fmt(r.n_cycles, "%.1f"), ident_fmt(r.frequency_hz), ident_fmt(r.zeta_log_decrement), ident_fmt(r.zeta_envelope_fit),
                        ident_fmt(r.envelope_residual, "%.4f"),
                        ident_fmt(r.zeta_hilbert), ident_fmt(r.frequency_hilbert_hz), ident_fmt(r.amplitude_start), ident_fmt(r.amplitude_end),
                        ident_fmt(r.law_zeta0), ident_fmt(r.law_zeta_slope), ident_fmt(r.law_f0_hz), ident_fmt(r.law_f_slope_hz)});
        for (const auto& p : r.by_amplitude)
          amp_rows.push_back({path, ident_fmt(p.t_s), ident_fmt(p.amplitude), ident_fmt(p.frequency_hz), ident_fmt(p.damping_ratio)});
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
      // The spread of one record is not known: an empty cell, not 0; nor the mean of none.
      summary.push_back({name, s.n >= 1 ? ident_fmt(s.mean) : "", s.n >= 2 ? ident_fmt(s.std) : "", std::to_string(s.n)});
    }
    io::write_table_csv(o.out + "/decay_summary.csv", {"estimate", "mean", "std", "n"}, summary);
    std::vector<std::string> inputs = {o.scenario};
    inputs.insert(inputs.end(), o.more.begin(), o.more.end());
    io::write_manifest(o.out + "/manifest.toml", start_manifest(o, "decay", inputs), nullptr);
    if (!failures.empty()) {
      // One error per record that failed (the others are written), each in the command's terms
      // (a library field such as DecayOptions::end_s named as --end-s) by the dispatcher.
      std::string all;
      for (std::size_t i = 0; i < failures.size(); ++i) all += (i ? "\nviaduct decay: error: " : "") + failures[i];
      throw InputError(all);
    }
    if (!o.quiet) std::printf("wrote %s/decay.csv, decay_amplitude.csv, decay_summary.csv\n", o.out.c_str());
    return ok;
  };
  return bound(std::move(c), +declare, +body);
}

}  // namespace viaduct::cli
