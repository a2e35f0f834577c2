// Model updating from files: parameters, the [fit] section, identified modes, fitted scenario.
#include "viaduct/io/fit.hpp"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "viaduct/core/error.hpp"
#include "atomic_file.hpp"
#include "csv_cells.hpp"
#include "viaduct/io/record.hpp"
#include "viaduct/io/results.hpp"

namespace viaduct::io {

namespace fs = std::filesystem;

namespace {

std::string fit_num(double v) { return format_number(v, 12); }

using detail::TextTable;

std::size_t column(const TextTable& t, const std::string& path, const std::string& name) {
  for (std::size_t i = 0; i < t.header.size(); ++i)
    if (t.header[i] == name) return i;
  throw InputError(path + ": no column '" + name + "'");
}

double number_cell(const std::string& path, int line, const std::string& column, const std::string& cell) {
  char* end = nullptr;
  const double v = std::strtod(cell.c_str(), &end);
  if (cell.empty() || end == cell.c_str() || *end != '\0')
    throw InputError(path + ":" + std::to_string(line) + ": column '" + column + "': '" + cell + "' is not a number");
  return v;
}

}  // namespace

study::FitParameter fit_parameter(const FlatScenario& flat, const std::string& key, double lower, double upper,
                                  const std::string& scale, const SourceLocation& where) {
  const SourceLocation at{where.file, where.line, key};
  auto fail = [&](const std::string& m) { throw InputError(at, m); };
  const KeySpec* spec = find_key_spec(key);
  if (!spec) fail("unknown scenario key");
  if (spec->type != ValueType::number && spec->type != ValueType::number_or_list)
    fail("cannot be fitted: it is not a number");
  if (!flat.has(key)) fail("is not set in the scenario (give it a value to start from)");
  const Value& v = flat.at(key);
  double initial = 0.0;
  if (v.type == ValueType::number) initial = v.x;
  else if (v.type == ValueType::number_list && v.xs.size() == 1) initial = v.xs[0];
  else fail("is a list of several values; only a single number can be fitted");
  if (!std::isfinite(lower) || !std::isfinite(upper) || !(lower < upper))
    fail("bounds must be finite with lower < upper, got " + fit_num(lower) + ":" + fit_num(upper));
  study::FitParameter p;
  p.key = key;
  p.unit = spec->unit;
  p.lower = lower;
  p.upper = upper;
  p.initial = initial;
  if (scale == "log") p.scale = study::ParameterScale::log;
  else if (scale == "linear") p.scale = study::ParameterScale::linear;
  else if (scale == "auto" || scale.empty()) p.scale = lower > 0 ? study::ParameterScale::log : study::ParameterScale::linear;
  else fail("scale must be auto, log or linear, got '" + scale + "'");
  if (p.scale == study::ParameterScale::log && !(lower > 0)) fail("a log scale needs lower > 0, got " + fit_num(lower));
  if (!(initial >= lower && initial <= upper))
    fail("its value " + fit_num(initial) + " (the start) is outside the bounds [" + fit_num(lower) + ", " + fit_num(upper) + "]");
  // The bounds must satisfy the key's own constraint.
  FlatScenario probe;
  probe.path = flat.path;
  probe.values[key] = v;
  for (double b : {lower, upper}) {
    try {
      set_number(probe, key, b);
    } catch (const InputError& e) {
      fail(std::string("bound ") + fit_num(b) + " violates the key's constraint " + spec->constraint);
    }
  }
  return p;
}

study::FitParameter parse_fit_parameter(const FlatScenario& flat, const std::string& text) {
  const SourceLocation where{"--param", 0, ""};
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) throw InputError(where, "expected KEY=LO:HI[:log|linear], got '" + text + "'");
  const std::string key = text.substr(0, eq);
  std::vector<std::string> parts;
  std::stringstream ss(text.substr(eq + 1));
  for (std::string p; std::getline(ss, p, ':');) parts.push_back(p);
  if (parts.size() < 2 || parts.size() > 3)
    throw InputError(SourceLocation{"--param", 0, key}, "expected " + key + "=LO:HI[:log|linear], got '" + text + "'");
  double b[2];
  for (int i = 0; i < 2; ++i) {
    char* end = nullptr;
    b[i] = std::strtod(parts[static_cast<std::size_t>(i)].c_str(), &end);
    if (parts[static_cast<std::size_t>(i)].empty() || *end != '\0')
      throw InputError(SourceLocation{"--param", 0, key}, std::string(i ? "upper" : "lower") + " bound '" +
                                                              parts[static_cast<std::size_t>(i)] + "' is not a number");
  }
  return fit_parameter(flat, key, b[0], b[1], parts.size() == 3 ? parts[2] : "auto", SourceLocation{"--param", 0, key});
}

