// Shards of a sweep and their merge (viaduct/io/sweep_shard.hpp).
#include "viaduct/io/sweep_shard.hpp"

#include <algorithm>
#include <sstream>

#include <toml.hpp>

#include "atomic_file.hpp"
#include "shard_files.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/io/results.hpp"

namespace viaduct::io {

std::pair<std::size_t, std::size_t> sweep_shard_range(int k, int n, std::size_t n_total) {
  const auto part = [&](int i) { return std::size_t(i) * n_total / std::size_t(n); };
  return {part(k - 1), part(k)};
}

void write_sweep_shard_toml(const SweepShard& s) {
  using detail::g17;
  using detail::toml_string;
  std::ostringstream os;
  os << "# viaduct sweep --shard: one part of a sweep; viaduct merge joins the parts\n[shard]\nkind = \"sweep\"\nk = " << s.k
     << "\nn = " << s.n << "\nbegin = " << s.begin << "\nend = " << s.end << "\nn_total = " << s.n_total
     << "\nfingerprint = " << toml_string(s.fingerprint) << "\nfiles = [";
  for (std::size_t i = 0; i < s.files.size(); ++i) os << (i ? ", " : "") << toml_string(s.files[i]);
  os << "]\nload_effects = " << (s.load_effects ? "true" : "false") << "\nn_variants = " << s.n_variants
     << "\nn_rows = " << s.n_rows << "\nn_failed = " << s.n_failed << "\nn_failed_input = " << s.n_failed_input << "\n";
  // The governing cases to the last bit (governing.csv rounds to 10 digits): the merge compares these.
  for (const auto& g : s.governing) {
    os << "\n[[governing]]\nstation = " << toml_string(g.station);
    for (const auto& [name, c] : {std::pair<const char*, const study::GoverningCase*>{"acc", &g.acc}, {"disp", &g.disp}})
      os << "\n" << name << " = " << g17(c->value) << "\n" << name << "_variant = " << toml_string(c->variant) << "\n"
         << name << "_train = " << toml_string(c->train) << "\n" << name << "_speed_mps = " << g17(c->speed);
    os << "\n";
  }
  write_text_file(s.dir + "/shard.toml", os.str());
}

std::string shard_kind(const std::string& dir) {
  const toml::value root = detail::read_shard_file(dir);
  const toml::value& shard = root.at("shard");
  if (!shard.contains("kind")) return "sample";
  return detail::find_in<std::string>(root, "shard", "kind", dir + "/shard.toml");
}

namespace {
study::GoverningCase governing_case(const toml::value& item, const std::string& q, const std::string& path) {
  auto get = [&](const std::string& key, auto as) {
    try {
      return toml::find<decltype(as)>(item, key);
    } catch (const std::exception&) {
      throw InputError(SourceLocation{path, 1, "governing." + key}, "missing or of the wrong type");
    }
  };
  return {get(q, 0.0), get(q + "_variant", std::string{}), get(q + "_train", std::string{}), get(q + "_speed_mps", 0.0)};
}
}  // namespace

SweepShard read_sweep_shard_toml(const std::string& dir) {
  using detail::find_in;
  const std::string path = dir + "/shard.toml";
  const toml::value v = detail::read_shard_file(dir);
  SweepShard s;
  s.dir = dir;
  s.k = find_in<int>(v, "shard", "k", path);
  s.n = find_in<int>(v, "shard", "n", path);
  s.begin = find_in<std::size_t>(v, "shard", "begin", path);
  s.end = find_in<std::size_t>(v, "shard", "end", path);
  s.n_total = find_in<std::size_t>(v, "shard", "n_total", path);
  s.fingerprint = find_in<std::string>(v, "shard", "fingerprint", path);
  s.files = find_in<std::vector<std::string>>(v, "shard", "files", path);
  for (const auto& f : s.files)  // only a sweep's own files: merge writes them into its --out
    if (f != "envelope.csv" && f != "failures.csv" && f != "load_effects.csv" && f != "vehicles.csv")
      throw InputError(SourceLocation{path, 1, "shard.files"}, "'" + f + "' is not a file a sweep writes");
  s.load_effects = find_in<bool>(v, "shard", "load_effects", path);
  s.n_variants = find_in<std::size_t>(v, "shard", "n_variants", path);
  s.n_rows = find_in<std::size_t>(v, "shard", "n_rows", path);
  s.n_failed = find_in<std::size_t>(v, "shard", "n_failed", path);
  s.n_failed_input = find_in<std::size_t>(v, "shard", "n_failed_input", path);
  if (v.contains("governing")) {
    if (!v.at("governing").is_array()) throw InputError(SourceLocation{path, 1, "governing"}, "expected an array of tables");
    for (const auto& item : v.at("governing").as_array()) {
      if (!item.is_table() || !item.contains("station") || !item.at("station").is_string())
        throw InputError(SourceLocation{path, 1, "governing.station"}, "missing or of the wrong type");
      s.governing.push_back({item.at("station").as_string().str, governing_case(item, "acc", path), governing_case(item, "disp", path)});
    }
  }
  if (s.k < 1 || s.k > s.n || s.end < s.begin || s.end > s.n_total || s.n_failed_input > s.n_failed)
    throw InputError(SourceLocation{path, 1, "shard"}, "inconsistent shard (k, n, begin, end, n_failed)");
  return s;
}

SweepMerge merge_sweep_shards(const std::vector<std::string>& dirs, const std::string& out) {
  std::vector<SweepShard> shards;
  for (const auto& d : dirs) shards.push_back(read_sweep_shard_toml(d));
  std::vector<detail::ShardPart> parts;
  for (const auto& s : shards)
    parts.push_back({s.dir, s.k, s.n, static_cast<long long>(s.begin), static_cast<long long>(s.end),
                     static_cast<long long>(s.n_total), s.fingerprint});
  detail::check_shards_join(parts, "cases");
  std::sort(shards.begin(), shards.end(), [](const SweepShard& x, const SweepShard& y) { return x.k < y.k; });
  SweepMerge m;
  m.n_shards = shards.size();
  m.n_cases = shards.front().n_total;
  m.n_variants = shards.front().n_variants;
  for (const auto& s : shards) {
    if (s.load_effects != shards.front().load_effects)
      throw InputError(SourceLocation{s.dir + "/shard.toml", 1, "shard.load_effects"},
                       "shard " + std::to_string(s.k) + " ran " + (s.load_effects ? "with" : "without") + " --load-effects, shard " +
                           std::to_string(shards.front().k) + (s.load_effects ? " without" : " with") +
                           ": run every shard with the same options");
    for (const auto& f : s.files)
      if (std::find(m.files.begin(), m.files.end(), f) == m.files.end()) m.files.push_back(f);
    m.n_rows += s.n_rows;
    m.n_failed += s.n_failed;
    m.n_failed_input += s.n_failed_input;
    // The first of equal values in case order wins: a later shard only with a larger value.
    for (const auto& g : s.governing) {
      auto it = std::find_if(m.governing.begin(), m.governing.end(), [&](const auto& x) { return x.station == g.station; });
      if (it == m.governing.end()) {
        m.governing.push_back(g);
        continue;
      }
      if (g.acc.value > it->acc.value) it->acc = g.acc;
      if (g.disp.value > it->disp.value) it->disp = g.disp;
    }
  }
  for (const auto& name : m.files) {
    detail::AtomicFile f(out + "/" + name);
    bool first = true;
    for (const auto& s : shards)
      if (std::find(s.files.begin(), s.files.end(), name) != s.files.end()) {
        detail::concatenate(s.dir, name, first, f.get());
        first = false;
      }
    f.commit();
  }
  write_governing_csv(out + "/governing.csv", m.governing);
  m.files.push_back("governing.csv");
  return m;
}

}  // namespace viaduct::io
