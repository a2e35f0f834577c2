#include "viaduct/io/scenario.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

#include <toml.hpp>

#include "toml_file.hpp"

namespace viaduct::io {

namespace fs = std::filesystem;

namespace {

std::string num(double v) { return format_number(v, 12); }

// "stations[3].name" -> "stations[].name"
std::string pattern_of(const std::string& key) {
  static const std::regex idx(R"(\[[0-9]+\])");
  return std::regex_replace(key, idx, "[]");
}

const KeySpec* find_spec(const std::string& key) {
  const std::string p = pattern_of(key);
  for (const auto& s : scenario_schema())
    if (s.key == p) return &s;
  return nullptr;
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0u : 1u)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string did_you_mean(const std::string& key) {
  const std::string p = pattern_of(key);
  std::string best;
  std::size_t bd = 1000;
  for (const auto& s : scenario_schema()) {
    const std::size_t d = edit_distance(p, s.key);
    if (d < bd) {
      bd = d;
      best = s.key;
    }
  }
  // Also match on the last component alone (e.g. "track.pads.k" vs "track.pad.k").
  if (bd <= std::max<std::size_t>(2, p.size() / 4)) return " (did you mean '" + best + "'?)";
  return "";
}

SourceLocation loc_of(const toml::value& v, const std::string& key, const std::string& file, const detail::TomlFile& tf) {
  SourceLocation w;
  w.file = file;
  w.key = key;
  w.line = tf.line_of(v);
  return w;
}

[[noreturn]] void bad(const SourceLocation& w, const std::string& msg) { throw InputError(w, msg); }

Value scalar_from_toml(const toml::value& v, const SourceLocation& w) {
  Value out;
  out.where = w;
  if (v.is_boolean()) {
    out.type = ValueType::boolean;
    out.b = v.as_boolean();
  } else if (v.is_integer()) {
    out.type = ValueType::integer;
    out.x = static_cast<double>(v.as_integer());
  } else if (v.is_floating()) {
    out.type = ValueType::number;
    out.x = v.as_floating();
    if (!std::isfinite(out.x)) bad(w, "must be a finite number, got " + num(out.x));
  } else if (v.is_string()) {
    out.type = ValueType::string;
    out.s = v.as_string().str;
  } else if (v.is_array()) {
    const auto& arr = v.as_array();
    bool all_num = true, all_str = true;
    for (const auto& e : arr) {
      all_num = all_num && (e.is_integer() || e.is_floating());
      all_str = all_str && e.is_string();
    }
    if (arr.empty() || all_num) {
      out.type = ValueType::number_list;
      for (const auto& e : arr) {
        out.xs.push_back(e.is_integer() ? static_cast<double>(e.as_integer()) : e.as_floating());
        if (!std::isfinite(out.xs.back())) bad(w, "must hold finite numbers, got " + num(out.xs.back()));
      }
    } else if (all_str) {
      out.type = ValueType::string_list;
      for (const auto& e : arr) out.ss.push_back(e.as_string().str);
    } else {
      bad(w, "arrays must hold only numbers or only strings");
    }
  } else {
    bad(w, "unsupported value type (dates and inline tables are not scenario values)");
  }
  return out;
}

void flatten(const toml::value& v, const std::string& prefix, const std::string& file, const detail::TomlFile& tf,
             std::map<std::string, Value>& out) {
  for (const auto& [k, child] : v.as_table()) {
    const std::string key = prefix.empty() ? k : prefix + "." + k;
    if (child.is_table()) {
      flatten(child, key, file, tf, out);
    } else if (child.is_array() && !child.as_array().empty() && child.as_array().front().is_table()) {
      const auto& arr = child.as_array();
      for (std::size_t i = 0; i < arr.size(); ++i) {
        if (!arr[i].is_table()) bad(loc_of(arr[i], key, file, tf), "mixed array of tables");
        flatten(arr[i], key + "[" + std::to_string(i) + "]", file, tf, out);
      }
    } else {
      out[key] = scalar_from_toml(child, loc_of(child, key, file, tf));
    }
  }
}

// A viaduct manifest ([run] with a command, and the resolved [scenario]) read as a scenario.
bool is_manifest(const toml::value& root) {
  return root.is_table() && root.contains("run") && root.at("run").is_table() && root.at("run").contains("command") &&
         root.contains("scenario") && root.at("scenario").is_table();
}

// Its [scenario] table: every resolved key as written there ("stations[0].name" = ...), but those
// that took their default when it was written ([run] scenario_defaulted): they default again.
void read_manifest_scenario(const detail::TomlFile& tf, const std::string& path, std::map<std::string, Value>& out) {
  for (const auto& [key, child] : tf.root.at("scenario").as_table()) {
    if (child.is_table() || (child.is_array() && !child.as_array().empty() && child.as_array().front().is_table()))
      bad(loc_of(child, key, path, tf), "a manifest's [scenario] holds flat keys only");
    out[key] = scalar_from_toml(child, loc_of(child, key, path, tf));
  }
  const toml::value& run = tf.root.at("run");
  if (run.contains("scenario_defaulted") && run.at("scenario_defaulted").is_array())
    for (const auto& k : run.at("scenario_defaulted").as_array())
      if (k.is_string()) out.erase(k.as_string());
}

detail::TomlFile parse_file(const std::string& path, const SourceLocation& referenced_from) {
  if (!fs::exists(path)) throw InputError(referenced_from, "file not found: " + path);
  try {
    return detail::parse_toml_file(path);
  } catch (const InputError&) {
    throw;
  } catch (const toml::syntax_error& e) {
    throw InputError(std::string("TOML syntax error: ") + e.what());
  } catch (const std::exception& e) {
    throw InputError(path + ": cannot read: " + e.what());
  }
}

std::string resolve_relative(const std::string& p, const SourceLocation& where) {
  if (p.empty()) return p;
  const fs::path path(p);
  if (path.is_absolute() || where.file.empty() || where.file == "--set" || where.file == "default")
    return path.lexically_normal().string();
  return (fs::path(where.file).parent_path() / path).lexically_normal().string();
}

// Type check: integer satisfies number; number satisfies number_or_list; list too.
bool type_fits(ValueType want, const Value& v) {
  switch (want) {
    case ValueType::number: return v.type == ValueType::number || v.type == ValueType::integer;
    case ValueType::integer: return v.type == ValueType::integer;
    case ValueType::number_or_list:
      return v.type == ValueType::number || v.type == ValueType::integer || v.type == ValueType::number_list;
    case ValueType::number_list: return v.type == ValueType::number_list;
    case ValueType::string_list: return v.type == ValueType::string_list || (v.type == ValueType::number_list && v.xs.empty());
    default: return v.type == want;
  }
}

const char* type_name(ValueType t) {
  switch (t) {
    case ValueType::boolean: return "a boolean";
    case ValueType::integer: return "an integer";
    case ValueType::number: return "a number";
    case ValueType::string: return "a string";
    case ValueType::number_list: return "a list of numbers";
    case ValueType::string_list: return "a list of strings";
    case ValueType::number_or_list: return "a number or a list of numbers";
  }
  return "?";
}

void check_constraint(const KeySpec& spec, const Value& v) {
  const std::string& c = spec.constraint;
  if (c.empty()) return;
  if (c.find('|') != std::string::npos) {
    std::stringstream ss(c);
    std::string opt;
    while (std::getline(ss, opt, '|'))
      if (opt == v.s) return;
    bad(v.where, "must be one of " + c + ", got '" + v.s + "'");
  }
  // Integer keys are counts and indices held in an int: beyond its range a value would wrap.
  if (spec.type == ValueType::integer && !(std::abs(v.x) <= 2147483647.0))
    bad(v.where, "must be an integer within +-2147483647, got " + (std::abs(v.x) >= 9.2e18 ? std::string("a value beyond 64 bits") : num(v.x)));
  std::vector<double> xs = v.xs;
  if (v.type == ValueType::number || v.type == ValueType::integer) xs = {v.x};
  for (double x : xs) {
    std::string unit = spec.unit.empty() || spec.unit == "-" ? "" : " [" + spec.unit + "]";
    if (!std::isfinite(x)) bad(v.where, "must be finite, got " + num(x));
    bool ok = true;
    if (c == "> 0") ok = x > 0;
    else if (c == ">= 0") ok = x >= 0;
    else if (c == ">= 1") ok = x >= 1;
    else if (c == ">= 0.5") ok = x >= 0.5;
    else if (c == "[0, 1)") ok = x >= 0 && x < 1;
    else if (c == "[0, 1]") ok = x >= 0 && x <= 1;
    else if (c == "(0, 1]") ok = x > 0 && x <= 1;
    else if (c == "[-1/3, 0]") ok = x >= -1.0 / 3.0 - 1e-15 && x <= 0;
    else if (c == "[1e-12, 0.1]") ok = x >= 1e-12 && x <= 0.1;
    else if (c == "[1, 5]") ok = x >= 1 && x <= 5;
    else if (c == "[0, 3]") ok = x >= 0 && x <= 3;
    else throw std::logic_error("scenario schema: constraint '" + c + "' of " + spec.key + " is not implemented");
    if (!ok) bad(v.where, "must be " + c + unit + ", got " + num(x));
  }
}

Value parse_override_value(const std::string& text, const SourceLocation& w) {
  try {
    detail::require_utf8(text, "--set");
  } catch (const InputError&) {
    throw InputError(w, "the value is not UTF-8 text or holds a control character");
  }
  try {
    std::istringstream is("v = " + text);
    const toml::value root = toml::parse(is, "--set");
    return scalar_from_toml(toml::find(root, "v"), w);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception&) {
    Value v;  // a bare word: take it as a string
    v.type = ValueType::string;
    v.s = text;
    v.where = w;
    return v;
  }
}

Value default_value(const KeySpec& spec, const std::string& key) {
  SourceLocation w{"default", 0, key};
  Value v = parse_override_value(spec.default_toml, w);
  if (spec.type == ValueType::number && v.type == ValueType::integer) v.type = ValueType::number;
  return v;
}

bool section_named(const std::map<std::string, Value>& m, const std::string& prefix) {
  for (const auto& kv : m)
    if (kv.first.compare(0, prefix.size(), prefix) == 0) return true;
  return false;
}

}  // namespace

std::string Value::to_toml() const {
  auto q = [](const std::string& text) {
    std::string o = "\"";
    for (char ch : text) {
      if (ch == '"' || ch == '\\') o += '\\';
      if (ch == '\n') {
        o += "\\n";
        continue;
      }
      o += ch;
    }
    return o + "\"";
  };
  auto n = [](double value) {
    std::ostringstream os;
    os.precision(17);
    os << value;
    std::string text = os.str();
    if (text.find_first_of(".eEn") == std::string::npos) text += ".0";
    return text;
  };
  switch (type) {
    case ValueType::boolean: return b ? "true" : "false";
    case ValueType::integer: return std::to_string(static_cast<long long>(x));
    case ValueType::number: return n(x);
    case ValueType::string: return q(s);
    case ValueType::number_list: {
      std::string o = "[";
      for (std::size_t i = 0; i < xs.size(); ++i) o += (i ? ", " : "") + n(xs[i]);
      return o + "]";
    }
    case ValueType::string_list: {
      std::string o = "[";
      for (std::size_t i = 0; i < ss.size(); ++i) o += (i ? ", " : "") + q(ss[i]);
      return o + "]";
    }
    case ValueType::number_or_list: break;
  }
  return "";
}

const Value& FlatScenario::at(const std::string& key) const {
  auto it = values.find(key);
  if (it == values.end()) throw InputError(SourceLocation{path, 0, key}, "required key is missing");
  return it->second;
}

FlatScenario load_flat(const std::string& path, const std::vector<std::string>& overrides, const std::vector<std::string>& unset) {
  FlatScenario fsn;
  fsn.path = path;
  if (!path.empty()) {  // empty: every key from the overrides (the Python package's dict)
    const detail::TomlFile root = parse_file(path, SourceLocation{});
    if (is_manifest(root.root)) read_manifest_scenario(root, path, fsn.values);  // viaduct replay
    else flatten(root.root, "", path, root, fsn.values);
  }
  for (const auto& o : overrides) {
    // One key=value per override: a line break would smuggle a second one in (or drop it).
    if (o.find_first_of("\n\r") != std::string::npos)
      throw InputError(SourceLocation{"--set", 0, o.substr(0, o.find_first_of("=\n\r"))},
                       "holds a line break: give one key=value per --set");
    const auto eq = o.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError(SourceLocation{"--set", 0, o}, "expected key=value");
    const std::string key = o.substr(0, eq);
    SourceLocation w{"--set", 0, key};
    if (!find_spec(key)) bad(w, "unknown key" + did_you_mean(key));
    fsn.values[key] = parse_override_value(o.substr(eq + 1), w);
  }
  // Component files: keys not already set are read from them.
  for (const std::string comp : {"bridge", "track"}) {
    auto it = fsn.values.find(comp + ".file");
    if (it == fsn.values.end()) continue;
    if (it->second.type != ValueType::string) bad(it->second.where, "must be a string (a path)");
    const std::string file = resolve_relative(it->second.s, it->second.where);
    it->second.s = file;
    const detail::TomlFile croot = parse_file(file, it->second.where);
    std::map<std::string, Value> cvals;
    flatten(croot.root, comp, file, croot, cvals);
    for (auto& kv : cvals) {
      if (kv.first == comp + ".file") bad(kv.second.where, "component files cannot reference other files");
      fsn.values.emplace(kv.first, kv.second);
    }
  }
  // --unset: a key as written in the scenario or its component files, or all under a prefix.
  for (const auto& key : unset) {
    const SourceLocation w{"--unset", 0, key};
    std::size_t n = 0;
    for (auto it = fsn.values.begin(); it != fsn.values.end();) {
      if (key_is_under(it->first, key)) {
        it = fsn.values.erase(it);
        ++n;
      } else {
        ++it;
      }
    }
    if (n == 0) bad(w, find_spec(key) ? "is not set in the scenario" : "unknown key" + did_you_mean(key));
  }
  // Unknown keys and types.
  for (auto& [key, v] : fsn.values) {
    const KeySpec* spec = find_spec(key);
    if (!spec) bad(v.where, "unknown key" + did_you_mean(key));
    if (!type_fits(spec->type, v))
      bad(v.where, std::string("must be ") + type_name(spec->type) + ", got " + v.to_toml());
    if (spec->type == ValueType::number && v.type == ValueType::integer) v.type = ValueType::number;
    if (spec->type == ValueType::string_list && v.type == ValueType::number_list) v.type = ValueType::string_list;
    check_constraint(*spec, v);
  }
  // Train files are relative to where the key was written.
  if (auto it = fsn.values.find("train.files"); it != fsn.values.end())
    for (auto& f : it->second.ss)
      if (!is_builtin_train(f)) f = resolve_relative(f, it->second.where);  // "hslm:A1-A10" names no file
  // So are the fit's record and mode files.
  for (auto& [key, v] : fsn.values) {
    const bool record_file = key.rfind("fit.records[", 0) == 0 && key.size() > 5 && key.compare(key.size() - 5, 5, ".file") == 0;
    if ((record_file || key == "fit.modes" || (key == "irregularity.profile" && !v.s.empty())) && v.type == ValueType::string) v.s = resolve_relative(v.s, v.where);
  }
  // Defaults for the sections the scenario names.
  std::set<std::string> array_items;  // e.g. "stations[0]"
  static const std::regex item(R"(^(.*\[[0-9]+\])\..*$)");
  for (const auto& kv : fsn.values) {
    std::smatch m;
    if (std::regex_match(kv.first, m, item)) array_items.insert(m[1]);
  }
  for (const auto& spec : scenario_schema()) {
    if (spec.default_toml.empty()) continue;
    const auto br = spec.key.find("[]");
    if (br == std::string::npos) {
      const std::string section = spec.key.substr(0, spec.key.find('.') + 1);
      const bool always = section == "bridge." || section == "train." || section == "analysis." ||
                          section == "filter." || section == "modal." || section == "ida." || spec.key.find('.') == std::string::npos;
      if (!always && !section_named(fsn.values, section)) continue;
      if (fsn.values.count(spec.key)) continue;
      fsn.values[spec.key] = default_value(spec, spec.key);
      fsn.defaulted.insert(spec.key);
    } else {
      const std::string head = spec.key.substr(0, br);
      for (const auto& itm : array_items) {
        if (pattern_of(itm) != head + "[]") continue;
        const std::string key = itm + spec.key.substr(br + 2);
        if (fsn.values.count(key)) continue;
        fsn.values[key] = default_value(spec, key);
        fsn.defaulted.insert(key);
      }
    }
  }
  derive_defaults(fsn);
  return fsn;
}

void derive_defaults(FlatScenario& flat) {
  // HHT-α's own β = (1 − α)²/4 and γ = (1 − 2α)/2 for the one of them not given (NewmarkOptions::hht):
  // plain Newmark's 1/4 and 1/2 with α < 0 amplify every step (solve/options.hpp).
  auto alpha = flat.values.find("analysis.alpha");
  if (alpha == flat.values.end()) return;
  const double a = alpha->second.x;
  const std::pair<const char*, double> derived[] = {{"analysis.beta", (1.0 - a) * (1.0 - a) / 4.0},
                                                     {"analysis.gamma", (1.0 - 2.0 * a) / 2.0}};
  for (const auto& [key, value] : derived) {
    auto it = flat.values.find(key);
    if (it != flat.values.end() && flat.defaulted.count(key)) it->second.x = value;
  }
}

void scale_key(FlatScenario& flat, const std::string& key, double factor, const SourceLocation& declared) {
  auto it = flat.values.find(key);
  if (it == flat.values.end())
    throw InputError(declared, "variant key '" + key + "' is not set in the scenario" + did_you_mean(key));
  Value& v = it->second;
  if (v.type == ValueType::number) v.x *= factor;
  else if (v.type == ValueType::number_list) for (double& x : v.xs) x *= factor;
  else throw InputError(declared, "variant key '" + key + "' must be numeric (not an integer, string or boolean)");
  flat.defaulted.erase(key);
  if (const KeySpec* spec = find_spec(key)) {
    try {
      check_constraint(*spec, v);
    } catch (const InputError& e) {
      throw InputError(declared, "factor " + num(factor) + " breaks the rule of " + e.what());
    }
  }
  derive_defaults(flat);
}

void set_number(FlatScenario& flat, const std::string& key, double value) {
  auto it = flat.values.find(key);
  if (it == flat.values.end())
    throw InputError(SourceLocation{flat.path, 0, key}, "key is not set in the scenario" + did_you_mean(key));
  Value v = it->second;
  if (v.type == ValueType::number_list && v.xs.size() == 1) v.xs[0] = value;
  else if (v.type == ValueType::number) v.x = value;
  else throw InputError(v.where, "must be a single number to be set (not a list of several, an integer, string or boolean)");
  if (const KeySpec* spec = find_spec(key)) check_constraint(*spec, v);  // before anything changes
  it->second = v;
  flat.defaulted.erase(key);
  derive_defaults(flat);
}

const KeySpec* find_key_spec(const std::string& key) { return find_spec(key); }

std::string format_resolved(const FlatScenario& flat) {
  std::ostringstream os;
  os << "# resolved scenario: " << flat.path << "\n";
  for (const auto& [key, v] : flat.values) {
    const KeySpec* spec = find_spec(key);
    os << key << " = " << v.to_toml() << "   #";
    if (spec && !spec->unit.empty() && spec->unit != "-") os << " [" << spec->unit << "]";
    if (flat.defaulted.count(key)) os << " default";
    else {
      os << " " << v.where.file;
      if (v.where.line > 0) os << ":" << v.where.line;
    }
    os << "\n";
  }
  return os.str();
}

std::string resolved_toml(const FlatScenario& flat) {
  std::ostringstream os;
  for (const auto& [key, v] : flat.values) os << "\"" << key << "\" = " << v.to_toml() << "\n";
  return os.str();
}

std::string schema_markdown() {
  std::ostringstream os;
  os << "| key | type | default | unit | constraint | meaning |\n|---|---|---|---|---|---|\n";
  for (const auto& s : scenario_schema()) {
    std::string type = type_name(s.type);
    type = type.substr(type.find(' ') + 1);
    std::string cons = s.constraint;
    for (std::size_t p = cons.find('|'); p != std::string::npos; p = cons.find('|', p + 2)) cons.replace(p, 1, "\\|");
    os << "| `" << s.key << "` | " << type << " | " << (s.default_toml.empty() ? "—" : "`" + s.default_toml + "`")
       << " | " << s.unit << " | " << cons << " | " << s.doc << " |\n";
  }
  return os.str();
}

}  // namespace viaduct::io
