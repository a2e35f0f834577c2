#pragma once
// Private to src/io: what the shards of a sampled study and of a sweep share — TOML text that
// reads back exactly, the check that a set of shards is one whole study, and the joining of
// their files.
#include <cstdio>
#include <string>
#include <vector>

#include <toml.hpp>

#include "viaduct/core/error.hpp"

namespace viaduct::io::detail {

/// A TOML basic string ("..." with " and \ escaped).
std::string toml_string(const std::string& s);
/// A TOML float that reads back as the same double (a decimal point even for whole numbers).
std::string g17(double x);

/// toml::find<T>(v, table, key), or InputError at path naming table.key.
template <class T>
T find_in(const toml::value& v, const std::string& table, const std::string& key, const std::string& path) {
  try {
    return toml::find<T>(v, table, key);
  } catch (const std::exception&) {
    throw InputError(SourceLocation{path, 1, table + "." + key}, "missing or of the wrong type");
  }
}

/// A state file viaduct wrote (shard.toml, sample_progress.toml) parsed: InputError when it is
/// not TOML or has no [table] (toml11's message, with the file and line), so that a damaged file
/// is an input error (exit 2), not an exception from the parser.
toml::value read_state_toml(const std::string& path, const std::string& table);
/// DIR/shard.toml by read_state_toml; InputError "not a shard" when it is missing.
toml::value read_shard_file(const std::string& dir);

/// One shard as its shard.toml says: part k of n, items [begin, end) of n_total.
struct ShardPart {
  std::string dir;
  int k = 0, n = 0;
  long long begin = 0, end = 0, n_total = 0;
  std::string fingerprint;  ///< SHA-256 of the resolved scenario
};
/// Sorts `parts` by k and checks they are parts 1..n of one study, each once, joining end to end
/// over [0, n_total): InputError naming the foreign, missing or repeated shard (`what`: "samples",
/// "cases").
void check_shards_join(std::vector<ShardPart>& parts, const std::string& what);
/// Appends the rows of dir/name (its header dropped unless `first`) to `out`; InputError when the
/// shard has no such file (it did not finish).
void concatenate(const std::string& dir, const std::string& name, bool first, std::FILE* out);

}  // namespace viaduct::io::detail
