// viaduct oma: output-only modal identification of ambient and post-passage records (issue #41).
// Options and output only; the numerics live in ident::identify_output_only (include/viaduct/ident/oma.hpp).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "cli.hpp"
#include "viaduct/ident/decay.hpp"
#include "viaduct/ident/modal_fit.hpp"
#include "viaduct/ident/oma.hpp"
#include "viaduct/io/record.hpp"
#include "viaduct/io/results.hpp"

namespace viaduct::cli {

namespace {

struct OmaCliOptions {
  std::vector<std::string> channels, references, carry, records;
  std::optional<double> f_min_hz, f_max_hz, start_s, end_s, entry_s, speed_kmh, train_length_m, bridge_length_m;
  ident::OmaPlan plan;
  ident::TrackingOptions tracking;
  bool free_decay = false;
};

std::string oma_cell(double v) { return io::table_cell(v, 8); }

struct OmaTables {
  std::vector<std::vector<std::string>> modes, shapes, stabilization, fdd, windows, tracked;
};

// One window's rows of modes.csv, shapes.csv (with its window number first), stabilization.csv, fdd.csv.
void add_oma_window(OmaTables& t, const std::string& record, std::size_t window, const ident::OmaWindow& w,
                const std::vector<std::string>& names) {
  const std::string win = std::to_string(window);
  for (std::size_t k = 0; k < w.ssi.modes.size(); ++k) {
    const ident::OmaMode& m = w.ssi.modes[k];
    t.modes.push_back({win, record, "ssi-cov", std::to_string(k + 1), oma_cell(m.frequency_hz), oma_cell(m.damping_ratio), "all", m.note,
                       oma_cell(m.frequency_std_hz), oma_cell(m.damping_std), oma_cell(m.frequency_spread_hz), oma_cell(m.damping_spread), oma_cell(m.mpc),
                       oma_cell(m.mpd_deg), std::to_string(m.order), std::to_string(m.n_poles)});
    for (Index c = 0; c < m.shape.size(); ++c)
      t.shapes.push_back({win, "ssi-cov", std::to_string(k + 1), names[static_cast<std::size_t>(c)], oma_cell(m.shape[c].real()), oma_cell(m.shape[c].imag())});
  }
  for (std::size_t k = 0; k < w.fdd.modes.size(); ++k) {
    const ident::FddMode& m = w.fdd.modes[k];
    t.modes.push_back({win, record, "fdd", std::to_string(k + 1), oma_cell(m.frequency_hz), "", "all", "", "", "", "", "", "", "", "", ""});
    t.modes.push_back({win, record, "efdd", std::to_string(k + 1), oma_cell(m.efdd_frequency_hz), oma_cell(m.efdd_damping_ratio), "all", m.note,
                       "", "", "", "", "", "", "", ""});
    for (Index c = 0; c < m.shape.size(); ++c)
      for (const char* method : {"fdd", "efdd"})
        t.shapes.push_back({win, method, std::to_string(k + 1), names[static_cast<std::size_t>(c)], oma_cell(m.shape[c].real()), oma_cell(m.shape[c].imag())});
  }
  for (const auto& p : w.ssi.poles)
    t.stabilization.push_back({win, std::to_string(p.order), oma_cell(p.frequency_hz), oma_cell(p.damping_ratio), oma_cell(p.mpc), oma_cell(p.mpd_deg),
                               ident::pole_status(p), p.cluster >= 0 ? std::to_string(p.cluster + 1) : ""});
  for (Index k = 0; k < w.fdd.frequency_hz.size(); ++k) {
    std::vector<std::string> row{win, oma_cell(w.fdd.frequency_hz[k])};
    for (Index j = 0; j < std::min<Index>(3, w.fdd.singular_values.cols()); ++j) row.push_back(oma_cell(w.fdd.singular_values(k, j)));
    while (row.size() < 5) row.push_back("");
    t.fdd.push_back(row);
  }
}

// Mean of the carried channels over the window [a, b] of record time: only the window's samples
// are visited (a day of records in 10-minute windows is not read once per window).
std::vector<std::string> carried_means(const io::Record& r, const std::vector<std::size_t>& carry, double a, double b) {
  const Index k0 = std::max<Index>(0, static_cast<Index>(std::ceil((a - r.t0_s) * r.fs_hz - 1e-9)));
  const Index k1 = std::min<Index>(r.n_samples() - 1, static_cast<Index>(std::floor((b - r.t0_s) * r.fs_hz + 1e-9)));
  std::vector<std::string> out;
  for (std::size_t c : carry) {
    double sum = 0.0;
    Index n = 0;
    for (Index k = k0; k <= k1; ++k) {
      const double v = r.data(k, static_cast<Index>(c));
      if (std::isfinite(v)) sum += v, ++n;
    }
    out.push_back(n ? oma_cell(sum / static_cast<double>(n)) : "");
  }
  return out;
}

// The positionals (files, or folders of them in name order) and --records (folders, or tables
// with a file column as `viaduct passages` reads them, files relative to the table's folder).
std::vector<std::string> expand_oma_records(const Common& o, const std::vector<std::string>& records) {
  namespace fs = std::filesystem;
  std::vector<std::string> sources, files;
  if (!o.scenario.empty()) sources.push_back(o.scenario);
  sources.insert(sources.end(), o.more.begin(), o.more.end());
  for (const auto& s : sources) {
    if (fs::is_directory(s)) {
      for (const auto& f : record_files_in(s)) files.push_back(f);
    } else {
      files.push_back(s);
    }
  }
  for (const auto& r : records) {
    if (fs::is_directory(r)) {
      for (const auto& f : record_files_in(r)) files.push_back(f);
    } else if (fs::exists(r)) {
      const fs::path base = fs::path(r).parent_path();
      for (const auto& e : io::read_passage_table(r))
        files.push_back(fs::path(e.file).is_absolute() || fs::exists(e.file) ? e.file : (base / e.file).string());
    } else {
      throw InputError("--records " + r + ": no such folder or table");
    }
  }
  if (files.empty()) throw InputError("no records: give record files or folders, or --records FOLDER|TABLE");
  return files;
}

void oma_declare(po::options_description& d, OmaCliOptions& k) {
  ident::SsiOptions& s = k.plan.ssi;
  d.add_options()("channel", list_value(k.channels), "a response channel (repeatable; default: every channel but --carry's)")(
      "ref", list_value(k.references), "a reference channel of SSI-COV (repeatable; default: every response channel)")(
      "f-min-hz", optional_value(k.f_min_hz), "lower edge of the band [Hz] (modes below are not reported)")(
      "f-max-hz", optional_value(k.f_max_hz), "upper edge [Hz] (default: 0.99 x Nyquist)")(
      "decimate", value(k.plan.decimate), "decimate every channel by this first (zero-phase low-pass, as scipy.signal.decimate)")(
      "start-s", optional_value(k.start_s), "record time to start at [s]")("end-s", optional_value(k.end_s), "record time to end at [s]")(
      "window-s", value(k.plan.window_s), "identify windows of this length [s], tracked over the records (0: each record whole)")(
      "free-decay", po::bool_switch(&k.free_decay), "each record is a passage: identify the free vibration after it (start detected, or --start-s)")(
      "min-order", value(s.min_order), "smallest model order")("max-order", value(s.max_order), "largest model order")(
      "order-step", value(s.order_step), "model order step")("block-rows", value(s.block_rows), "block rows i of the Toeplitz matrix (0: chosen)")(
      "tol-frequency", value(s.tol_frequency), "stable pole: relative frequency change below this")(
      "tol-damping", value(s.tol_damping), "... relative damping change below this")("tol-mac", value(s.tol_mac), "... MAC above this")(
      "max-damping", value(s.max_damping), "poles more damped are spurious")("min-mpc", value(s.min_mpc), "poles with a lower MPC are spurious")(
      "max-mpd-deg", value(s.max_mpd_deg), "poles with a higher MPD [deg] are spurious")(
      "cluster-distance", value(s.cluster_distance), "stable poles closer than |df|/f + 1 - MAC form one mode")(
      "min-cluster-fraction", value(s.min_cluster_fraction), "a mode holds poles of at least this fraction of the orders")(
      "jackknife-blocks", value(s.uncertainty_blocks), "pieces of a window for the jackknife standard deviations (0: none)")(
      "min-periods", value(k.plan.min_periods), "a window holds at least this many periods of --f-min-hz")(
      "nperseg", value(k.plan.fdd.nperseg), "FDD: Welch segment (0: chosen)")(
      "fdd-prominence-db", value(k.plan.fdd.min_prominence_db), "FDD: least prominence of a peak of the first singular value [dB]")(
      "track-tol-frequency", value(k.tracking.tol_frequency), "tracking: relative frequency change between windows")(
      "track-min-mac", value(k.tracking.min_mac), "tracking: least MAC between windows")(
      "carry", list_value(k.carry), "a channel (e.g. temperature) whose mean per window goes into tracked.csv (repeatable)")(
      "records", list_value(k.records), "a folder of records, or a table (CSV with a file column, as viaduct passages reads; repeatable)")(
      "entry-s", optional_value(k.entry_s), "--free-decay: time the first axle enters the bridge [s] ...")(
      "speed-kmh", optional_value(k.speed_kmh), "... the train speed [km/h] ...")("train-length-m", optional_value(k.train_length_m), "... its length [m] ...")(
      "bridge-length-m", optional_value(k.bridge_length_m), "... and the bridge length [m]: the decay starts when the last axle leaves");
}

int oma_body(const Common& o, const OmaCliOptions& k) {
  ident::OmaPlan plan = k.plan;
  if (k.f_min_hz) plan.ssi.f_min_hz = *k.f_min_hz;
  if (k.f_max_hz) plan.ssi.f_max_hz = *k.f_max_hz;
  if (k.start_s) plan.start_s = *k.start_s;
  if (k.end_s) plan.end_s = *k.end_s;
  plan.ssi.free_decay = k.free_decay;
  if (k.free_decay && plan.window_s > 0.0) throw InputError("--free-decay and --window-s exclude each other (a passage's decay is one window)");
  const int n_train = int{k.entry_s.has_value()} + int{k.speed_kmh.has_value()} + int{k.train_length_m.has_value()} +
                      int{k.bridge_length_m.has_value()};
  if (n_train != 0 && n_train != 4) throw InputError("--entry-s, --speed-kmh, --train-length-m and --bridge-length-m go together");
  if (n_train == 4 && !k.free_decay) throw InputError("--entry-s, --speed-kmh, --train-length-m and --bridge-length-m need --free-decay");
  if (n_train == 4 && k.start_s) throw InputError("give --start-s or the train's passage, not both");
  if (n_train == 4) plan.start_s = ident::passage_end_time(*k.entry_s, *k.train_length_m, *k.bridge_length_m, *k.speed_kmh / 3.6);
  const std::vector<std::string> files = expand_oma_records(o, k.records);
  OmaTables t;
  std::vector<std::vector<ident::OmaMode>> all_modes;
  std::vector<std::vector<std::string>> window_info;  // window, record, t_start, t_end, the carried channels' means
  std::vector<std::string> failures, warnings, names_first, carry_names;
  std::size_t window = 0;
  for (const auto& path : files) {
    try {
      const io::Record whole = read_record(path, o);
      std::vector<std::size_t> carry;
      for (const auto& c : k.carry) carry.push_back(whole.channel(c));
      if (carry_names.empty())
        for (std::size_t c : carry) carry_names.push_back(whole.channels[c]);
      std::vector<std::size_t> used;
      if (!k.channels.empty()) {
        used = selected(whole, k.channels);
      } else {
        for (std::size_t c = 0; c < whole.channels.size(); ++c)
          if (std::find(carry.begin(), carry.end(), c) == carry.end()) used.push_back(c);
      }
      const io::Record rec = usable(whole, used, o);
      Matrix y(rec.n_samples(), static_cast<Index>(used.size()));
      std::vector<std::string> names;
      for (std::size_t j = 0; j < used.size(); ++j) {
        y.col(static_cast<Index>(j)) = rec.data.col(static_cast<Index>(used[j]));
        names.push_back(rec.channels[used[j]]);
      }
      if (names_first.empty()) names_first = names;
      else if (names != names_first)
        throw InputError("its channels differ from the first record's (" + names_first.front() + ", ...): tracking needs the same sensors");
      ident::OmaPlan p = plan;
      p.ssi.references.clear();
      for (const auto& r : k.references) {
        const std::size_t c = rec.channel(r);
        const auto it = std::find(used.begin(), used.end(), c);
        if (it == used.end()) throw InputError("--ref " + r + " is not one of the response channels");
        p.ssi.references.push_back(static_cast<Index>(it - used.begin()));
      }
      for (const ident::OmaWindow& w : ident::identify_output_only(y, rec.fs_hz, rec.t0_s, names, p)) {
        ++window;
        if (!w.error.empty()) {
          failures.push_back(path + " (" + format_number(w.t_start_s) + " to " + format_number(w.t_end_s) + " s): " + w.error);
          continue;
        }
        if (!w.warning.empty())
          warnings.push_back(path + " (" + format_number(w.t_start_s) + " to " + format_number(w.t_end_s) + " s): " + w.warning);
        add_oma_window(t, path, window, w, names);
        all_modes.push_back(w.ssi.modes);
        std::vector<std::string> info{std::to_string(window), path, oma_cell(w.t_start_s), oma_cell(w.t_end_s)};
        for (const auto& c : carried_means(whole, carry, w.t_start_s, w.t_end_s)) info.push_back(c);
        window_info.push_back(info);
        if (!o.quiet) {
          std::printf("%s, %.1f to %.1f s: %zu modes (SSI-COV, block rows %ld):", path.c_str(), w.t_start_s, w.t_end_s, w.ssi.modes.size(),
                      static_cast<long>(w.ssi.block_rows));
          for (const auto& m : w.ssi.modes) std::printf(" %.4g Hz (%.2f %%)", m.frequency_hz, 100 * m.damping_ratio);
          std::printf("\n");
        }
      }
    } catch (const InputError& e) {
      failures.push_back(path + ": " + e.what());
    }
  }
  make_out_dir(o.out);
  io::write_table_csv(o.out + "/modes.csv",
                      {"window", "record", "method", "mode", "frequency_hz", "damping_ratio", "response", "note", "frequency_std_hz",
                       "damping_std", "frequency_spread_hz", "damping_spread", "mpc", "mpd_deg", "order", "n_poles"},
                      t.modes);
  io::write_table_csv(o.out + "/shapes.csv", {"window", "method", "mode", "response", "re", "im"}, t.shapes);
  io::write_table_csv(o.out + "/stabilization.csv", {"window", "order", "frequency_hz", "damping_ratio", "mpc", "mpd_deg", "status", "mode"},
                      t.stabilization);
  io::write_table_csv(o.out + "/fdd.csv", {"window", "frequency_hz", "sv1", "sv2", "sv3"}, t.fdd);
  const auto tracks = ident::track_modes(all_modes, k.tracking);
  std::vector<std::string> header{"window", "record", "t_start_s", "t_end_s", "track", "frequency_hz", "damping_ratio", "frequency_std_hz", "damping_std", "mac_to_previous"};
  for (std::size_t c = 0; c < k.carry.size(); ++c) header.push_back(c < carry_names.size() ? carry_names[c] : k.carry[c]);
  std::map<int, ident::ComplexVector> last_shape;
  for (std::size_t w = 0; w < all_modes.size(); ++w)
    for (std::size_t m = 0; m < all_modes[w].size(); ++m) {
      const ident::OmaMode& md = all_modes[w][m];
      const int tr = tracks[w][m];
      std::string mac;
      if (last_shape.count(tr)) mac = oma_cell(ident::mac(last_shape[tr], md.shape)(0, 0));
      last_shape[tr] = md.shape;
      std::vector<std::string> row{window_info[w][0], window_info[w][1], window_info[w][2], window_info[w][3], std::to_string(tr + 1),
                                   oma_cell(md.frequency_hz), oma_cell(md.damping_ratio), oma_cell(md.frequency_std_hz), oma_cell(md.damping_std), mac};
      row.insert(row.end(), window_info[w].begin() + 4, window_info[w].end());
      t.tracked.push_back(row);
    }
  io::write_table_csv(o.out + "/tracked.csv", header, t.tracked);
  print_warnings("oma", warnings);
  io::Manifest manifest = start_manifest(o, "oma", files);
  manifest.warnings = warnings;
  io::write_manifest(o.out + "/manifest.toml", manifest, nullptr);
  if (!failures.empty()) {
    std::string all;
    for (std::size_t i = 0; i < failures.size(); ++i) all += (i ? "\nviaduct oma: error: " : "") + failures[i];
    throw InputError(all);
  }
  if (!o.quiet)
    std::printf("wrote %s/modes.csv, shapes.csv, stabilization.csv, fdd.csv, tracked.csv (%zu windows)\n", o.out.c_str(), window);
  return ok;
}

}  // namespace

Command oma_command() {
  Command c = record_command("oma", "[RECORD...]", "output-only modal identification (SSI-COV, FDD) of ambient or post-passage records, tracked");
  c.many_positionals = true;
  c.needs_scenario = false;  // --records may give them all
  c.usage_and_samples =
      "Records (files, folders of them in name order, or --records TABLE) of ambient vibration, or of\n"
      "passages with --free-decay (the start detected, --start-s, or the train's passage as decay takes it).\n"
      "Each record, or each --window-s of it, is identified by covariance-driven SSI\n"
      "with reference channels over model orders --min-order..--max-order: poles stable in frequency,\n"
      "damping and shape from order to order are clustered into modes (f, damping, their jackknife\n"
      "standard deviations, shapes), and by FDD/EFDD as a quick look. Modes are tracked from window\n"
      "to window by frequency and MAC. Writes OUT/modes.csv and shapes.csv (method ssi-cov, fdd,\n"
      "efdd; `fit` takes them with fit.modes_method = \"ssi-cov\"), stabilization.csv, fdd.csv\n"
      "(singular values of the spectral matrix), tracked.csv (window, time, track, f, damping and\n"
      "--carry's means). A window or record that fails is named on stderr (exit 2) after the others\n"
      "are written. Plot with scripts/plot/plot_oma.py OUT. Method and accuracy: docs/identification.md.\n\n"
      "Sample runs:\n"
      "  viaduct run scenarios/old-guadiana-talgo.toml --set analysis.free_vibration_s=8 --out out/passage\n"
      "  viaduct oma out/passage/history.csv --free-decay --channel S1_mid_acc --channel S1_3L4_acc --channel S2_mid_acc --f-min-hz 2 --f-max-hz 30 --out out/oma\n";
  return bound(std::move(c), +oma_declare, +oma_body);
}

}  // namespace viaduct::cli
