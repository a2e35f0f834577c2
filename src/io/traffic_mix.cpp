// Traffic mix files (EN 1991-2 Annex D Tables D.1-D.3 under data/trains/fatigue/, or a line's own):
// [[trains]] tables of a train file, passages a day and a speed.
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

#include <toml.hpp>

#include "toml_file.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/io/traffic_mix.hpp"

namespace viaduct::io {

namespace fs = std::filesystem;

namespace {

// The number at `key` of table `t` (an integer or a float), or InputError at its line.
double mix_number(const detail::TomlFile& parsed, const toml::value& t, const std::string& key, const SourceLocation& at) {
  if (!t.contains(key)) throw InputError(at, "required");
  const toml::value& v = t.at(key);
  const SourceLocation here{at.file, parsed.line_of(v), at.key};
  if (v.is_integer()) return static_cast<double>(v.as_integer());
  if (v.is_floating()) return v.as_floating();
  throw InputError(here, "must be a number");
}

}  // namespace

study::TrafficMix read_traffic_mix(const std::string& path) {
  if (!fs::exists(path)) throw InputError("traffic mix file not found: " + path);
  detail::TomlFile parsed;
  try {
    parsed = detail::parse_toml_file(path);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(std::string("TOML syntax error: ") + e.what());
  }
  const toml::value& root = parsed.root;
  auto where = [&](const toml::value& v, const std::string& key) { return SourceLocation{path, parsed.line_of(v), key}; };
  for (const auto& [k, v] : root.as_table())
    if (k != "title" && k != "trains") throw InputError(where(v, k), "unknown traffic mix key (title, [[trains]])");
  study::TrafficMix mix;
  mix.title = root.contains("title") && root.at("title").is_string() ? root.at("title").as_string().str : fs::path(path).stem().string();
  if (!root.contains("trains") || !root.at("trains").is_array() || root.at("trains").as_array().empty())
    throw InputError(SourceLocation{path, root.contains("trains") ? parsed.line_of(root.at("trains")) : 1, "trains"},
                     "a traffic mix needs [[trains]] tables (file, per_day, speed_kmh)");
  const auto& trains = root.at("trains").as_array();
  for (std::size_t i = 0; i < trains.size(); ++i) {
    const toml::value& t = trains[i];
    const std::string item = "trains[" + std::to_string(i) + "]";
    if (!t.is_table()) throw InputError(where(t, item), "must be a table (file, per_day, speed_kmh)");
    const SourceLocation at{path, parsed.line_of(t), item};
    for (const auto& [k, v] : t.as_table())
      if (k != "file" && k != "per_day" && k != "speed_kmh" && k != "name")
        throw InputError(where(v, item + "." + k), "unknown key (file, per_day, speed_kmh, name)");
    if (!t.contains("file") || !t.at("file").is_string()) throw InputError(SourceLocation{path, at.line, item + ".file"}, "required: the train file (relative to this file)");
    study::MixTrain mt;
    const std::string file = (fs::path(path).parent_path() / t.at("file").as_string().str).lexically_normal().string();
    if (!fs::exists(file)) throw InputError(where(t.at("file"), item + ".file"), "no train file " + file);
    mt.train = read_train_file(file);
    mt.name = fs::path(file).stem().string();
    if (t.contains("name")) {  // given: a non-empty string (not the file's name in its place, silently)
      const auto& n = t.at("name");
      if (!n.is_string() || n.as_string().str.empty())
        throw InputError(where(n, item + ".name"), "must be a non-empty string (the train's name in damage.csv)");
      mt.name = n.as_string().str;
    }
    mt.per_day = mix_number(parsed, t, "per_day", SourceLocation{path, at.line, item + ".per_day"});
    if (!(mt.per_day >= 0.0) || !std::isfinite(mt.per_day))
      throw InputError(where(t.at("per_day"), item + ".per_day"), "violated constraint per_day >= 0 (passages a day)");
    const double kmh = mix_number(parsed, t, "speed_kmh", SourceLocation{path, at.line, item + ".speed_kmh"});
    if (!(kmh > 0.0) || !std::isfinite(kmh)) throw InputError(where(t.at("speed_kmh"), item + ".speed_kmh"), "violated constraint speed_kmh > 0");
    mt.speed = kmh / 3.6;
    mix.trains.push_back(std::move(mt));
  }
  // A train listed twice (one type at two speeds) is told apart by its speed in damage.csv; the
  // same name at the same speed twice would be two rows no one can tell apart.
  for (std::size_t i = 0; i < mix.trains.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (mix.trains[i].name == mix.trains[j].name && mix.trains[i].speed == mix.trains[j].speed)
        throw InputError(where(trains[i], "trains[" + std::to_string(i) + "]"),
                         "the same train (" + mix.trains[i].name + ") at the same speed as trains[" + std::to_string(j) +
                             "]: add their passages a day together, or tell them apart with name = \"...\"");
  std::vector<int> seen(mix.trains.size(), 0);
  for (std::size_t i = 0; i < mix.trains.size(); ++i)
    for (std::size_t j = 0; j < mix.trains.size(); ++j)
      if (i != j && mix.trains[i].name == mix.trains[j].name) seen[i] = 1;
  for (std::size_t i = 0; i < mix.trains.size(); ++i)
    if (seen[i]) mix.trains[i].name += " at " + format_number(mix.trains[i].speed * 3.6, 6) + " km/h";
  // A name given equal to another's speed-qualified one ("type5 at 80 km/h") would still give
  // two rows of one name.
  for (std::size_t i = 0; i < mix.trains.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (mix.trains[i].name == mix.trains[j].name)
        throw InputError(where(trains[i], "trains[" + std::to_string(i) + "]"),
                         "two trains named \"" + mix.trains[i].name + "\" in damage.csv (trains[" + std::to_string(j) +
                             "] and this one): give one another name = \"...\"");
  return mix;
}

std::vector<TableColumn> fatigue_mix_damage_columns(const study::MixDamage& d, const study::FatigueCount& f) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto finite = [&](double v) { return std::isfinite(v) ? v : nan; };  // ∞ years: no damage, an empty cell
  std::vector<TableColumn> c;
  auto text = [&](const char* name) { c.push_back({name, TableColumn::Kind::text, {}, {}, {}}); };
  auto number = [&](const char* name) { c.push_back({name, TableColumn::Kind::number, {}, {}, {}}); };
  text("train");
  for (const char* n : {"per_day", "speed_kmh"}) number(n);
  text("curve");
  for (const char* n : {"cycles", "damaging_cycles", "max_range_mpa", "damage_per_passage", "damage_per_year", "share_of_year",
                        "equivalent_range_2e6_mpa", "years_to_d1"})
    number(n);
  text("message");
  // m: the passage's sum (none for the total and a train that failed); ran: a year's damage to show.
  auto row = [&](const std::string& name, double per_day, double kmh, const study::MinerSum* m, bool ran, double per_year,
                 double share, const std::string& message) {
    c[0].cells.push_back(name);
    c[1].values.push_back(per_day);
    c[2].values.push_back(kmh);
    c[3].cells.push_back(f.curve.name);
    c[4].values.push_back(m ? m->cycles : nan);
    c[5].values.push_back(m ? m->damaging : nan);
    c[6].values.push_back(m ? m->max_range_pa * 1e-6 : nan);
    c[7].values.push_back(m ? m->damage : nan);
    c[8].values.push_back(ran ? per_year : nan);
    c[9].values.push_back(ran ? share : nan);
    c[10].values.push_back(ran ? study::equivalent_range_2e6(per_year, f.curve) * 1e-6 : nan);
    c[11].values.push_back(ran ? finite(per_year > 0.0 ? 1.0 / per_year : nan) : nan);
    c[12].cells.push_back(message);
  };
  double per_day = 0.0;
  for (const study::TrainDamage& t : d.trains) {
    per_day += t.per_day;
    row(t.name, t.per_day, t.speed * 3.6, t.passage ? &t.passage->miner : nullptr, t.passage.has_value(), t.per_year,
        d.per_year > 0.0 ? t.per_year / d.per_year : nan, t.error);
  }
  row("total", per_day, nan, nullptr, true, d.per_year, d.per_year > 0.0 ? 1.0 : nan,
      d.n_failed == 0 ? "" : std::to_string(d.n_failed) + " trains failed: the total lacks them");
  return c;
}

std::vector<TableColumn> fatigue_mix_cycle_columns(const study::MixDamage& d, const study::FatigueCount& f) {
  std::vector<TableColumn> c = {{"train", TableColumn::Kind::text, {}, {}, {}}};
  for (const char* n : {"range_low_mpa", "range_high_mpa", "mean_low_mpa", "mean_high_mpa", "count"})
    c.push_back({n, TableColumn::Kind::number, {}, {}, {}});
  for (const study::TrainDamage& t : d.trains) {
    if (!t.passage) continue;
    for (const auto& [b, n] : t.passage->bins) {
      c[0].cells.push_back(t.name);
      c[1].values.push_back(static_cast<double>(b.first) * f.range_bin_mpa);
      c[2].values.push_back(static_cast<double>(b.first + 1) * f.range_bin_mpa);
      c[3].values.push_back(static_cast<double>(b.second) * f.mean_bin_mpa);
      c[4].values.push_back(static_cast<double>(b.second + 1) * f.mean_bin_mpa);
      c[5].values.push_back(n);
    }
  }
  return c;
}

}  // namespace viaduct::io
