// Model updating from files: parameters, the [fit] section, identified modes, fitted scenario.
#include "viaduct/io/fit.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "viaduct/core/error.hpp"
#include "csv_cells.hpp"

namespace viaduct::io {

namespace fs = std::filesystem;

namespace {

std::string num(double v) { return format_number(v, 12); }

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
    fail("bounds must be finite with lower < upper, got " + num(lower) + ":" + num(upper));
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
  if (p.scale == study::ParameterScale::log && !(lower > 0)) fail("a log scale needs lower > 0, got " + num(lower));
  if (!(initial >= lower && initial <= upper))
    fail("its value " + num(initial) + " (the start) is outside the bounds [" + num(lower) + ", " + num(upper) + "]");
  // The bounds must satisfy the key's own constraint.
  FlatScenario probe;
  probe.path = flat.path;
  probe.values[key] = v;
  for (double b : {lower, upper}) {
    try {
      set_number(probe, key, b);
    } catch (const InputError& e) {
      fail(std::string("bound ") + num(b) + " violates the key's constraint " + spec->constraint);
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
    if (v->x > 0.1) throw InputError(v->where, "must be at most 0.1, got " + num(v->x));
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
  std::ofstream out(path);
  if (!out) throw SolverError("cannot write " + path);
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
  if (!out) throw SolverError("cannot write " + path);
}

}  // namespace viaduct::io
