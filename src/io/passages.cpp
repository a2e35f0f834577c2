// The passages workflow (issue #19 part 5; #37 item 2: in the library, for the command and Python).
#include "viaduct/io/passages.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <utility>

#include "viaduct/core/error.hpp"
#include "viaduct/model/structure.hpp"
#include "viaduct/study/comparison.hpp"
#include "viaduct/study/simulation.hpp"

namespace viaduct::io {

namespace {

// A record to read: its path, the train it carries (a name or a file, as written) and a speed.
struct PassageFile {
  std::string file, train, where;  // where: "TABLE:LINE" or the folder
  double speed_kmh = 0.0;
  std::string base;  // the table's folder, against which a relative train file is also tried
};

// Every source: a folder (its record files in name order) or a table of passages.
std::vector<PassageFile> passage_files(const std::vector<std::string>& sources) {
  std::vector<PassageFile> out;
  for (const auto& src : sources) {
    namespace fs = std::filesystem;
    if (fs::is_directory(src)) {
      for (const auto& f : record_files_in(src)) out.push_back({f, "", src, 0.0, ""});
    } else if (fs::exists(src)) {
      const std::string base = fs::path(src).parent_path().string();
      for (const auto& e : read_passage_table(src))
        out.push_back({e.file, e.train, src + ":" + std::to_string(e.line), e.speed_kmh, base.empty() ? "" : base + "/"});
    } else {
      throw InputError("--records " + src + ": no such folder or table");
    }
  }
  return out;
}

// The trains the files name (a scenario train's name, or a train file: as written, then against
// the table's folder), into `trains`; each file's index. Every unknown train in one error.
std::vector<std::size_t> passage_trains(const std::vector<PassageFile>& files, const std::optional<std::string>& dflt,
                                        const study::Scenario& sc, std::vector<load::Train>& trains) {
  trains = sc.trains;  // then the train files read, appended (iterators into it do not outlive a turn)
  std::map<std::string, std::size_t> read;  // train file -> index
  std::vector<std::size_t> idx;
  std::string errors;
  for (const auto& e : files) {
    const std::string name = !e.train.empty() ? e.train : dflt ? *dflt : sc.trains.size() == 1 ? sc.trains.front().name : "";
    if (name.empty()) {
      errors += "\n  " + e.where + ": no train for " + e.file + ": give a train column, --train, or a scenario with one train";
      idx.push_back(0);
      continue;
    }
    const auto scenario_end = trains.begin() + static_cast<long>(sc.trains.size());
    const auto it = std::find_if(trains.begin(), scenario_end, [&](const load::Train& t) { return t.name == name; });
    if (it != scenario_end) {
      idx.push_back(static_cast<std::size_t>(it - trains.begin()));
      continue;
    }
    std::string path = name;
    if (!e.train.empty() && name.front() != '/' && std::filesystem::is_regular_file(e.base + name)) path = e.base + name;
    if (!std::filesystem::is_regular_file(path)) {
      std::string have;
      for (const auto& t : sc.trains) have += (have.empty() ? "" : ", ") + t.name;
      errors += "\n  " + e.where + ": train '" + name + "' is neither a train of the scenario (" + (have.empty() ? "none" : have) +
                ") nor a train file";
      idx.push_back(0);
      continue;
    }
    const auto f = read.find(path);
    if (f != read.end()) {
      idx.push_back(f->second);
      continue;
    }
    trains.push_back(read_train_file(path));
    read[path] = trains.size() - 1;
    idx.push_back(trains.size() - 1);
  }
  if (!errors.empty()) throw InputError("passages: trains not found:" + errors);
  return idx;
}

struct ChannelMap {
  std::string channel;
  std::size_t station = 0;
};

std::vector<ChannelMap> channel_maps(const std::vector<std::string>& pairs, const study::Scenario& sc) {
  if (pairs.empty()) throw InputError("at least one --map CHANNEL=STATION is required (the first identifies the speed)");
  std::vector<ChannelMap> out;
  for (const auto& m : pairs) {
    const auto eq = m.find('=');
    if (eq == std::string::npos) throw InputError("--map needs CHANNEL=STATION, got '" + m + "'");
    out.push_back({m.substr(0, eq), study::station_index(sc, m.substr(eq + 1), "--map")});
  }
  return out;
}

// One record read into a passage: the mapped channels only, their kind from their units.
study::Passage read_passage(const PassageFile& e, std::size_t train, const std::vector<ChannelMap>& maps, const study::Scenario& sc,
                            const PassagesRequest& q) {
  ImportReport rep;
  const Record whole = read_record(e.file, q.read, &rep);
  if (q.on_read) q.on_read(e.file, rep);
  std::vector<std::size_t> used;
  for (const auto& m : maps) used.push_back(whole.channel(m.channel));
  std::vector<std::string> cuts;
  const Record rec = valid_span(whole, used, "viaduct passages", &cuts);  // another channel's missing samples cut nothing
  if (q.on_cut)
    for (const auto& c : cuts) q.on_cut(c);
  study::Passage p;
  p.name = e.file;
  p.train = train;
  p.fs_hz = rec.fs_hz;
  p.t0_s = rec.t0_s;
  p.speed = e.speed_kmh / 3.6;
  for (const auto& m : maps) {
    const std::size_t c = rec.channel(m.channel);
    const study::ResponseKind k = channel_quantity(rec.units[c], rec.channels[c], "--map");
    study::require_strain_fibre(sc, m.station, rec.channels[c], k, "--map");
    p.channels.push_back({rec.channels[c], m.station, k, rec.data.col(static_cast<Index>(c))});
  }
  return p;
}

// What a user must read of the passages: failed envelope cases, identified speeds at the edge of
// the range or outside the envelope's speeds, offsets kept and residuals with structure.
std::vector<std::string> passage_warnings(const study::PassageStudy& r, const study::PassageOptions& po, double lo, double hi) {
  std::vector<std::string> warnings = r.envelope_failures;
  for (const auto& p : r.passages) {
    if (!p.failure.empty() || !p.identified) continue;
    if (p.speed < po.v_min * 1.005 || p.speed > po.v_max * 0.995)
      warnings.push_back(p.name + ": identified speed " + format_number(p.speed * 3.6, 5) +
                         " km/h at the edge of the range searched; widen --v-min-kmh/--v-max-kmh");
    if (p.speed < lo || p.speed > hi)
      warnings.push_back(p.name + ": " + format_number(p.speed * 3.6, 5) + " km/h is outside the envelope's speeds (sweep.*)");
    for (const auto& f : p.speed_flags) warnings.push_back(p.name + ": identified speed: " + f + " (passages.csv speed_flag)");
  }
  for (const auto& p : r.passages)
    for (const auto& c : p.channels)
      if (!c.offset_warning.empty()) warnings.push_back(p.name + ", " + c.offset_warning);
  for (const auto& p : r.passages)
    for (const auto& c : p.channels)
      if (!c.unit_warning.empty()) warnings.push_back(p.name + ", " + c.unit_warning + " (within = false)");
  for (const auto& p : r.passages)
    for (const auto& c : p.channels)
      if (c.residual != "white")
        warnings.push_back(p.name + ", " + c.channel + ": the record less the model holds a" +
                           (c.residual == "offset" ? "n offset" : " " + c.residual) + " of " + format_number(c.residual_size, 4) +
                           " " + study::response_unit(c.kind) + " (passages.csv residual): the peak is not judged (within = false); "
                           "zero the channel, or cut the record where it jumps or drifts");
  return warnings;
}

TableColumn text(const std::string& name) { return {name, TableColumn::Kind::text, {}, {}, {}}; }
TableColumn number(const std::string& name) { return {name, TableColumn::Kind::number, {}, {}, {}}; }
TableColumn flag(const std::string& name) { return {name, TableColumn::Kind::flag, {}, {}, {}}; }

}  // namespace

PassagesOutcome run_passages(const FlatScenario& flat, const PassagesRequest& q) {
  if (q.records.empty()) throw InputError("--records FOLDER|TABLE is required (a folder of records or a table file,train,speed_kmh)");
  const study::Scenario sc = to_scenario(flat);
  if (sc.sweep_speeds.empty())
    throw InputError(SourceLocation{flat.path, 0, "sweep"},
                     "no speeds for the model's envelope: give sweep.speeds_kmh, sweep.speed_min/max/step_kmh or sweep.speed_min/max_mps with n_speeds");
  const std::vector<ChannelMap> maps = channel_maps(q.maps, sc);
  const std::vector<PassageFile> files = passage_files(q.records);
  std::vector<load::Train> trains;
  const std::vector<std::size_t> train_of = passage_trains(files, q.train, sc, trains);
  study::PassageOptions po;
  const auto [lo, hi] = std::minmax_element(sc.sweep_speeds.begin(), sc.sweep_speeds.end());
  po.v_min = q.v_min_kmh ? *q.v_min_kmh / 3.6 : *lo;
  po.v_max = q.v_max_kmh ? *q.v_max_kmh / 3.6 : *hi;
  po.speed_band = q.speed_band;
  po.noise_band = q.noise_band;
  po.zero = study::parse_zero(q.zero, "--zero");
  po.threads = q.threads;
  // Read every record (the mapped channels only); one that cannot be read is a failed passage.
  PassagesOutcome out;
  std::vector<study::Passage> passages;
  std::vector<study::PassageResult> unread;
  bool strain = false;
  for (std::size_t i = 0; i < files.size(); ++i) {
    out.inputs.push_back(files[i].file);
    try {
      passages.push_back(read_passage(files[i], train_of[i], maps, sc, q));
      for (const auto& c : passages.back().channels) strain = strain || c.kind == study::ResponseKind::strain;
    } catch (const InputError& e) {
      study::PassageResult f;
      f.name = files[i].file;
      f.train = trains[train_of[i]].name;
      f.failure = e.what();
      f.input_error = true;
      unread.push_back(f);  // reported with the others at the end
    }
  }
  study::RunSettings rs = sc.settings;
  rs.filter.enabled = false;
  rs.ida.log = q.log;
  const study::PreparedModel pm = study::prepare_model(model::build_structure(sc.bridge, sc.track), sc.stations, rs, true, strain);
  po.progress = q.progress;
  out.study = passages.empty() ? study::PassageStudy{}
                               : study::run_passages(pm, rs, sc.settings.filter, trains, sc.sweep_speeds, passages, po);
  out.study.passages.insert(out.study.passages.end(), unread.begin(), unread.end());
  out.warnings = passage_warnings(out.study, po, *lo, *hi);
  out.settings = sc.settings;
  out.speed_band = po.speed_band;
  out.noise_band = po.noise_band;
  for (const auto& p : out.study.passages) out.n_failed += !p.failure.empty(), out.n_input_errors += p.input_error;
  return out;
}

std::vector<TableColumn> passage_columns(const PassagesOutcome& r) {
  std::vector<TableColumn> c = {text("passage"),     text("train"),        number("speed_kmh"),      number("speed_uncertainty_kmh"),
                                text("speed_source"), number("signature_correlation"), text("channel"), text("station"),
                                text("quantity"),    text("unit"),         number("measured"),       number("predicted"),
                                number("predicted_low"), number("predicted_high"), number("ratio"), number("noise_rms"),
                                number("correlation"), flag("within"),     text("residual"),         number("residual_size"),
                                number("zero_removed"), text("speed_flag")};
  for (const auto& p : r.study.passages) {
    if (!p.failure.empty()) continue;
    std::string speed_flag;
    for (const auto& f : p.speed_flags) speed_flag += (speed_flag.empty() ? "" : "; ") + f;
    for (const auto& ch : p.channels) {
      const double nan = std::nan("");
      std::size_t j = 0;
      auto t = [&](const std::string& v) { c[j++].cells.push_back(v); };
      auto x = [&](double v) { c[j++].values.push_back(v); };
      t(p.name), t(p.train), x(p.speed * 3.6), x(r.speed_band * p.speed_se * 3.6), t(p.identified ? "identified" : "given");
      x(p.identified ? p.signature_correlation : nan), t(ch.channel), t(ch.station), t(study::response_name(ch.kind));
      t(study::response_unit(ch.kind)), x(ch.measured), x(ch.predicted), x(ch.predicted_low), x(ch.predicted_high);
      x(std::isfinite(ch.ratio) ? ch.ratio : nan), x(ch.noise_rms), x(ch.correlation);
      c[j++].flags.push_back(ch.within ? 1 : 0);
      t(ch.residual), x(ch.residual == "white" ? nan : ch.residual_size), x(ch.zero_removed), t(speed_flag);
    }
  }
  return c;
}

std::vector<TableColumn> passage_envelope_columns(const PassagesOutcome& r) {
  std::vector<TableColumn> c = {text("train"), text("station"), text("quantity"), text("unit"), number("speed_kmh"), number("peak")};
  for (const auto& e : r.study.curves)
    for (std::size_t i = 0; i < e.speeds.size(); ++i) {
      c[0].cells.push_back(e.train), c[1].cells.push_back(e.station), c[2].cells.push_back(study::response_name(e.kind));
      c[3].cells.push_back(study::response_unit(e.kind)), c[4].values.push_back(e.speeds[i] * 3.6), c[5].values.push_back(e.peaks[i]);
    }
  return c;
}

std::vector<TableColumn> passage_summary_columns(const PassagesOutcome& r) {
  // Per station and quantity, in the order they first appear.
  std::map<std::pair<std::string, std::string>, std::vector<const study::ChannelVerdict*>> groups;
  std::vector<std::pair<std::string, std::string>> order;
  for (const auto& p : r.study.passages)
    for (const auto& ch : p.channels) {
      if (!p.failure.empty()) continue;
      const auto key = std::make_pair(ch.station, std::string(study::response_name(ch.kind)));
      if (!groups.count(key)) order.push_back(key);
      groups[key].push_back(&ch);
    }
  std::vector<TableColumn> c = {text("station"),      text("quantity"),  number("n"),       number("ratio_median"),
                                number("ratio_min"), number("ratio_max"), number("n_within")};
  for (const auto& key : order) {
    std::vector<double> ratios;
    int within = 0;
    for (const auto* ch : groups[key]) {
      if (std::isfinite(ch->ratio)) ratios.push_back(ch->ratio);
      within += ch->within;
    }
    std::sort(ratios.begin(), ratios.end());
    const std::size_t n = ratios.size();
    const double nan = std::nan("");
    const double median = n == 0 ? nan : n % 2 ? ratios[n / 2] : 0.5 * (ratios[n / 2 - 1] + ratios[n / 2]);
    c[0].cells.push_back(key.first), c[1].cells.push_back(key.second);
    c[2].values.push_back(static_cast<double>(groups[key].size())), c[3].values.push_back(median);
    c[4].values.push_back(n ? ratios.front() : nan), c[5].values.push_back(n ? ratios.back() : nan);
    c[6].values.push_back(within);
  }
  return c;
}

std::vector<TableColumn> passage_failure_columns(const PassagesOutcome& r) {
  std::vector<TableColumn> c = {text("passage"), text("train"), text("message")};
  for (const auto& p : r.study.passages)
    if (!p.failure.empty()) c[0].cells.push_back(p.name), c[1].cells.push_back(p.train), c[2].cells.push_back(p.failure);
  return c;
}

void write_passages_tables(const std::string& dir, const PassagesOutcome& r) {
  write_table_columns_csv(dir + "/passages.csv", passage_columns(r), 8);
  write_table_columns_csv(dir + "/model_envelope.csv", passage_envelope_columns(r), 8);
  write_table_columns_csv(dir + "/passages_summary.csv", passage_summary_columns(r), 8);
  write_table_columns_csv(dir + "/failures.csv", passage_failure_columns(r), 8);
}

}  // namespace viaduct::io