FitDeclaration fit_declaration(const FlatScenario& flat) {
  FitDeclaration d;
  auto get = [&](const std::string& k) -> const Value* {
    auto it = flat.values.find(k);
    return it == flat.values.end() ? nullptr : &it->second;
  };
  for (int i = 0;; ++i) {
    const std::string p = "fit.params[" + std::to_string(i) + "]";
    const Value* key = get(p + ".key");
    const Value* lo = get(p + ".lower");
    const Value* hi = get(p + ".upper");
    if (!key && !lo && !hi) break;
    const Value* any = key ? key : lo ? lo : hi;
    if (!key || !lo || !hi) throw InputError(any->where, p + " needs key, lower and upper");
    d.params.push_back(fit_parameter(flat, key->s, lo->x, hi->x, get(p + ".scale") ? get(p + ".scale")->s : "auto", key->where));
  }
  for (int i = 0;; ++i) {
    const std::string p = "fit.records[" + std::to_string(i) + "]";
    const Value* file = get(p + ".file");
    const Value* map = get(p + ".map");
    if (!file && !map) break;
    if (!file || !map) throw InputError((file ? file : map)->where, p + " needs file and map");
    FitDeclaration::RecordSpec r;
    r.file = file->s;
    r.map = map->ss;
    r.where = file->where;
    if (const Value* v = get(p + ".speed_kmh")) r.speed_kmh = v->x;
    if (const Value* v = get(p + ".train")) r.train = v->s;
    d.records.push_back(r);
  }
  if (const Value* v = get("fit.modes")) d.modes = v->s;
  if (const Value* v = get("fit.modes_method")) d.modes_method = v->s;
  auto& o = d.options;
  o.weights.time = get("fit.weights.time") ? get("fit.weights.time")->x : -1.0;
  o.weights.modal = get("fit.weights.modal") ? get("fit.weights.modal")->x : -1.0;
  if (const Value* v = get("fit.weights.peak")) o.weights.peak = v->x;
  if (const Value* v = get("fit.weights.envelope")) o.weights.envelope = v->x;
  if (const Value* v = get("fit.weights.spectrum")) o.weights.spectrum = v->x;
  if (const Value* v = get("fit.weights.damping")) o.weights.damping = v->x;
  if (const Value* v = get("fit.envelope_window_s")) o.envelope_window_s = v->x;
  if (const Value* v = get("fit.max_shift_s")) o.max_shift_s = v->x;
  if (const Value* v = get("fit.starts")) o.starts = static_cast<int>(v->x);
  if (const Value* v = get("fit.spectral_start")) o.spectral_start = v->b;
  if (const Value* v = get("fit.max_iterations")) o.max_iterations = static_cast<int>(v->x);
  if (const Value* v = get("fit.max_time_s")) o.max_time_s = v->x;
  if (const Value* v = get("fit.fd_step")) {
    if (v->x > 0.1) throw InputError(v->where, "must be at most 0.1, got " + fit_num(v->x));
    o.fd_step = v->x;
  }
  return d;
}

study::ScenarioBuilder scenario_builder(const FlatScenario& flat, const std::vector<study::FitParameter>& params) {
  std::vector<std::string> keys;
  for (const auto& p : params) keys.push_back(p.key);
  return [flat, keys](const std::vector<double>& values) {
    FlatScenario f = flat;
    for (std::size_t i = 0; i < keys.size() && i < values.size(); ++i) set_number(f, keys[i], values[i]);
    return to_scenario(f);
  };
}

