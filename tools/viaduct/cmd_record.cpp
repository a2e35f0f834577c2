// viaduct filter / viaduct spectrum: processing of record files (measured or simulated).
#include <algorithm>
#include <cmath>
#include <charconv>
#include <filesystem>
#include <cstdio>
#include <functional>
#include <limits>
#include <optional>

#include "cli.hpp"
#include "viaduct/io/record.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/signal/iir.hpp"
#include "viaduct/signal/peaks.hpp"
#include "viaduct/signal/resample.hpp"
#include "viaduct/signal/spectrum.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/model/structure.hpp"
#include "viaduct/study/simulation.hpp"
#include "viaduct/study/comparison.hpp"
#include "viaduct/study/speed.hpp"

namespace viaduct::cli {

// Channels named by --channel (all when none).
std::vector<std::size_t> selected(const io::Record& r, const std::vector<std::string>& channels) {
  std::vector<std::size_t> out;
  if (!channels.empty())
    for (const auto& c : channels) out.push_back(r.channel(c));
  else
    for (std::size_t i = 0; i < r.channels.size(); ++i) out.push_back(i);
  return out;
}

void add_channel_option(po::options_description& d, std::vector<std::string>& channels) {
  d.add_options()("channel", list_value(channels), "channel to process (repeatable; default: all), full name or without its unit");
}

namespace {

std::string base_name(const io::Record& r, std::size_t c) {
  return r.channels[c].substr(0, r.channels[c].size() - r.units[c].size() - 1);
}

signal::Window window_option(const std::string& w) { return signal::window_of(w, "--window"); }

// The selected channels of `in`, each transformed by `fn` (which may change the length), as a
// record at rate fs_hz starting where `in` starts.
io::Record transform_channels(const io::Record& in, const std::vector<std::size_t>& chans, double fs_hz,
                              const std::function<Vector(const Vector&)>& fn) {
  io::Record out;
  out.fs_hz = fs_hz;
  out.t0_s = in.t0_s;
  std::vector<Vector> cols;
  for (std::size_t ch : chans) {
    cols.push_back(fn(in.data.col(static_cast<Index>(ch))));
    out.channels.push_back(in.channels[ch]);
    out.units.push_back(in.units[ch]);
  }
  out.data.resize(cols.front().size(), static_cast<Index>(cols.size()));
  for (std::size_t j = 0; j < cols.size(); ++j) out.data.col(static_cast<Index>(j)) = cols[j];
  return out;
}

struct FilterOptions {
  std::vector<std::string> channels;
  std::string band = "bandpass";
  double low_hz = 1.0, high_hz = 30.0;
  int order = 3;
  double ripple_db = 0.5;
};

// A time window and a frequency band, shared by spectrum and peaks.
struct WindowBand {
  std::optional<double> start_s, end_s, f_min, f_max;
};

void add_window_band_options(po::options_description& d, WindowBand& w) {
  d.add_options()("start-s", optional_value(w.start_s), "analyse from this time on [s] (default: the record's start)")(
      "end-s", optional_value(w.end_s), "analyse up to this time [s] (default: its end)")(
      "f-min", optional_value(w.f_min), "[Hz] lowest frequency kept (spectrum)")(
      "f-max", optional_value(w.f_max), "[Hz] highest frequency kept (spectrum)");
}

// Indices [first, last] of the frequencies inside the band; InputError when none is.
std::pair<Index, Index> band_of(const Vector& f, const WindowBand& w) {
  const double lo = w.f_min.value_or(-1.0), hi = w.f_max.value_or(std::numeric_limits<double>::infinity());
  Index first = 0, last = f.size() - 1;
  while (first < f.size() && f[first] < lo) ++first;
  while (last >= 0 && f[last] > hi) --last;
  if (first > last)
    throw InputError("--f-min/--f-max: no frequency of the spectrum (0 to " + format_number(f[f.size() - 1], 6) + " Hz) in the band");
  return {first, last};
}

struct SpectrumOptions {
  WindowBand wb;
  std::vector<std::string> channels;
  bool welch = false;
  long nperseg = 4096, noverlap = -1;
  std::string window = "hann", detrend = "constant";
};

struct PeaksOptions {
  WindowBand wb;
  std::vector<std::string> channels;
  bool time = false;
  std::string window = "hann";
  std::optional<double> min_height;
  double min_prominence = 0.0, min_distance = 0.0;
  int max_peaks = 10;
};

struct SpeedOptions {
  std::vector<std::string> channels;
  std::optional<std::string> model, station, train, second;
  std::optional<double> sensor_distance_m;
  double lowpass_hz = 30.0;
  std::optional<double> distance_m;
  double v_min_kmh = 40.0, v_max_kmh = 400.0;
  int harmonics = 4;
  bool peaks = false;
  double min_interval_s = 0.1;
  std::string zero = "keep";
  double merge_m = 0.0;
};

struct ResampleOptions {
  std::vector<std::string> channels;
  std::optional<double> fs_hz;
  std::optional<int> decimate;
};

struct EnvelopeOptions {
  std::vector<std::string> channels;
  std::string kind = "rms";
  double window_s = 1.0;
};

}  // namespace

Command filter_command() {
  Command c = record_command("filter", "RECORD", "zero-phase Chebyshev I filtering of a record's channels (filtered.csv)");
  const auto declare = [](po::options_description& d, FilterOptions& f) {
    add_channel_option(d, f.channels);
    d.add_options()("band", value(f.band), "lowpass, highpass or bandpass")(
        "low-hz", value(f.low_hz), "lower band edge [Hz] (highpass, bandpass)")(
        "high-hz", value(f.high_hz), "upper band edge [Hz] (lowpass, bandpass)")(
        "order", value(f.order), "Chebyshev I order (band-pass: 2 x order poles)")(
        "ripple-db", value(f.ripple_db), "passband ripple [dB]; one pass is -ripple at the edges");
  };
  c.usage_and_samples =
      "RECORD is a CSV record (docs/records.md), e.g. a history.csv written by viaduct run.\n"
      "Filters forward and backward as scipy.signal.sosfiltfilt(cheby1(order, ripple_db, edges,\n"
      "band, fs=fs, output='sos'), x) does, and writes OUT/filtered.csv with the same columns.\n\n"
      "Sample runs:\n"
      "  viaduct filter data/records/synthetic-deck.csv --low-hz 1 --high-hz 30 --out out/filtered\n"
      "  viaduct filter data/records/synthetic-deck.csv --band lowpass --high-hz 15 --channel deck_acc --out out/lp\n";
  const auto body = [](const Common& o, const FilterOptions& f) {
    const io::Record whole = read_record(o.scenario, o);
    const auto chans = selected(whole, f.channels);
    const io::Record in = usable(whole, chans, o);
    signal::Cheby1Spec spec;
    const std::string& band = f.band;
    if (band == "bandpass") spec.band = signal::BandType::bandpass;
    else if (band == "lowpass") spec.band = signal::BandType::lowpass;
    else if (band == "highpass") spec.band = signal::BandType::highpass;
    else throw InputError("--band must be lowpass, highpass or bandpass, got '" + band + "'");
    spec.low_hz = f.low_hz;
    spec.high_hz = f.high_hz;
    spec.order = f.order;
    spec.ripple_db = f.ripple_db;
    const signal::Sos sos = signal::cheby1(spec, in.fs_hz);
    const io::Record out = transform_channels(in, chans, in.fs_hz, [&](const Vector& x) { return signal::sosfiltfilt(sos, x); });
    write_record_outputs(o, "filtered.csv", out);
    if (!o.quiet)
      std::printf("%zu channels, %ld samples at %.6g Hz; wrote %s/filtered.csv\n", chans.size(),
                  static_cast<long>(in.n_samples()), in.fs_hz, o.out.c_str());
    return ok;
  };
  return bound(std::move(c), +declare, +body);
}

Command spectrum_command() {
  Command c = record_command("spectrum", "RECORD", "amplitude spectrum or Welch PSD of a record's channels (spectrum.csv)");
  const auto declare = [](po::options_description& d, SpectrumOptions& s) {
    add_channel_option(d, s.channels);
    d.add_options()("welch", po::bool_switch(&s.welch), "Welch power spectral density instead of the amplitude spectrum")(
        "nperseg", value(s.nperseg), "Welch: samples per segment")(
        "noverlap", value(s.noverlap), "Welch: overlap in samples (-1: half a segment)")(
        "window", value(s.window), "hann or rectangular (boxcar: SciPy's name for it)")(
        "detrend", value(s.detrend), "Welch: constant, linear or none");
    add_window_band_options(d, s.wb);
  };
  c.usage_and_samples =
      "Amplitude spectrum: one-sided 2|X|/sum(w) of the whole record (a sine of amplitude a on a\n"
      "bin reads a with the rectangular window; Hann gives smoother peaks, correct amplitude at\n"
      "bin centres). Welch PSD: scipy.signal.welch conventions (unit^2/Hz). Writes\n"
      "OUT/spectrum.csv: frequency_hz, then <channel>_amp_<unit> or <channel>_psd_<unit>2_per_hz;\n"
      "--start-s/--end-s take a part of the record, --f-min/--f-max keep a band.\n\n"
      "Sample runs:\n"
      "  viaduct spectrum data/records/synthetic-deck.csv --out out/spectrum\n"
      "  viaduct spectrum data/records/synthetic-deck.csv --welch --nperseg 1024 --out out/psd\n";
  const auto body = [](const Common& o, const SpectrumOptions& s) {
    const io::Record whole = io::time_window(read_record(o.scenario, o), s.wb.start_s, s.wb.end_s, "--start-s/--end-s");
    const auto chans = selected(whole, s.channels);
    const io::Record in = usable(whole, chans, o);
    const signal::Window w = window_option(s.window);
    const bool welch = s.welch;
    std::vector<Vector> cols;
    Vector f;
    std::vector<std::string> names;
    if (welch) {
      signal::WelchOptions wo;
      wo.nperseg = s.nperseg;
      wo.noverlap = s.noverlap;
      wo.window = w;
      wo.detrend = signal::detrend_of(s.detrend, "--detrend");
      for (std::size_t ch : chans) {
        const signal::Psd p = signal::welch(in.data.col(static_cast<Index>(ch)), in.fs_hz, wo);
        f = p.frequency_hz;
        cols.push_back(p.density);
        names.push_back(base_name(in, ch) + "_psd_" + in.units[ch] + "2_per_hz");
      }
    } else {
      for (std::size_t ch : chans) {
        const signal::AmplitudeSpectrum a = signal::amplitude_spectrum(in.data.col(static_cast<Index>(ch)), in.fs_hz, w);
        f = a.frequency_hz;
        cols.push_back(a.amplitude);
        names.push_back(base_name(in, ch) + "_amp_" + in.units[ch]);
      }
    }
    const auto [first, last] = band_of(f, s.wb);
    f = Vector(f.segment(first, last - first + 1));
    for (auto& col : cols) col = Vector(col.segment(first, last - first + 1));
    make_out_dir(o.out);
    const std::string path = o.out + "/spectrum.csv";
    names.insert(names.begin(), "frequency_hz");
    cols.insert(cols.begin(), f);
    io::write_columns_csv(path, names, cols);
    io::write_manifest(o.out + "/manifest.toml", start_manifest(o, "spectrum", {o.scenario}), nullptr);
    if (!o.quiet)
      std::printf("%zu channels, %ld frequencies up to %.6g Hz; wrote %s\n", chans.size(), static_cast<long>(f.size()),
                  f[f.size() - 1], path.c_str());
    return ok;
  };
  return bound(std::move(c), +declare, +body);
}

Command peaks_command() {
  Command c = record_command("peaks", "RECORD", "peaks of a record's spectrum or time history, with interpolated positions (peaks.csv)");
  const auto declare = [](po::options_description& d, PeaksOptions& p) {
    add_channel_option(d, p.channels);
    d.add_options()("time", po::bool_switch(&p.time), "pick peaks of the time history (default: of the amplitude spectrum)")(
        "window", value(p.window), "spectrum window: hann or rectangular (boxcar)")(
        "min-height", optional_value(p.min_height), "keep peaks at least this high (channel unit)")(
        "min-prominence", value(p.min_prominence), "keep peaks at least this prominent (SciPy's definition)")(
        "min-distance", value(p.min_distance), "between kept peaks: Hz (spectrum) or s (time)")(
        "max-peaks", value(p.max_peaks), "keep the highest N (0: all)");
    add_window_band_options(d, p.wb);
  };
  c.usage_and_samples =
      "Writes OUT/peaks.csv: channel,unit,frequency_hz (or t_s),value,prominence, positions\n"
      "refined between samples (log-parabola). On a Hann spectrum a sine's frequency is found\n"
      "within 0.1 bin. --start-s/--end-s take a part of the record (on a passage, the free vibration\n"
      "after the train: the top peaks of the whole record are forcing lines), --f-min/--f-max a band.\n\n"
      "Sample runs:\n"
      "  viaduct peaks data/records/synthetic-deck.csv --channel deck_acc --max-peaks 3 --out out/peaks\n"
      "  viaduct peaks data/records/synthetic-deck.csv --channel deck_acc --start-s 4 --f-min 5 --f-max 20 --max-peaks 1 --out out/peaks-free\n"
      "  viaduct peaks data/records/synthetic-deck.csv --channel deck_disp --time --min-distance 0.2 --max-peaks 0 --out out/axles\n";
  const auto body = [](const Common& o, const PeaksOptions& p) {
    const io::Record whole = io::time_window(read_record(o.scenario, o), p.wb.start_s, p.wb.end_s, "--start-s/--end-s");
    if (p.time && (p.wb.f_min || p.wb.f_max)) throw InputError("--f-min/--f-max choose spectrum peaks: not with --time");
    const bool time = p.time;
    const signal::Window window = window_option(p.window);
    signal::PeakOptions po_;
    if (p.min_height) po_.min_height = *p.min_height;
    po_.min_prominence = p.min_prominence;
    const int max_peaks = p.max_peaks;
    if (max_peaks < 0) throw InputError("--max-peaks must be >= 0");
    po_.max_peaks = static_cast<std::size_t>(max_peaks);
    const double dist = p.min_distance;
    if (!(dist >= 0.0) || !std::isfinite(dist)) throw InputError("--min-distance must be >= 0");
    std::vector<std::string> chan, unit;
    std::vector<double> pos, val, prom;
    for (std::size_t ch : selected(whole, p.channels)) {
      const io::Record in = usable(whole, {ch}, o);  // each channel over its own valid span
      Vector y = in.data.col(static_cast<Index>(ch));
      double step = 1.0 / in.fs_hz, origin = in.t0_s;
      if (!time) {
        const auto a = signal::amplitude_spectrum(y, in.fs_hz, window);
        step = in.fs_hz / static_cast<double>(in.n_samples());
        const auto [first, last] = band_of(a.frequency_hz, p.wb);  // peaks inside the band only
        y = a.amplitude.segment(first, last - first + 1);
        origin = static_cast<double>(first) * step;
      }
      po_.min_distance = std::max<Index>(1, static_cast<Index>(std::ceil(dist / step)));
      for (const auto& pk : signal::find_peaks(y, po_)) {
        chan.push_back(in.channels[ch]);
        unit.push_back(in.units[ch]);
        pos.push_back(origin + pk.position * step);
        val.push_back(pk.value);
        prom.push_back(pk.prominence);
      }
    }
    std::vector<std::vector<std::string>> rows;
    for (std::size_t i = 0; i < pos.size(); ++i)
      rows.push_back({chan[i], unit[i], io::table_cell(pos[i]), io::table_cell(val[i]), io::table_cell(prom[i])});
    make_out_dir(o.out);
    const std::string path = o.out + "/peaks.csv";
    io::write_table_csv(path, {"channel", "unit", time ? "t_s" : "frequency_hz", "value", "prominence"}, rows);
    io::write_manifest(o.out + "/manifest.toml", start_manifest(o, "peaks", {o.scenario}), nullptr);
    if (!o.quiet) {
      for (std::size_t i = 0; i < pos.size() && i < 12; ++i)
        std::printf("  %-20s %s = %-12.6g value %.6g %s\n", chan[i].c_str(), time ? "t" : "f", pos[i], val[i], unit[i].c_str());
      std::printf("%zu peaks; wrote %s\n", pos.size(), path.c_str());
    }
    return ok;
  };
  return bound(std::move(c), +declare, +body);
}

namespace {

// What a record channel's unit compares with at a station: acceleration, deflection or strain.
study::ResponseKind kind_of(const io::Record& in, std::size_t ch) { return io::channel_quantity(in.units[ch], in.channels[ch], "--channel"); }

// --model: the record's channels against the station's simulated response at trial speeds.
std::vector<std::vector<std::string>> speed_by_signature(const Common& o, const SpeedOptions& s, const io::Record& whole,
                                                         std::vector<std::vector<std::string>>& axle_rows) {
  const io::FlatScenario flat = io::load_flat(*s.model);
  study::Scenario sc = io::to_scenario(flat);
  if (s.channels.empty()) throw InputError("--model: name the record's channels at --station with --channel");
  load::Train train;
  if (!s.train) {
    if (sc.trains.empty()) throw InputError("--model: " + *s.model + " has no train: give --train FILE");
    train = sc.trains.front();
  } else if (std::filesystem::is_regular_file(*s.train)) {
    train = io::read_train_file(*s.train);
  } else {
    const auto it = std::find_if(sc.trains.begin(), sc.trains.end(), [&](const load::Train& t) { return t.name == *s.train; });
    if (it == sc.trains.end()) throw InputError("--train: '" + *s.train + "' is neither a train file nor a train of " + *s.model);
    train = *it;
  }
  if (!s.station && sc.stations.size() != 1) throw InputError("--station: name the station of " + *s.model + " where the sensor sits");
  const std::size_t st = s.station ? station_index(sc, *s.station, "--station") : 0;
  const auto chans = selected(whole, s.channels);
  bool strain = false;
  for (std::size_t ch : chans) strain = strain || kind_of(whole, ch) == study::ResponseKind::strain;
  if (strain && sc.stations[st].fibre_m == 0.0)
    throw InputError("--station " + sc.stations[st].name + ": a strain channel needs stations[].fibre_m in " + *s.model);
  study::RunSettings rs = sc.settings;
  rs.filter.enabled = false;
  const study::PreparedModel pm = study::prepare_model(model::build_structure(sc.bridge, sc.track), sc.stations, rs, true, strain);
  const auto& spec = sc.stations[st];
  const double x_station = spec.on_deck ? pm.structure.span_start[spec.span] + spec.x_local : spec.x_track;
  std::vector<std::vector<std::string>> rows;
  auto num = [](double v) { return io::table_cell(v, 8); };
  const study::ZeroSpec zero = study::parse_zero(s.zero, "--zero");
  for (std::size_t ch : chans) {
    io::Record in = usable(whole, {ch}, o);
    const study::ResponseKind q = kind_of(in, ch);
    auto match = [&] {
      return study::match_train_signature(pm, rs, train, st, q, in.data.col(static_cast<Index>(ch)), in.fs_hz, in.t0_s, sc.settings.filter,
                                          s.v_min_kmh / 3.6, s.v_max_kmh / 3.6);
    };
    study::SignatureMatch m = match();
    if (study::quasi_static_kind(q)) {  // the zero of a deflection or strain: before the first axle reaches the deck
      const double entry = m.shift_s + (pm.structure.span_start.front() - pm.structure.path_start()) / m.speed;
      Vector x = in.data.col(static_cast<Index>(ch));
      const study::ZeroOutcome z = study::apply_zero(zero, x, in.fs_hz, in.t0_s, entry, in.channels[ch], in.units[ch], "--zero");
      if (!z.warning.empty()) std::fprintf(stderr, "viaduct speed: warning: %s\n", z.warning.c_str());
      if (z.removed != 0.0) {
        in.data.col(static_cast<Index>(ch)) = x;
        m = match();
      }
    }
    const double dt_st = (x_station - pm.structure.path_start()) / m.speed;
    // The model's misfit (issue #39 item 5): checks that do not trust the model; a doubted model's
    // uncertainties (speed and first axle) cover the axles' timing alone too.
    const study::SignatureCheck check = study::check_train_signature(m, train, q, in.data.col(static_cast<Index>(ch)), in.fs_hz, in.t0_s,
                                                                     sc.settings.filter, s.v_min_kmh / 3.6, s.v_max_kmh / 3.6);
    const double entry = m.shift_s + dt_st;
    double entry_se = std::hypot(m.shift_se, dt_st / m.speed * m.speed_se);
    if (check.timing_checked && !check.flags.empty())
      entry_se = std::max(entry_se, (std::abs(entry - check.timing_entry_s) + 3 * check.timing_entry_se) / 3);
    const double unc = 3 * check.speed_se;
    const std::vector<std::string>& flags = check.flags;
    std::string flag;
    for (const auto& f : flags) {
      flag += (flag.empty() ? "" : "; ") + f;
      std::fprintf(stderr, "viaduct speed: warning: %s: %s\n", in.channels[ch].c_str(), f.c_str());
    }
    rows.push_back({in.channels[ch], "train-signature", num(m.speed * 3.6), num(unc * 3.6), "", std::to_string(m.n_evaluations),
                    num(entry), num(3 * entry_se), num(m.correlation), num(m.amplitude), flag});
    if (study::quasi_static_kind(q)) {  // the axles, where the channel sees them one by one
      const study::AxleMatch am = study::match_axles(in.data.col(static_cast<Index>(ch)), in.fs_hz, in.t0_s, train, m.speed, m.speed_se,
                                                     entry, entry_se, study::signature_filter(sc.settings.filter, q));
      for (const auto& a : am.axles)
        axle_rows.push_back({in.channels[ch], std::to_string(a.axle + 1), num(a.offset_m), num(a.load_n * 1e-3), num(a.t_s), num(3 * a.t_se),
                             a.seen ? "true" : "false", a.seen ? num(a.peak_t_s) : "", a.seen ? num(a.peak_value) : "",
                             a.seen ? num(a.peak_t_s - a.t_s) : ""});
      if (!o.quiet)
        std::printf("%-22s axles seen one by one: %zu of %zu (within %.1f ms of their time; RMS %.2f ms)\n", in.channels[ch].c_str(),
                    am.n_seen, am.axles.size(), am.tolerance_s * 1e3, am.rms_residual_s * 1e3);
    }
    if (!o.quiet)
      std::printf("%-22s train-signature %.3f km/h +- %.3f (3 standard errors); first axle at %s at %.4f s +- %.4f; correlation %.4f, "
                  "amplitude %.4g x model; %ld templates\n",
                  in.channels[ch].c_str(), m.speed * 3.6, unc * 3.6, spec.name.c_str(), entry, 3 * entry_se, m.correlation,
                  m.amplitude, static_cast<long>(m.n_evaluations));
  }
  return rows;
}

// A train for --train without --model: a train file, or hslm:A1 … hslm:A10.
load::Train train_alone(const std::string& t) {
  if (std::filesystem::is_regular_file(t)) return io::read_train_file(t);
  if (t.rfind("hslm:A", 0) == 0) {
    const std::string k = t.substr(6);
    int n = 0;
    const auto r = std::from_chars(k.data(), k.data() + k.size(), n);
    if (r.ec == std::errc() && r.ptr == k.data() + k.size() && n >= 1 && n <= 10)
      return load::hslm_a("HSLM-A" + std::to_string(n), load::hslm_a_row(n));
  }
  throw InputError("--train: '" + t + "' is neither a train file nor hslm:A1 … hslm:A10");
}

// --train without --model: the peaks of deflection or strain channels matched to the train's axles or bogies.
std::vector<std::vector<std::string>> speed_by_train(const Common& o, const SpeedOptions& s, const io::Record& whole) {
  const load::Train train = train_alone(*s.train);
  std::vector<std::vector<std::string>> rows;
  auto num = [](double v) { return io::table_cell(v, 8); };
  for (std::size_t ch : selected(whole, s.channels)) {
    const io::Record in = usable(whole, {ch}, o);
    if (!study::quasi_static_kind(kind_of(in, ch)))
      throw InputError("--train without --model: channel " + in.channels[ch] + " is not a deflection or strain; the axles are timed on deflection "
                       "or strain channels (or give --model)");
    study::TrainTimingOptions to;
    to.v_min = s.v_min_kmh / 3.6;
    to.v_max = s.v_max_kmh / 3.6;
    to.merge_m = s.merge_m;
    to.filter.cheby.band = signal::BandType::lowpass;
    to.filter.cheby.high_hz = std::min(s.lowpass_hz, 0.4 * in.fs_hz);
    const study::TrainTiming t = study::speed_from_train(in.data.col(static_cast<Index>(ch)), in.fs_hz, in.t0_s, train, to);
    rows.push_back({in.channels[ch], "train-geometry", num(t.speed * 3.6), num(3 * t.speed_se * 3.6), "", std::to_string(t.n_matched),
                    num(t.entry_s), num(3 * t.entry_se), "", "", ""});
    if (!o.quiet)
      std::printf("%-22s train-geometry %.3f km/h +- %.3f (3 standard errors); first axle at the sensor at %.4f s +- %.4f; %zu of %zu %s "
                  "matched (%zu peaks; RMS %.2f ms)\n",
                  in.channels[ch].c_str(), t.speed * 3.6, 3 * t.speed_se * 3.6, t.entry_s, 3 * t.entry_se, t.n_matched, t.n_groups,
                  t.merge_m == 0 ? "axles" : ("groups of axles closer than " + format_number(t.merge_m, 3) + " m").c_str(), t.n_peaks,
                  t.rms_residual_s * 1e3);
  }
  return rows;
}

// --second-channel with --sensor-distance-m: the delay of one sensor behind the other.
std::vector<std::string> speed_by_delay(const Common& o, const SpeedOptions& s, const io::Record& whole) {
  if (s.channels.size() != 1) throw InputError("--sensor-distance-m: give the first sensor's --channel (one) and --second-channel");
  const std::size_t a = whole.channel(s.channels.front()), b = whole.channel(*s.second);
  const io::Record in = usable(whole, {a, b}, o);
  require_positive(*s.sensor_distance_m, "--sensor-distance-m");
  study::FilterSpec f;  // a low-pass on both: the first channel's noise is delayed with it, and must be smooth
  f.cheby.band = signal::BandType::lowpass;
  f.cheby.high_hz = s.lowpass_hz;
  const double max_delay = *s.sensor_distance_m / (s.v_min_kmh / 3.6);
  const study::Delay d = study::delay_between(in.data.col(static_cast<Index>(a)), in.data.col(static_cast<Index>(b)), in.fs_hz, f, max_delay);
  if (!(d.delay_s > 0))
    throw InputError("--second-channel " + in.channels[b] + " leads " + in.channels[a] + " (delay " + format_number(d.delay_s, 4) +
                     " s): the train passed the second sensor first; swap them");
  const double v = *s.sensor_distance_m / d.delay_s, v_se = v / d.delay_s * d.delay_se;
  if (d.correlation < study::kMinSignatureCorrelation)
    throw InputError("no train found: " + in.channels[b] + " against " + in.channels[a] + " delayed correlates " +
                     format_number(d.correlation, 3) + " at best (one train seen by both: at least " +
                     format_number(study::kMinSignatureCorrelation, 3) + ")");
  if (v < s.v_min_kmh / 3.6 || v > s.v_max_kmh / 3.6)
    throw InputError("no train found between " + format_number(s.v_min_kmh, 4) + " and " + format_number(s.v_max_kmh, 4) +
                     " km/h: the delay " + format_number(d.delay_s, 4) + " s over " + format_number(*s.sensor_distance_m, 4) +
                     " m gives " + format_number(v * 3.6, 5) + " km/h");
  auto num = [](double x) { return io::table_cell(x, 8); };
  if (!o.quiet)
    std::printf("%s -> %s: delay %.5f s +- %.5f, %.3f km/h +- %.3f (3 standard errors), correlation %.4f\n", in.channels[a].c_str(),
                in.channels[b].c_str(), d.delay_s, 3 * d.delay_se, v * 3.6, 3 * v_se * 3.6, d.correlation);
  return {in.channels[a] + ">" + in.channels[b], "sensor-delay", num(v * 3.6), num(3 * v_se * 3.6), "", "2", "", "", num(d.correlation), "", ""};
}

}  // namespace

Command speed_command() {
  Command c = record_command("speed", "RECORD",
                             "train speed from a record: spectral lines of a characteristic distance, or axle peaks (speed.csv)");
  const auto declare = [](po::options_description& d, SpeedOptions& s) {
    add_channel_option(d, s.channels);
    d.add_options()("distance-m", optional_value(s.distance_m), "the train's characteristic distance d [m] (e.g. 13.14 for a Talgo rake, D for HSLM)")(
        "v-min-kmh", value(s.v_min_kmh), "lowest speed searched [km/h]")(
        "v-max-kmh", value(s.v_max_kmh), "highest speed searched [km/h]")(
        "harmonics", value(s.harmonics), "harmonics of v/d in the spectral comb")(
        "peaks", po::bool_switch(&s.peaks), "use axle-passage peaks (a channel that sees each axle) instead of spectral lines")(
        "min-interval-s", value(s.min_interval_s), "peaks: least time between two axle peaks [s]")(
        "model", optional_value(s.model), "a scenario: match the record to the station's simulated response to the train at trial speeds")(
        "station", optional_value(s.station), "--model: the scenario's station where the sensor sits")(
        "train", optional_value(s.train), "a train file (or hslm:A1 … hslm:A10; with --model also a train of the scenario, default its "
                                           "first); without --model: deflection or strain peaks matched to the train's axles or bogies")(
        "merge-m", value(s.merge_m), "--train without --model: axles closer than this [m] are one peak (0: axles, bogies or bogie pairs, "
                                     "whichever the record matches best)")(
        "second-channel", optional_value(s.second), "a second sensor along the track: the speed from its delay behind --channel")(
        "sensor-distance-m", optional_value(s.sensor_distance_m), "[m] the distance from --channel's sensor to --second-channel's")(
        "lowpass-hz", value(s.lowpass_hz), "--second-channel: both channels low-passed at this frequency [Hz] before the delay is fitted");
    add_zero_option(d, s.zero, "--model: ");
  };
  c.usage_and_samples =
      "Spectral: the speed whose harmonics k*v/d (k = 1..harmonics) best match the lines of the\n"
      "channel's Hann spectrum (zero-padded); uncertainty = one record bin at the highest harmonic.\n"
      "Peaks: v = d / median interval between axle peaks; uncertainty = standard error.\n"
      "--model SCENARIO: the train's signature. The station's response (acceleration, deflection\n"
      "or strain, as the channel's unit says) is simulated with the train's axles at trial speeds\n"
      "(log grid of 1 % steps over --v-min-kmh..--v-max-kmh, then golden section) and matched\n"
      "to the record: filtered alike (accelerations: the scenario's [filter]; deflection and\n"
      "strain: low-passed at its upper edge), aligned by cross-correlation, then amplitude, speed\n"
      "and shift fitted by least squares. Also gives the record time at which the first axle\n"
      "passes the station. Uncertainty = 3 standard errors of the fit (noise and any mismatch of\n"
      "model and record widen them; on simulated passages of five trains at 5 % noise the error\n"
      "stayed within 2.5 of them: tests/verification/test_speed_signature.cpp).\n"
      "--second-channel B --sensor-distance-m D: v = D / delay of B behind --channel, both\n"
      "low-passed at --lowpass-hz, the delay fitted by least squares with its standard error.\n"
      "Writes OUT/speed.csv: channel,method,speed_kmh,uncertainty_kmh,frequency_hz,n_used,\n"
      "first_axle_s,first_axle_uncertainty_s,correlation,amplitude. With --model also OUT/axles.csv\n"
      "for deflection and strain channels: each axle's time at the station (entry + offset/v, with\n"
      "3 standard errors) and the record's peak matched to it where the channel sees axles one by\n"
      "one (short influence lines: short spans, rails, cross-girders; peaks of 10 % of the largest\n"
      "prominence or more, within a tenth of the shortest time between axles; seen = false where\n"
      "the channel merges them).\n\n"
      "Sample runs:\n"
      "  viaduct speed data/records/synthetic-deck.csv --channel deck_acc --distance-m 13.14 --v-min-kmh 100 --v-max-kmh 250 --out out/speed\n"
      "  viaduct speed data/records/synthetic-deck.csv --channel deck_disp --distance-m 13.14 --peaks --min-interval-s 0.2 --out out/speed-peaks\n"
      "  viaduct speed data/records/logger-semicolon.csv --channel 'Disp S1 mid' --model scenarios/old-guadiana-talgo.toml --station S1_mid --v-min-kmh 150 --v-max-kmh 160 --out out/speed-model\n";
  const auto body = [](const Common& o, const SpeedOptions& s) {
    const io::Record in = read_record(o.scenario, o);
    const std::vector<std::string> header = {"channel", "method", "speed_kmh", "uncertainty_kmh", "frequency_hz", "n_used",
                                             "first_axle_s", "first_axle_uncertainty_s", "correlation", "amplitude", "flag"};
    if (s.train && !s.model && !s.sensor_distance_m && !s.distance_m) {
      const auto rows = speed_by_train(o, s, in);
      write_table_outputs(o, "speed.csv", header, rows);
      if (!o.quiet) std::printf("wrote %s/speed.csv\n", o.out.c_str());
      return ok;
    }
    if (s.model || s.sensor_distance_m) {
      if (s.model && s.sensor_distance_m) throw InputError("give --model or --sensor-distance-m, not both");
      if (s.sensor_distance_m.has_value() != s.second.has_value()) throw InputError("--sensor-distance-m and --second-channel go together");
      std::vector<std::vector<std::string>> axle_rows;
      const auto rows = s.model ? speed_by_signature(o, s, in, axle_rows) : std::vector<std::vector<std::string>>{speed_by_delay(o, s, in)};
      make_out_dir(o.out);
      io::write_table_csv(o.out + "/speed.csv", header, rows);
      if (s.model)
        io::write_table_csv(o.out + "/axles.csv", {"channel", "axle", "offset_m", "load_kN", "t_s", "t_uncertainty_s", "seen", "peak_t_s",
                                                   "peak_value", "residual_s"}, axle_rows);
      std::vector<std::string> inputs{o.scenario};
      if (s.model) inputs.push_back(*s.model);
      io::write_manifest(o.out + "/manifest.toml", start_manifest(o, "speed", inputs), nullptr);
      if (!o.quiet) std::printf("wrote %s/speed.csv\n", o.out.c_str());
      return ok;
    }
    if (!s.distance_m) throw InputError("--distance-m is required (the train's characteristic distance), or --model, or --sensor-distance-m");
    const double d = *s.distance_m;
    const bool peaks = s.peaks;
    std::vector<std::vector<std::string>> rows;
    auto num = [](double v) { return io::table_cell(v, 8); };
    for (std::size_t ch : selected(in, s.channels)) {
      const Vector x = usable(in, {ch}, o).data.col(static_cast<Index>(ch));
      const study::SpeedEstimate e =
          peaks ? study::speed_from_peaks(x, in.fs_hz, d, s.min_interval_s, s.v_min_kmh / 3.6, s.v_max_kmh / 3.6)
                : study::speed_from_spectrum(x, in.fs_hz, d, s.v_min_kmh / 3.6, s.v_max_kmh / 3.6, s.harmonics);
      rows.push_back({in.channels[ch], peaks ? "axle-peaks" : "spectral-lines", num(e.speed * 3.6),
                      num(e.uncertainty * 3.6), num(e.frequency_hz), std::to_string(e.n_used), "", "", "", "", ""});
      if (!o.quiet)
        std::printf("%-22s %-15s %.2f km/h +- %.2f (f = %.4f Hz, %d used)\n", in.channels[ch].c_str(),
                    rows.back()[1].c_str(), e.speed * 3.6, e.uncertainty * 3.6, e.frequency_hz, e.n_used);
    }
    write_table_outputs(o, "speed.csv", header, rows);
    if (!o.quiet) std::printf("wrote %s/speed.csv\n", o.out.c_str());
    return ok;
  };
  return bound(std::move(c), +declare, +body);
}

Command resample_command() {
  Command c = record_command("resample", "RECORD",
                             "a record at another sampling rate: decimation or anti-aliased interpolation (resampled.csv)");
  const auto declare = [](po::options_description& d, ResampleOptions& r) {
    add_channel_option(d, r.channels);
    d.add_options()("fs-hz", optional_value(r.fs_hz), "new sampling rate [Hz] (anti-alias low-pass when lower)")(
        "decimate", optional_value(r.decimate), "keep every q-th sample after scipy.signal.decimate's low-pass");
  };
  c.usage_and_samples =
      "--decimate Q follows scipy.signal.decimate(x, Q) (Chebyshev I order 8, 0.05 dB, zero phase).\n"
      "--fs-hz F low-passes at 0.8·F/2 when F is lower than the record's rate, then interpolates\n"
      "linearly (amplitudes within 1.2 % in the passband). Writes OUT/resampled.csv.\n\n"
      "Sample runs:\n"
      "  viaduct resample data/records/synthetic-deck.csv --decimate 5 --out out/dec\n"
      "  viaduct resample data/records/synthetic-deck.csv --fs-hz 4096 --out out/up\n";
  const auto body = [](const Common& o, const ResampleOptions& r) {
    const io::Record whole = read_record(o.scenario, o);
    if (r.fs_hz.has_value() == r.decimate.has_value()) throw InputError("give exactly one of --fs-hz or --decimate");
    const auto chans = selected(whole, r.channels);
    const io::Record in = usable(whole, chans, o);
    const bool dec = r.decimate.has_value();
    const double fs_out = dec ? in.fs_hz / *r.decimate : *r.fs_hz;
    const io::Record out = transform_channels(in, chans, fs_out, [&](const Vector& x) {
      return dec ? signal::decimate(x, *r.decimate) : signal::resample(x, in.fs_hz, fs_out);
    });
    write_record_outputs(o, "resampled.csv", out);
    if (!o.quiet)
      std::printf("%zu channels: %ld samples at %.6g Hz -> %ld at %.6g Hz; wrote %s/resampled.csv\n", chans.size(),
                  static_cast<long>(in.n_samples()), in.fs_hz, static_cast<long>(out.n_samples()), out.fs_hz, o.out.c_str());
    return ok;
  };
  return bound(std::move(c), +declare, +body);
}

Command envelope_command() {
  Command c = record_command("envelope", "RECORD", "running RMS, max-abs or Hilbert envelope of a record's channels (envelope.csv)");
  const auto declare = [](po::options_description& d, EnvelopeOptions& e) {
    add_channel_option(d, e.channels);
    d.add_options()("kind", value(e.kind), "rms, maxabs or hilbert")(
        "window-s", value(e.window_s), "rms and maxabs: centred window [s]");
  };
  c.usage_and_samples =
      "rms: root mean square over a centred window; maxabs: largest |x| over a centred window;\n"
      "hilbert: |analytic signal| (scipy.signal.hilbert), best on a band-passed channel.\n"
      "Writes OUT/envelope.csv with the same channel names.\n\n"
      "Sample runs:\n"
      "  viaduct envelope data/records/synthetic-deck.csv --kind rms --window-s 0.5 --out out/rms\n"
      "  viaduct envelope data/records/synthetic-deck.csv --kind hilbert --channel deck_acc --out out/hilbert\n";
  const auto body = [](const Common& o, const EnvelopeOptions& e) {
    const io::Record whole = read_record(o.scenario, o);
    const std::string& kind = e.kind;
    if (kind != "rms" && kind != "maxabs" && kind != "hilbert") throw InputError("--kind must be rms, maxabs or hilbert");
    const double w_s = e.window_s;
    if (!(w_s > 0.0) || !std::isfinite(w_s)) throw InputError("--window-s must be > 0");
    const Index w = 2 * static_cast<Index>(std::llround(w_s * whole.fs_hz / 2)) + 1;
    const auto chans = selected(whole, e.channels);
    const io::Record in = usable(whole, chans, o);
    const io::Record out = transform_channels(in, chans, in.fs_hz, [&](const Vector& x) {
      return kind == "rms" ? signal::running_rms(x, w) : kind == "maxabs" ? signal::maxabs_envelope(x, w) : signal::hilbert_envelope(x);
    });
    write_record_outputs(o, "envelope.csv", out);
    if (!o.quiet) std::printf("%s envelope of %zu channels; wrote %s/envelope.csv\n", kind.c_str(), chans.size(), o.out.c_str());
    return ok;
  };
  return bound(std::move(c), +declare, +body);
}

namespace {

struct InspectOptions {};

// One record's block on stdout and its rows of inspect.csv.
void inspect_one(const std::string& path, const Common& o, std::vector<std::vector<std::string>>& rows) {
  io::ImportReport rep;
  const io::Record r = io::read_record(path, o.read, &rep);
  const Index n = r.n_samples();
  const double duration = static_cast<double>(n - 1) / r.fs_hz;
  std::printf("%s\n  %s\n  time: %s\n  %ld samples at %.10g Hz, %.10g to %.10g s (%.6g s)", path.c_str(), rep.layout.c_str(), rep.time.c_str(),
              static_cast<long>(n), r.fs_hz, r.t0_s, r.t0_s + duration, duration);
  if (rep.max_time_offset > 1e-6) std::printf("; time stamps within %.2g samples of the grid", rep.max_time_offset);
  std::printf("\n");
  if (rep.gap_samples > 0) std::printf("  gaps: %ld samples missing from the time column\n", static_cast<long>(rep.gap_samples));
  for (const auto& l : rep.notes) std::printf("  note: %s\n", l.c_str());
  for (const auto& l : rep.repairs) std::printf("  repaired: %s\n", l.c_str());
  std::printf("  %-24s %-22s %10s %8s %8s %12s %12s %12s %12s %12s %7s %6s\n", "channel", "in the file", "x factor", "missing", "filled",
              "min", "max", "mean", "rms-mean", "drift", "at-lim", "flat");
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    const io::ImportReport::Channel* rc = nullptr;
    for (const auto& x : rep.channels)
      if (x.channel == r.channels[c]) rc = &x;
    io::ChannelSummary s = io::summarise_channel(r.data.col(static_cast<Index>(c)));
    if (rc && rc->clipped > 0) s.clipped = true, s.at_limits = rc->clipped;  // the reader made those samples missing
    const std::string header = rc ? rc->header : r.channels[c];
    const double factor = rc ? rc->factor : 1.0;
    const long missing = rc ? static_cast<long>(rc->missing) : 0, filled = rc ? static_cast<long>(rc->interpolated) : 0;
    std::printf("  %-24s %-22s %10.6g %8ld %8ld %12.5g %12.5g %12.5g %12.5g %12.5g %7ld %6ld\n", r.channels[c].c_str(), header.c_str(), factor,
                missing, filled, s.min, s.max, s.mean, s.rms_ac, s.drift, static_cast<long>(s.at_limits), static_cast<long>(s.longest_flat));
    if (s.clipped)
      std::printf("  warning: %s: %ld samples sit at its max or min in runs longer than any elsewhere: clipped (over the sensor's or "
                  "logger's range)?\n", r.channels[c].c_str(), static_cast<long>(s.at_limits));
    for (const auto& [a, b] : io::missing_runs(r, c))
      std::printf("  %s has no value from %.10g to %.10g s (%ld samples)\n", r.channels[c].c_str(), r.t0_s + static_cast<double>(a) / r.fs_hz,
                  r.t0_s + static_cast<double>(b - 1) / r.fs_hz, static_cast<long>(b - a));
    rows.push_back({path, r.channels[c], header, r.units[c], io::table_cell(factor), io::table_cell(r.fs_hz), io::table_cell(r.t0_s),
                    io::table_cell(duration), std::to_string(n), std::to_string(missing), std::to_string(filled), io::table_cell(s.min),
                    io::table_cell(s.max), io::table_cell(s.mean), io::table_cell(s.rms_ac), io::table_cell(s.drift),
                    std::to_string(s.at_limits), std::to_string(s.longest_flat), s.clipped ? "yes" : "no"});
  }
}

}  // namespace

