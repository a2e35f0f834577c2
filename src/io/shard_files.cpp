// What the shards of sampled studies and of sweeps share (shard_files.hpp).
#include "shard_files.hpp"
#include "toml_file.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace viaduct::io::detail {

std::string toml_string(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    o += c;
  }
  return o + "\"";
}

std::string g17(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  std::string s = b;
  if (s.find_first_of(".eni") == std::string::npos) s += ".0";
  return s;
}

toml::value read_state_toml(const std::string& path, const std::string& table) {
  try {
    toml::value root = parse_toml_file(path).root;
    if (!root.contains(table) || !root.at(table).is_table())
      throw InputError(SourceLocation{path, 1, table}, "no [" + table + "] table: not a file viaduct wrote, or a damaged one");
    return root;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path + ": " + e.what());
  }
}

toml::value read_shard_file(const std::string& dir) {
  const std::string path = dir + "/shard.toml";
  if (!std::filesystem::exists(path))
    throw InputError(SourceLocation{path, 1, ""}, "not a shard: " + dir + " has no shard.toml (viaduct sweep --shard K/N writes one)");
  return read_state_toml(path, "shard");
}

void check_shards_join(std::vector<ShardPart>& parts, const std::string& what) {
  if (parts.empty()) throw InputError("no shard directories given");
  std::sort(parts.begin(), parts.end(), [](const ShardPart& x, const ShardPart& y) { return x.k < y.k; });
  const ShardPart& a = parts.front();
  for (const auto& s : parts) {
    if (s.fingerprint != a.fingerprint || s.n != a.n)
      throw InputError(SourceLocation{s.dir + "/shard.toml", 1, "fingerprint"},
                       "shard " + std::to_string(s.k) + "/" + std::to_string(s.n) + " in " + s.dir + " is of another study than " + a.dir);
  }
  for (int k = 1; k <= a.n; ++k) {
    const auto c = std::count_if(parts.begin(), parts.end(), [&](const ShardPart& s) { return s.k == k; });
    if (c == 0) throw InputError("shard " + std::to_string(k) + "/" + std::to_string(a.n) +
                                 " is missing: run it with viaduct sweep ... --shard " + std::to_string(k) + "/" + std::to_string(a.n));
    if (c > 1) throw InputError("shard " + std::to_string(k) + "/" + std::to_string(a.n) + " is given twice");
  }
  for (std::size_t i = 0; i < parts.size(); ++i)
    if (parts[i].begin != (i == 0 ? 0 : parts[i - 1].end) || (i + 1 == parts.size() && parts[i].end != a.n_total))
      throw InputError(SourceLocation{parts[i].dir + "/shard.toml", 1, "begin"}, "the shards' " + what + " do not join end to end");
}

void concatenate(const std::string& dir, const std::string& name, bool first, std::FILE* out) {
  std::ifstream in(dir + "/" + name, std::ios::binary);
  if (!in) throw InputError(SourceLocation{dir + "/" + name, 1, ""}, "missing: the shard in " + dir + " did not finish; rerun it");
  std::string line;
  bool header = true;
  while (std::getline(in, line)) {
    if (!(header && !first)) std::fprintf(out, "%s\n", line.c_str());
    header = false;
  }
}

}  // namespace viaduct::io::detail