namespace {

// One mode from viaduct decay's decay_summary.csv: mean frequency and envelope-fit damping.
study::ModalTarget read_decay_summary(const std::string& path) {
  const TextTable t = detail::read_text_table(path, /*quoted=*/true);
  const std::size_t c_est = column(t, path, "estimate"), c_mean = column(t, path, "mean");
  study::ModalTarget target;
  study::ModalTarget::Mode m;
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    if (t.rows[i][c_est] == "frequency_hz") m.frequency_hz = number_cell(path, t.lines[i], "mean", t.rows[i][c_mean]);
    if (t.rows[i][c_est] == "zeta_envelope_fit") m.damping_ratio = number_cell(path, t.lines[i], "mean", t.rows[i][c_mean]);
  }
  if (!(m.frequency_hz > 0) || !std::isfinite(m.frequency_hz))
    throw InputError(path + ": no finite frequency_hz row (a decay_summary.csv of viaduct decay?)");
  if (!(m.damping_ratio > 0 && m.damping_ratio < 1)) m.damping_ratio = std::numeric_limits<double>::quiet_NaN();
  target.modes.push_back(m);
  return target;
}

}  // namespace

study::ModalTarget read_identified_modes(const std::string& path, const std::string& method) {
  fs::path modes_path = path;
  if (fs::is_directory(modes_path)) {
    if (!fs::exists(modes_path / "modes.csv") && fs::exists(modes_path / "decay_summary.csv"))
      return read_decay_summary((modes_path / "decay_summary.csv").string());
    modes_path /= "modes.csv";
  } else if (modes_path.filename() == "decay_summary.csv") {
    return read_decay_summary(modes_path.string());
  }
  const std::string mp = modes_path.string();
  const TextTable t = detail::read_text_table(mp, /*quoted=*/true);
  const std::size_t c_method = column(t, mp, "method"), c_mode = column(t, mp, "mode"), c_f = column(t, mp, "frequency_hz");
  std::map<int, double> freq, zeta;
  std::size_t c_zeta = t.header.size();
  for (std::size_t i = 0; i < t.header.size(); ++i)
    if (t.header[i] == "damping_ratio") c_zeta = i;
  // viaduct oma's modes.csv holds a window column: the modes of one window only are one target.
  std::set<std::string> windows;
  for (std::size_t i = 0; i < t.header.size(); ++i)
    if (t.header[i] == "window")
      for (const auto& row : t.rows) windows.insert(row[i]);
  if (windows.size() > 1)
    throw InputError(mp + ": modes of " + std::to_string(windows.size()) +
                     " windows (viaduct oma over several records or --window-s); identify the one record to fit on its own");
  std::set<std::string> methods;
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    methods.insert(t.rows[i][c_method]);
    if (t.rows[i][c_method] != method) continue;
    const int mode = static_cast<int>(number_cell(mp, t.lines[i], "mode", t.rows[i][c_mode]));
    const double f = number_cell(mp, t.lines[i], "frequency_hz", t.rows[i][c_f]);
    if (!(f > 0) || !std::isfinite(f)) throw InputError(mp + ":" + std::to_string(t.lines[i]) + ": frequency_hz must be > 0");
    freq[mode] = f;
    if (c_zeta < t.header.size()) {
      const std::string& cell = t.rows[i][c_zeta];
      char* end = nullptr;
      const double z = std::strtod(cell.c_str(), &end);
      zeta[mode] = !cell.empty() && *end == '\0' && z > 0 && z < 1 ? z : std::numeric_limits<double>::quiet_NaN();
    }
  }
  if (freq.empty()) {
    std::string have;
    for (const auto& m : methods) have += (have.empty() ? "" : ", ") + m;
    throw InputError(mp + ": no mode of method '" + method + "' (the file has: " + (have.empty() ? "none" : have) + ")");
  }
  study::ModalTarget target;
  std::map<int, std::map<std::string, double>> shape;
  const fs::path shapes_path = modes_path.parent_path() / "shapes.csv";
  if (fs::exists(shapes_path)) {
    const std::string sp = shapes_path.string();
    const TextTable s = detail::read_text_table(sp, /*quoted=*/true);
    const std::size_t s_method = column(s, sp, "method"), s_mode = column(s, sp, "mode"),
                      s_resp = column(s, sp, "response"), s_re = column(s, sp, "re");
    for (std::size_t i = 0; i < s.rows.size(); ++i) {
      if (s.rows[i][s_method] != method) continue;
      const int mode = static_cast<int>(number_cell(sp, s.lines[i], "mode", s.rows[i][s_mode]));
      const std::string& resp = s.rows[i][s_resp];
      if (std::find(target.sensors.begin(), target.sensors.end(), resp) == target.sensors.end()) target.sensors.push_back(resp);
      shape[mode][resp] = number_cell(sp, s.lines[i], "re", s.rows[i][s_re]);
    }
  }
  for (const auto& [mode, f] : freq) {
    study::ModalTarget::Mode m;
    m.frequency_hz = f;
    if (zeta.count(mode)) m.damping_ratio = zeta[mode];
    if (shape.count(mode)) {
      m.shape.resize(static_cast<Index>(target.sensors.size()));
      for (std::size_t k = 0; k < target.sensors.size(); ++k) {
        auto it = shape[mode].find(target.sensors[k]);
        if (it == shape[mode].end())
          throw InputError(shapes_path.string() + ": mode " + std::to_string(mode) + " has no entry for " + target.sensors[k]);
        m.shape[static_cast<Index>(k)] = it->second;
      }
    }
    target.modes.push_back(m);
  }
  return target;
}