Command inspect_command() {
  Command c = record_command("inspect", "RECORD [RECORD ...]",
                             "what a record file holds: layout, units, rate, gaps, NaNs, clipping, offsets (inspect.csv)");
  c.many_positionals = true;
  const auto declare = [](po::options_description&, InspectOptions&) {};
  c.usage_and_samples =
      "Reads each record as every command does (docs/records.md) and prints what it understood and\n"
      "repaired, and per channel: unit and factor, missing and interpolated samples, min, max,\n"
      "mean (offset), RMS about the mean, drift (last tenth minus first), samples at the limits in\n"
      "runs of 3 or more (clipping?) and the longest run of one value (a stuck sensor?). Writes\n"
      "OUT/inspect.csv, a row per file and channel. A file that cannot be read is reported and the\n"
      "others are inspected (exit 1; 2 when none could be read).\n\n"
      "Sample runs:\n"
      "  viaduct inspect data/records/synthetic-deck.csv --out out/inspect\n"
      "  viaduct inspect data/records/logger-semicolon.csv --out out/inspect-logger\n";
  const auto body = [](const Common& o, const InspectOptions&) {
    std::vector<std::string> files{o.scenario};
    files.insert(files.end(), o.more.begin(), o.more.end());
    std::vector<std::vector<std::string>> rows;
    std::size_t failed = 0;
    for (const auto& f : files) {
      try {
        inspect_one(f, o, rows);
      } catch (const InputError& e) {
        if (files.size() == 1) throw;
        ++failed;
        std::fprintf(stderr, "viaduct inspect: error: %s\n", e.what());
      }
    }
    make_out_dir(o.out);
    io::write_table_csv(o.out + "/inspect.csv",
                        {"file", "channel", "header", "unit", "factor", "fs_hz", "t0_s", "duration_s", "samples", "missing", "interpolated",
                         "min", "max", "mean", "rms_ac", "drift", "at_limits", "longest_flat", "clipped"},
                        rows);
    io::write_manifest(o.out + "/manifest.toml", start_manifest(o, "inspect", files), nullptr);
    if (failed == files.size()) return static_cast<int>(usage_error);
    return failed > 0 ? static_cast<int>(runtime_failure) : static_cast<int>(ok);
  };
  return bound(std::move(c), +declare, +body);
}

}  // namespace viaduct::cli
