// A manifest run again (replay.hpp).
#include "viaduct/io/replay.hpp"

#include <algorithm>
#include <filesystem>

#include <toml.hpp>

#include "viaduct/core/error.hpp"
#include "viaduct/io/results.hpp"

namespace viaduct::io {

ReplaySpec read_replay(const std::string& manifest) {
  if (!std::filesystem::is_regular_file(manifest)) throw InputError(manifest + ": file not found");
  toml::value m;
  try {
    m = toml::parse(manifest);
  } catch (const std::exception& e) {
    throw InputError(manifest + ": not a readable manifest: " + e.what());
  }
  if (!m.contains("run") || !m.at("run").is_table() || !m.at("run").contains("command"))
    throw InputError(manifest + ": not a viaduct manifest (no [run] command)");
  const toml::value& run = m.at("run");
  if (!run.contains("arguments") || !run.contains("positional"))
    throw InputError(manifest + ": written before manifests could be replayed (no [run] arguments): run the command again");
  ReplaySpec r;
  r.manifest = manifest;
  r.command = toml::find<std::string>(run, "command");
  r.positional = toml::find<std::string>(run, "positional");
  r.arguments = toml::find<std::vector<std::string>>(run, "arguments");
  r.has_scenario = m.contains("scenario") && m.at("scenario").is_table();
  // The scenario's own files: their keys are in [scenario], a change to them does not matter.
  std::vector<std::string> own;
  if (run.contains("scenario_file")) own.push_back(toml::find<std::string>(run, "scenario_file"));
  if (r.has_scenario)
    for (const char* k : {"bridge.file", "track.file"})
      if (m.at("scenario").contains(k) && m.at("scenario").at(k).is_string()) own.push_back(m.at("scenario").at(k).as_string());
  auto same = [](const std::string& a, const std::string& b) {
    std::error_code ec;
    return std::filesystem::weakly_canonical(a, ec) == std::filesystem::weakly_canonical(b, ec);
  };
  if (m.contains("inputs") && m.at("inputs").is_array())
    for (const auto& in : m.at("inputs").as_array()) {
      const std::string file = toml::find_or<std::string>(in, "file", ""), sum = toml::find_or<std::string>(in, "sha256", "");
      if (file.empty() || sum == "directory" || sum == "unreadable") continue;  // no file (a value set by a command)
      if (std::any_of(own.begin(), own.end(), [&](const std::string& o) { return same(o, file); })) continue;
      r.inputs.emplace_back(file, sum);
    }
  return r;
}

void check_replay_inputs(const ReplaySpec& spec) {
  for (const auto& [file, sum] : spec.inputs) {
    if (!std::filesystem::exists(file))
      throw InputError(spec.manifest + ": " + file + ", which the run read, is missing: the replay would not run what was run");
    if (sha256_file(file) != sum)
      throw InputError(spec.manifest + ": " + file + " changed since the run (its SHA-256 differs): the replay would not run "
                       "what was run");
  }
}

}  // namespace viaduct::io