void write_scenario_toml(const std::string& path, const FlatScenario& flat, const std::string& comment) {
  static const std::regex item(R"(^(.*)\[([0-9]+)\]\.([^.]+)$)");
  std::map<std::string, std::vector<std::pair<std::string, Value>>> tables;              // table -> leaves
  std::map<std::string, std::map<int, std::vector<std::pair<std::string, Value>>>> arrays;  // array -> index -> leaves
  for (const auto& [key, v] : flat.values) {
    if (key == "bridge.file" || key == "track.file") continue;  // their keys are merged in flat
    const bool fitted_or_set = !flat.defaulted.count(key);
    if (!fitted_or_set) continue;
    Value val = v;
    const bool path_key = key == "train.files" || key == "fit.modes" ||
                          (key.rfind("fit.records[", 0) == 0 && key.size() > 5 && key.compare(key.size() - 5, 5, ".file") == 0);
    if (path_key && val.type == ValueType::string) val.s = fs::absolute(val.s).lexically_normal().string();
    if (path_key && val.type == ValueType::string_list)
      for (auto& s : val.ss) s = fs::absolute(s).lexically_normal().string();
    std::smatch m;
    if (std::regex_match(key, m, item)) {
      arrays[m[1]][std::stoi(m[2])].push_back({m[3], val});
      continue;
    }
    const auto dot = key.rfind('.');
    const std::string table = dot == std::string::npos ? "" : key.substr(0, dot);
    tables[table].push_back({dot == std::string::npos ? key : key.substr(dot + 1), val});
  }
  std::ostringstream out;
  std::stringstream cs(comment);
  for (std::string line; std::getline(cs, line);) out << "# " << line << "\n";
  auto leaves = [&](const std::vector<std::pair<std::string, Value>>& ls) {
    for (const auto& [k, v] : ls) out << k << " = " << v.to_toml() << "\n";
  };
  if (tables.count("")) leaves(tables[""]);
  for (const auto& [t, ls] : tables) {
    if (t.empty()) continue;
    out << "\n[" << t << "]\n";
    leaves(ls);
  }
  for (const auto& [a, items] : arrays)
    for (const auto& [idx, ls] : items) {
      (void)idx;
      out << "\n[[" << a << "]]\n";
      leaves(ls);
    }
  detail::write_text_atomically(path, out.str());
}

namespace {
std::string fit_cell(double v) { return table_cell(v, 10); }
// A standard error is infinite for a parameter the data do not determine ("determined" says so).
std::string error_cell(double v) { return std::isfinite(v) ? fit_cell(v) : ""; }

std::pair<std::string, std::string> split_pair(const std::string& s, const std::string& option) {
  const auto eq = s.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == s.size())
    throw InputError(option + " needs NAME=VALUE, got '" + s + "'");
  return {s.substr(0, eq), s.substr(eq + 1)};
}

