// viaduct filter / viaduct spectrum: processing of record files (measured or simulated).
#include <cmath>
#include <cstdio>
#include <functional>

#include "cli.hpp"
#include "viaduct/io/record.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/signal/iir.hpp"
#include "viaduct/signal/peaks.hpp"
#include "viaduct/signal/resample.hpp"
#include "viaduct/signal/spectrum.hpp"
#include "viaduct/study/speed.hpp"

namespace viaduct::cli {

namespace {

// Channels named by --channel (all when none).
std::vector<std::size_t> selected(const io::Record& r, const po::variables_map& vm) {
  std::vector<std::size_t> out;
  if (vm.count("channel"))
    for (const auto& c : vm["channel"].as<std::vector<std::string>>()) out.push_back(r.channel(c));
  else
    for (std::size_t i = 0; i < r.channels.size(); ++i) out.push_back(i);
  return out;
}

std::string base_name(const io::Record& r, std::size_t c) {
  return r.channels[c].substr(0, r.channels[c].size() - r.units[c].size() - 1);
}

signal::Window window_option(const po::variables_map& vm) {
  const std::string w = vm["window"].as<std::string>();
  if (w == "hann") return signal::Window::hann;
  if (w == "rectangular") return signal::Window::rectangular;
  throw InputError("--window must be hann or rectangular, got '" + w + "'");
}

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

void add_channel_option(po::options_description& d) {
  d.add_options()("channel", po::value<std::vector<std::string>>()->composing(),
                  "channel to process (repeatable; default: all), full name or without its unit");
}

}  // namespace

Command filter_command() {
  Command c;
  c.name = "filter";
  c.positional = "RECORD";
  c.summary = "zero-phase Chebyshev I filtering of a record's channels (filtered.csv)";
  c.add_options = [](po::options_description& d) {
    add_channel_option(d);
    d.add_options()("band", po::value<std::string>()->default_value("bandpass"), "lowpass, highpass or bandpass")(
        "low-hz", po::value<double>()->default_value(1.0), "lower band edge [Hz] (highpass, bandpass)")(
        "high-hz", po::value<double>()->default_value(30.0), "upper band edge [Hz] (lowpass, bandpass)")(
        "order", po::value<int>()->default_value(3), "Chebyshev I order (band-pass: 2 x order poles)")(
        "ripple-db", po::value<double>()->default_value(0.5), "passband ripple [dB]; one pass is -ripple at the edges");
  };
  c.usage_and_samples =
      "RECORD is a CSV record (docs/records.md), e.g. a history.csv written by viaduct run.\n"
      "Filters forward and backward as scipy.signal.sosfiltfilt(cheby1(order, ripple_db, edges,\n"
      "band, fs=fs, output='sos'), x) does, and writes OUT/filtered.csv with the same columns.\n\n"
      "Sample runs:\n"
      "  viaduct filter data/records/synthetic-deck.csv --low-hz 1 --high-hz 30 --out out/filtered\n"
      "  viaduct filter data/records/synthetic-deck.csv --band lowpass --high-hz 15 --channel deck_acc --out out/lp\n";
  c.run = [](const Common& o, const po::variables_map& vm) {
    const io::Record in = io::read_record(o.scenario);
    signal::Cheby1Spec spec;
    const std::string band = vm["band"].as<std::string>();
    if (band == "bandpass") spec.band = signal::BandType::bandpass;
    else if (band == "lowpass") spec.band = signal::BandType::lowpass;
    else if (band == "highpass") spec.band = signal::BandType::highpass;
    else throw InputError("--band must be lowpass, highpass or bandpass, got '" + band + "'");
    spec.low_hz = vm["low-hz"].as<double>();
    spec.high_hz = vm["high-hz"].as<double>();
    spec.order = vm["order"].as<int>();
    spec.ripple_db = vm["ripple-db"].as<double>();
    const signal::Sos sos = signal::cheby1(spec, in.fs_hz);
    const auto chans = selected(in, vm);
    const io::Record out = transform_channels(in, chans, in.fs_hz, [&](const Vector& x) { return signal::sosfiltfilt(sos, x); });
    make_out_dir(o.out);
    io::write_record_csv(o.out + "/filtered.csv", out);
    io::write_manifest(o.out + "/manifest.toml", start_manifest(o, "filter", {o.scenario}), nullptr);
    if (!o.quiet)
      std::printf("%zu channels, %ld samples at %.6g Hz; wrote %s/filtered.csv\n", chans.size(),
                  static_cast<long>(in.n_samples()), in.fs_hz, o.out.c_str());
    return ok;
  };
  return c;
}

Command spectrum_command() {
  Command c;
  c.name = "spectrum";
  c.positional = "RECORD";
  c.summary = "amplitude spectrum or Welch PSD of a record's channels (spectrum.csv)";
  c.add_options = [](po::options_description& d) {
    add_channel_option(d);
    d.add_options()("welch", po::bool_switch(), "Welch power spectral density instead of the amplitude spectrum")(
        "nperseg", po::value<long>()->default_value(4096), "Welch: samples per segment")(
        "noverlap", po::value<long>()->default_value(-1), "Welch: overlap in samples (-1: half a segment)")(
        "window", po::value<std::string>()->default_value("hann"), "hann or rectangular")(
        "detrend", po::value<std::string>()->default_value("constant"), "Welch: constant, linear or none");
  };
  c.usage_and_samples =
      "Amplitude spectrum: one-sided 2|X|/sum(w) of the whole record (a sine of amplitude a on a\n"
      "bin reads a with the rectangular window; Hann gives smoother peaks, correct amplitude at\n"
      "bin centres). Welch PSD: scipy.signal.welch conventions (unit^2/Hz). Writes\n"
      "OUT/spectrum.csv: frequency_hz, then <channel>_amp_<unit> or <channel>_psd_<unit>2_per_hz.\n\n"
      "Sample runs:\n"
      "  viaduct spectrum data/records/synthetic-deck.csv --out out/spectrum\n"
      "  viaduct spectrum data/records/synthetic-deck.csv --welch --nperseg 1024 --out out/psd\n";
  c.run = [](const Common& o, const po::variables_map& vm) {
    const io::Record in = io::read_record(o.scenario);
    const auto chans = selected(in, vm);
    const signal::Window w = window_option(vm);
    const bool welch = vm["welch"].as<bool>();
    std::vector<Vector> cols;
    Vector f;
    std::vector<std::string> names;
    if (welch) {
      signal::WelchOptions wo;
      wo.nperseg = vm["nperseg"].as<long>();
      wo.noverlap = vm["noverlap"].as<long>();
      wo.window = w;
      const std::string d = vm["detrend"].as<std::string>();
      if (d == "constant") wo.detrend = signal::Detrend::constant;
      else if (d == "linear") wo.detrend = signal::Detrend::linear;
      else if (d == "none") wo.detrend = signal::Detrend::none;
      else throw InputError("--detrend must be constant, linear or none");
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
  return c;
}

Command peaks_command() {
  Command c;
  c.name = "peaks";
  c.positional = "RECORD";
  c.summary = "peaks of a record's spectrum or time history, with interpolated positions (peaks.csv)";
  c.add_options = [](po::options_description& d) {
    add_channel_option(d);
    d.add_options()("time", po::bool_switch(), "pick peaks of the time history (default: of the amplitude spectrum)")(
        "window", po::value<std::string>()->default_value("hann"), "spectrum window: hann or rectangular")(
        "min-height", po::value<double>(), "keep peaks at least this high (channel unit)")(
        "min-prominence", po::value<double>()->default_value(0.0), "keep peaks at least this prominent (SciPy's definition)")(
        "min-distance", po::value<double>()->default_value(0.0), "between kept peaks: Hz (spectrum) or s (time)")(
        "max-peaks", po::value<int>()->default_value(10), "keep the highest N (0: all)");
  };
  c.usage_and_samples =
      "Writes OUT/peaks.csv: channel,unit,frequency_hz (or t_s),value,prominence, positions\n"
      "refined between samples (log-parabola). On a Hann spectrum a sine's frequency is found\n"
      "within 0.1 bin.\n\n"
      "Sample runs:\n"
      "  viaduct peaks data/records/synthetic-deck.csv --channel deck_acc --max-peaks 3 --out out/peaks\n"
      "  viaduct peaks data/records/synthetic-deck.csv --channel deck_disp --time --min-distance 0.2 --max-peaks 0 --out out/axles\n";
  c.run = [](const Common& o, const po::variables_map& vm) {
    const io::Record in = io::read_record(o.scenario);
    const bool time = vm["time"].as<bool>();
    const signal::Window window = window_option(vm);
    signal::PeakOptions po_;
    if (vm.count("min-height")) po_.min_height = vm["min-height"].as<double>();
    po_.min_prominence = vm["min-prominence"].as<double>();
    const int max_peaks = vm["max-peaks"].as<int>();
    if (max_peaks < 0) throw InputError("--max-peaks must be >= 0");
    po_.max_peaks = static_cast<std::size_t>(max_peaks);
    const double dist = vm["min-distance"].as<double>();
    if (!(dist >= 0.0) || !std::isfinite(dist)) throw InputError("--min-distance must be >= 0");
    std::vector<std::string> chan, unit;
    std::vector<double> pos, val, prom;
    for (std::size_t ch : selected(in, vm)) {
      Vector y = in.data.col(static_cast<Index>(ch));
      double step = 1.0 / in.fs_hz, origin = in.t0_s;
      if (!time) {
        const auto a = signal::amplitude_spectrum(y, in.fs_hz, window);
        y = a.amplitude;
        step = in.fs_hz / static_cast<double>(in.n_samples());
        origin = 0.0;
      }
      po_.min_distance = std::max<Index>(1, static_cast<Index>(std::ceil(dist / step)));
      for (const auto& p : signal::find_peaks(y, po_)) {
        chan.push_back(in.channels[ch]);
        unit.push_back(in.units[ch]);
        pos.push_back(origin + p.position * step);
        val.push_back(p.value);
        prom.push_back(p.prominence);
      }
    }
    std::vector<std::vector<std::string>> rows;
    for (std::size_t i = 0; i < pos.size(); ++i)
      rows.push_back({chan[i], unit[i], format_number(pos[i], 10), format_number(val[i], 10), format_number(prom[i], 10)});
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
  return c;
}

Command speed_command() {
  Command c;
  c.name = "speed";
  c.positional = "RECORD";
  c.summary = "train speed from a record: spectral lines of a characteristic distance, or axle peaks (speed.csv)";
  c.add_options = [](po::options_description& d) {
    add_channel_option(d);
    d.add_options()("distance-m", po::value<double>(), "the train's characteristic distance d [m] (e.g. 13.14 for a Talgo rake, D for HSLM)")(
        "v-min-kmh", po::value<double>()->default_value(40.0), "lowest speed searched [km/h]")(
        "v-max-kmh", po::value<double>()->default_value(400.0), "highest speed searched [km/h]")(
        "harmonics", po::value<int>()->default_value(4), "harmonics of v/d in the spectral comb")(
        "peaks", po::bool_switch(), "use axle-passage peaks (a channel that sees each axle) instead of spectral lines")(
        "min-interval-s", po::value<double>()->default_value(0.1), "peaks: least time between two axle peaks [s]");
  };
  c.usage_and_samples =
      "Spectral: the speed whose harmonics k*v/d (k = 1..harmonics) best match the lines of the\n"
      "channel's Hann spectrum (zero-padded); uncertainty = one record bin at the highest harmonic.\n"
      "Peaks: v = d / median interval between axle peaks; uncertainty = standard error.\n"
      "Writes OUT/speed.csv: channel,method,speed_kmh,uncertainty_kmh,frequency_hz,n_used.\n\n"
      "Sample runs:\n"
      "  viaduct speed data/records/synthetic-deck.csv --channel deck_acc --distance-m 13.14 --v-min-kmh 100 --v-max-kmh 250 --out out/speed\n"
      "  viaduct speed data/records/synthetic-deck.csv --channel deck_disp --distance-m 13.14 --peaks --min-interval-s 0.2 --out out/speed-peaks\n";
  c.run = [](const Common& o, const po::variables_map& vm) {
    const io::Record in = io::read_record(o.scenario);
    if (!vm.count("distance-m")) throw InputError("--distance-m is required (the train's characteristic distance)");
    const double d = vm["distance-m"].as<double>();
    const bool peaks = vm["peaks"].as<bool>();
    std::vector<std::vector<std::string>> rows;
    auto num = [](double v) { return format_number(v, 8); };
    for (std::size_t ch : selected(in, vm)) {
      const Vector x = in.data.col(static_cast<Index>(ch));
      const study::SpeedEstimate e =
          peaks ? study::speed_from_peaks(x, in.fs_hz, d, vm["min-interval-s"].as<double>())
                : study::speed_from_spectrum(x, in.fs_hz, d, vm["v-min-kmh"].as<double>() / 3.6,
                                             vm["v-max-kmh"].as<double>() / 3.6, vm["harmonics"].as<int>());
      rows.push_back({in.channels[ch], peaks ? "axle-peaks" : "spectral-lines", num(e.speed * 3.6),
                      num(e.uncertainty * 3.6), num(e.frequency_hz), std::to_string(e.n_used)});
      if (!o.quiet)
        std::printf("%-22s %-15s %.2f km/h +- %.2f (f = %.4f Hz, %d used)\n", in.channels[ch].c_str(),
                    rows.back()[1].c_str(), e.speed * 3.6, e.uncertainty * 3.6, e.frequency_hz, e.n_used);
    }
    make_out_dir(o.out);
    io::write_table_csv(o.out + "/speed.csv", {"channel", "method", "speed_kmh", "uncertainty_kmh", "frequency_hz", "n_used"}, rows);
    io::write_manifest(o.out + "/manifest.toml", start_manifest(o, "speed", {o.scenario}), nullptr);
    if (!o.quiet) std::printf("wrote %s/speed.csv\n", o.out.c_str());
    return ok;
  };
  return c;
}

Command resample_command() {
  Command c;
  c.name = "resample";
  c.positional = "RECORD";
  c.summary = "a record at another sampling rate: decimation or anti-aliased interpolation (resampled.csv)";
  c.add_options = [](po::options_description& d) {
    add_channel_option(d);
    d.add_options()("fs-hz", po::value<double>(), "new sampling rate [Hz] (anti-alias low-pass when lower)")(
        "decimate", po::value<int>(), "keep every q-th sample after scipy.signal.decimate's low-pass");
  };
  c.usage_and_samples =
      "--decimate Q follows scipy.signal.decimate(x, Q) (Chebyshev I order 8, 0.05 dB, zero phase).\n"
      "--fs-hz F low-passes at 0.8·F/2 when F is lower than the record's rate, then interpolates\n"
      "linearly (amplitudes within 1.2 % in the passband). Writes OUT/resampled.csv.\n\n"
      "Sample runs:\n"
      "  viaduct resample data/records/synthetic-deck.csv --decimate 5 --out out/dec\n"
      "  viaduct resample data/records/synthetic-deck.csv --fs-hz 4096 --out out/up\n";
  c.run = [](const Common& o, const po::variables_map& vm) {
    const io::Record in = io::read_record(o.scenario);
    if (vm.count("fs-hz") == vm.count("decimate")) throw InputError("give exactly one of --fs-hz or --decimate");
    const auto chans = selected(in, vm);
    const bool dec = vm.count("decimate") > 0;
    const double fs_out = dec ? in.fs_hz / vm["decimate"].as<int>() : vm["fs-hz"].as<double>();
    const io::Record out = transform_channels(in, chans, fs_out, [&](const Vector& x) {
      return dec ? signal::decimate(x, vm["decimate"].as<int>()) : signal::resample(x, in.fs_hz, fs_out);
    });
    make_out_dir(o.out);
    io::write_record_csv(o.out + "/resampled.csv", out);
    io::write_manifest(o.out + "/manifest.toml", start_manifest(o, "resample", {o.scenario}), nullptr);
    if (!o.quiet)
      std::printf("%zu channels: %ld samples at %.6g Hz -> %ld at %.6g Hz; wrote %s/resampled.csv\n", chans.size(),
                  static_cast<long>(in.n_samples()), in.fs_hz, static_cast<long>(out.n_samples()), out.fs_hz, o.out.c_str());
    return ok;
  };
  return c;
}

Command envelope_command() {
  Command c;
  c.name = "envelope";
  c.positional = "RECORD";
  c.summary = "running RMS, max-abs or Hilbert envelope of a record's channels (envelope.csv)";
  c.add_options = [](po::options_description& d) {
    add_channel_option(d);
    d.add_options()("kind", po::value<std::string>()->default_value("rms"), "rms, maxabs or hilbert")(
        "window-s", po::value<double>()->default_value(1.0), "rms and maxabs: centred window [s]");
  };
  c.usage_and_samples =
      "rms: root mean square over a centred window; maxabs: largest |x| over a centred window;\n"
      "hilbert: |analytic signal| (scipy.signal.hilbert), best on a band-passed channel.\n"
      "Writes OUT/envelope.csv with the same channel names.\n\n"
      "Sample runs:\n"
      "  viaduct envelope data/records/synthetic-deck.csv --kind rms --window-s 0.5 --out out/rms\n"
      "  viaduct envelope data/records/synthetic-deck.csv --kind hilbert --channel deck_acc --out out/hilbert\n";
  c.run = [](const Common& o, const po::variables_map& vm) {
    const io::Record in = io::read_record(o.scenario);
    const std::string kind = vm["kind"].as<std::string>();
    if (kind != "rms" && kind != "maxabs" && kind != "hilbert") throw InputError("--kind must be rms, maxabs or hilbert");
    const double w_s = vm["window-s"].as<double>();
    if (!(w_s > 0.0) || !std::isfinite(w_s)) throw InputError("--window-s must be > 0");
    const Index w = 2 * static_cast<Index>(std::llround(w_s * in.fs_hz / 2)) + 1;
    const auto chans = selected(in, vm);
    const io::Record out = transform_channels(in, chans, in.fs_hz, [&](const Vector& x) {
      return kind == "rms" ? signal::running_rms(x, w) : kind == "maxabs" ? signal::maxabs_envelope(x, w) : signal::hilbert_envelope(x);
    });
    make_out_dir(o.out);
    io::write_record_csv(o.out + "/envelope.csv", out);
    io::write_manifest(o.out + "/manifest.toml", start_manifest(o, "envelope", {o.scenario}), nullptr);
    if (!o.quiet) std::printf("%s envelope of %zu channels; wrote %s/envelope.csv\n", kind.c_str(), chans.size(), o.out.c_str());
    return ok;
  };
  return c;
}

}  // namespace viaduct::cli
