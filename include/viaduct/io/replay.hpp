#pragma once
/// \file A manifest run again (`viaduct replay`, issue #37): what a manifest says was run — the
/// command, its first positional and its other arguments — and the check that every file it read
/// (but the scenario's own, whose resolved keys the manifest holds) is still the one it read.

#include <string>
#include <vector>

namespace viaduct::io {

struct ReplaySpec {
  std::string manifest;                ///< the manifest's path
  std::string command;                 ///< [run] command
  std::string positional;              ///< [run] positional: the first positional as given
  std::vector<std::string> arguments;  ///< [run] arguments
  bool has_scenario = false;           ///< the manifest holds a [scenario] (replayed from the manifest)
  /// [[inputs]] read from files outside the scenario (train, coach and record files, profiles...),
  /// with the checksum written.
  std::vector<std::pair<std::string, std::string>> inputs;
};

/// Reads what `manifest` says was run. InputError naming the file when it is no viaduct manifest
/// or was written before manifests could be replayed (no [run] arguments).
ReplaySpec read_replay(const std::string& manifest);

/// InputError naming the first input that is missing or whose SHA-256 is not the one written:
/// the replay would not run what was run.
void check_replay_inputs(const ReplaySpec& spec);

}  // namespace viaduct::io