// A record's mapped channels as the fit sees them.
study::FitRecord load_fit_record(const std::string& file, const std::vector<std::string>& maps, double speed_kmh,
                                 const std::string& train, const std::string& where, const FitRequest& request) {
  if (maps.empty()) throw InputError(where + ": record " + file + " maps no channel (--map CHANNEL=STATION)");
  ImportReport report;
  const Record whole = read_record(file, request.read, &report);
  std::vector<std::size_t> used;
  for (const auto& m : maps) {
    try {  // an unknown channel is reported below, after what reading the file did
      used.push_back(whole.channel(split_pair(m, where + " map").first));
    } catch (const InputError&) {
    }
  }
  // Another channel's missing samples cut nothing; those of a mapped one cut to the longest piece.
  const Record rec = valid_span(whole, used, where + ": record " + file, &report.repairs);
  if (!report.repairs.empty()) report.plain = false;
  if (request.on_read) request.on_read(file, report);
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
    ch.acceleration = q == ChannelQuantity::acceleration || q == ChannelQuantity::velocity;  // band-filtered alike
    ch.velocity = q == ChannelQuantity::velocity;
    ch.strain = q == ChannelQuantity::strain;
    ch.samples = rec.data.col(static_cast<Index>(c));
    fr.channels.push_back(std::move(ch));
  }
  return fr;
}

}  // namespace

