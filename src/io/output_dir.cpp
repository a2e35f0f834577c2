// One run per output directory (output_dir.hpp).
#include "viaduct/io/output_dir.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <mutex>

#include <toml.hpp>

#include "viaduct/core/error.hpp"
#include "viaduct/io/results.hpp"

namespace viaduct::io {

namespace fs = std::filesystem;

namespace {
std::mutex g_mutex;
std::map<std::string, std::vector<std::string>> g_written;  // canonical directory -> files written
std::map<std::string, std::string> g_sums;  // path as written -> SHA-256 of what was written, when known

std::string canonical_dir(const std::string& dir) {
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(fs::absolute(dir.empty() ? "." : dir), ec);
  return ec ? dir : p.string();
}
}  // namespace

void begin_outputs(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw SolverError("cannot create output directory " + dir + ": " + ec.message());
  const fs::path manifest = fs::path(dir) / "manifest.toml";
  fs::remove(manifest, ec);
  if (ec) throw SolverError("cannot remove the earlier run's " + manifest.string() + ": " + ec.message());
  const std::lock_guard<std::mutex> lock(g_mutex);
  g_written[canonical_dir(dir)].clear();
}

void note_output(const std::string& path, const std::string& sha256) {
  const fs::path p(path);
  const std::string dir = canonical_dir(p.has_parent_path() ? p.parent_path().string() : ".");
  const std::lock_guard<std::mutex> lock(g_mutex);
  if (sha256.empty()) g_sums.erase(path);
  else g_sums[path] = sha256;
  auto it = g_written.find(dir);
  if (it == g_written.end()) return;  // not an output directory of this process
  if (std::find(it->second.begin(), it->second.end(), path) == it->second.end()) it->second.push_back(path);
}

std::string output_checksum(const std::string& path) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  auto it = g_sums.find(path);
  return it == g_sums.end() ? std::string() : it->second;
}

std::vector<std::string> outputs_written(const std::string& dir) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  auto it = g_written.find(canonical_dir(dir));
  return it == g_written.end() ? std::vector<std::string>{} : it->second;
}

void check_output_dir(const std::string& dir) {
  const fs::path manifest = fs::path(dir) / "manifest.toml";
  std::error_code ec;
  if (!fs::is_regular_file(manifest, ec))
    throw InputError(dir + ": no manifest.toml: the run that wrote this directory did not finish (or it is not a "
                           "viaduct output directory); its files are not a result: run the command again");
  toml::value m;
  try {
    m = toml::parse(manifest.string());
  } catch (const std::exception& e) {
    throw InputError(manifest.string() + ": damaged manifest: " + e.what());
  }
  if (!m.contains("outputs")) return;  // written before #36: nothing to check against
  for (const auto& o : toml::find<std::vector<toml::value>>(m, "outputs")) {
    const std::string name = toml::find_or<std::string>(o, "file", "");
    const std::string sum = toml::find_or<std::string>(o, "sha256", "");
    const fs::path f = fs::path(dir) / name;
    if (!fs::is_regular_file(f, ec))
      throw InputError(dir + ": " + name + ", which the manifest lists, is missing");
    if (sha256_file(f.string()) != sum)
      throw InputError(dir + ": " + name + " changed since the run that wrote the manifest (its SHA-256 differs): "
                             "the directory holds files of two runs");
  }
}

}  // namespace viaduct::io