std::pair<study::FitProblem, study::FitOptions> fit_setup(const FlatScenario& flat, const FitRequest& request) {
  FitDeclaration decl = fit_declaration(flat);
  study::FitProblem problem;
  // Parameters.
  if (!request.params.empty()) {
    for (const auto& p : request.params) problem.params.push_back(parse_fit_parameter(flat, p));
  } else {
    problem.params = decl.params;
  }
  if (problem.params.empty()) throw InputError("no parameter to fit: give --param KEY=LO:HI or [[fit.params]] in the scenario");
  for (std::size_t i = 0; i < problem.params.size(); ++i)
    for (std::size_t j = i + 1; j < problem.params.size(); ++j)
      if (problem.params[i].key == problem.params[j].key) throw InputError("--param: " + problem.params[i].key + " is given twice");
  // Records.
  const std::vector<std::string>& maps = request.maps;
  const std::vector<double>& speeds = request.speeds_kmh;
  for (double v : speeds)
    if (!(v > 0) || !std::isfinite(v)) throw InputError("--speed-kmh must be > 0, got " + fit_cell(v));
  const std::string& train = request.train;
  if (!request.records.empty()) {
    const auto& files = request.records;
    if (speeds.size() > 1 && speeds.size() != files.size())
      throw InputError("--speed-kmh: give one speed for all records or one per --record (" + std::to_string(files.size()) + ")");
    for (std::size_t i = 0; i < files.size(); ++i)
      problem.records.push_back(load_fit_record(files[i], maps, speeds.empty() ? 0.0 : speeds[speeds.size() > 1 ? i : 0], train,
                                                "--record " + files[i], request));
  } else {
    if (!speeds.empty()) throw InputError("--speed-kmh needs --record (declared records carry their own speed_kmh)");
    for (const auto& r : decl.records)
      problem.records.push_back(load_fit_record(r.file, r.map, r.speed_kmh, r.train,
                                                r.where.file + ":" + std::to_string(r.where.line), request));
  }
  // Identified modes.
  const std::string modes = request.modes ? *request.modes : decl.modes;
  const std::string method = request.modes_method ? *request.modes_method : decl.modes_method;
  if (!modes.empty()) {
    study::ModalTarget t = read_identified_modes(modes, method);
    std::map<std::string, std::string> to_station;
    for (const auto& m : maps) to_station.insert(split_pair(m, "--map"));
    const study::Scenario sc = to_scenario(flat);
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
  if (!request.weights.empty()) {
    opt.weights = study::FitWeights{0, 0, 0, 0, 0};
    for (const auto& w : request.weights) {
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
  if (request.starts) opt.starts = *request.starts;
  if (request.no_spectral_start) opt.spectral_start = false;
  opt.zero = study::parse_zero(request.zero, "--zero");
  if (request.max_iterations) opt.max_iterations = *request.max_iterations;
  if (request.max_time_s) opt.max_time_s = *request.max_time_s;
  opt.threads = request.threads;
  std::string why;
  if (!opt.is_valid(&why)) throw InputError(why);
  problem.scenario_at = scenario_builder(flat, problem.params);
  return {std::move(problem), std::move(opt)};
}

namespace {
// fit.csv, fit_correlation.csv, fit_trace.csv, fit_residuals.csv, fit_time.csv, fit_modes.csv.
void write_fit_tables(const std::string& dir, const study::FitProblem& problem, const study::FitResult& r) {
  const std::size_t np = problem.params.size();
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < np; ++i) {
    const auto& p = problem.params[i];
    const double ref = std::abs(r.estimate[i]) > 0 ? std::abs(r.estimate[i]) : p.upper - p.lower;
    rows.push_back({p.key, p.unit, p.scale == study::ParameterScale::log ? "log" : "linear", fit_cell(p.lower), fit_cell(p.upper),
                    fit_cell(p.initial), fit_cell(r.estimate.empty() ? p.initial : r.estimate[i]),
                    r.std_error.empty() ? "" : error_cell(r.std_error[i]), r.std_error.empty() ? "" : error_cell(r.std_error[i] / ref),
                    r.sensitivity.empty() ? "" : fit_cell(r.sensitivity[i]), r.at_bound.empty() ? "" : (r.at_bound[i] ? "true" : "false"),
                    r.determined.empty() ? "" : (r.determined[i] ? "true" : "false")});
  }
  write_table_csv(dir + "/fit.csv",
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
        row.push_back(r.correlation.size() ? fit_cell(r.correlation(static_cast<Index>(i), static_cast<Index>(j))) : "");
      cr.push_back(row);
    }
    write_table_csv(dir + "/fit_correlation.csv", head, cr);
  }
  {
    std::vector<std::string> head = {"start", "stage", "iteration", "cost"};
    for (const auto& p : problem.params) head.push_back(p.key);
    std::vector<std::vector<std::string>> tr;
    for (const auto& tp : r.trace) {
      std::vector<std::string> row = {std::to_string(tp.start + 1), tp.stage == 1 ? "spectral" : "fit", std::to_string(tp.iteration), fit_cell(tp.cost)};
      for (double v : tp.values) row.push_back(fit_cell(v));
      tr.push_back(row);
    }
    write_table_csv(dir + "/fit_trace.csv", head, tr);
  }
  {
    std::vector<std::vector<std::string>> tr;
    for (const auto& t : r.terms) tr.push_back({t.objective, t.record, t.channel, fit_cell(t.before), fit_cell(t.after)});
    write_table_csv(dir + "/fit_residuals.csv", {"objective", "record", "channel", "before", "after"}, tr);
  }
  {
    std::vector<std::vector<std::string>> tr;
    for (const auto& ov : r.overlays)
      for (Index i = 0; i < ov.t.size(); ++i)
        tr.push_back({ov.record, ov.channel, fit_cell(ov.t[i]), fit_cell(ov.measured[i]), fit_cell(ov.initial[i]), fit_cell(ov.fitted[i])});
    write_table_csv(dir + "/fit_time.csv", {"record", "channel", "t_s", "measured", "initial", "fitted"}, tr);
  }
  {
    std::vector<std::vector<std::string>> tr;
    for (std::size_t k = 0; k < r.modal_pairs.size(); ++k) {
      const auto& mp = r.modal_pairs[k];
      tr.push_back({std::to_string(k + 1), fit_cell(mp.frequency_hz), fit_cell(mp.model_before_hz), fit_cell(mp.model_after_hz),
                    fit_cell(mp.mac_before), fit_cell(mp.mac_after), fit_cell(mp.damping_ratio), fit_cell(mp.model_damping_before),
                    fit_cell(mp.model_damping_after)});
    }
    write_table_csv(dir + "/fit_modes.csv",
                        {"mode", "identified_hz", "model_before_hz", "model_after_hz", "mac_before", "mac_after",
                         "identified_damping_ratio", "model_damping_before", "model_damping_after"},
                        tr);
  }
}

// fit.toml (the summary) and fitted.toml (the scenario with the estimates).
void write_fit_summary(const std::string& dir, const std::string& scenario_path, const FlatScenario& flat,
                       const study::FitProblem& problem, const study::FitOptions& options, const study::FitResult& r) {
  const std::size_t np = problem.params.size();
  // fit.toml: the summary.
  {
    auto q = [](const std::string& s) {
      Value v;
      v.type = ValueType::string;
      v.s = s;
      return v.to_toml();
    };
    std::ostringstream t;
    t << "# viaduct fit: " << scenario_path << "\n[fit]\n";
    t << "status = " << q(study::to_string(r.status)) << "\nmessage = " << q(r.message) << "\n";
    t << "cost_initial = " << fit_cell(r.cost_initial) << "\ncost_final = " << fit_cell(r.cost_final) << "\n";
    t << "n_residuals = " << r.n_residuals << "\niterations = " << r.iterations << "\nevaluations = " << r.evaluations
      << "\nsimulations = " << r.simulations << "\nstarts = " << options.starts << "\nbest_start = " << r.best_start + 1 << "\n";
    t << "wall_s = " << fit_cell(r.wall_s) << "\nthreads = " << options.threads << "\n";
    t << "weights = { time = " << fit_cell(options.weights.time) << ", peak = " << fit_cell(options.weights.peak) << ", envelope = "
      << fit_cell(options.weights.envelope) << ", spectrum = " << fit_cell(options.weights.spectrum) << ", modal = " << fit_cell(options.weights.modal)
      << ", damping = " << fit_cell(options.weights.damping) << " }\n";
    t << "warnings = [";
    for (std::size_t i = 0; i < r.warnings.size(); ++i) t << (i ? ", " : "") << q(r.warnings[i]);
    t << "]\n";
    t << "start_costs = [";
    for (std::size_t i = 0; i < r.start_costs.size(); ++i) t << (i ? ", " : "") << (std::isfinite(r.start_costs[i]) ? fit_cell(r.start_costs[i]) : "inf");
    t << "]\n";
    t << "record_shifts_s = [";
    for (std::size_t i = 0; i < r.shift_s.size(); ++i) t << (i ? ", " : "") << (std::isfinite(r.shift_s[i]) ? fit_cell(r.shift_s[i]) : "nan");
    t << "]\n";
    for (std::size_t i = 0; i < np && !r.std_error.empty(); ++i) {
      t << "\n[[fit.params]]\nkey = " << q(problem.params[i].key) << "\nunit = " << q(problem.params[i].unit)
        << "\ninitial = " << fit_cell(problem.params[i].initial) << "\nestimate = " << fit_cell(r.estimate[i])
        << "\nstd_error = " << (std::isfinite(r.std_error[i]) ? fit_cell(r.std_error[i]) : "inf")
        << "\ndetermined = " << (r.determined[i] ? "true" : "false") << "\n";
    }
    detail::write_text_atomically(dir + "/fit.toml", t.str());
  }
  // The scenario with the fitted values.
  FlatScenario fitted = flat;
  for (std::size_t i = 0; i < np && !r.estimate.empty(); ++i) set_number(fitted, problem.params[i].key, r.estimate[i]);
  write_scenario_toml(dir + "/fitted.toml", fitted,
                          "Written by viaduct fit from " + scenario_path + " (" + study::to_string(r.status) +
                              "): the fitted keys hold their estimates; see fit.csv for standard errors.");
}
}  // namespace

void write_fit_outputs(const std::string& dir, const std::string& scenario_path, const FlatScenario& flat,
                       const study::FitProblem& problem, const study::FitOptions& options, const study::FitResult& r) {
  write_fit_tables(dir, problem, r);
  write_fit_summary(dir, scenario_path, flat, problem, options, r);
}

}  // namespace viaduct::io
