// viaduct replay: a manifest run again (issue #37).
#include <vector>

#include "cli.hpp"
#include "viaduct/io/replay.hpp"

namespace viaduct::cli {

Command replay_command(const std::vector<Command>* commands) {
  Command c;
  c.name = "replay";
  c.summary = "run again the command that wrote a manifest, from the manifest (its resolved scenario)";
  c.positional = "MANIFEST";
  c.usage_and_samples =
      "Runs the command that wrote MANIFEST (an output directory's manifest.toml) again, with the\n"
      "resolved scenario the manifest holds (every key, defaults included, --set folded in) and the\n"
      "same options, into --out: the files come out byte for byte as the first time. Every other\n"
      "file the run read (train and coach files, records, profiles) must be unchanged (its SHA-256):\n"
      "a replay that could not run what was run is refused.\n\n"
      "Sample runs:\n"
      "  viaduct run scenarios/hslm-simply-supported.toml --speed-kmh 250 --out out/replayed-first\n"
      "  viaduct replay out/replayed-first/manifest.toml --out out/replayed\n";
  c.run = [commands](const Common& o) {
    const io::ReplaySpec spec = io::read_replay(o.scenario);
    const Command* cmd = nullptr;
    for (const auto& k : *commands)
      if (k.name == spec.command) cmd = &k;
    if (!cmd || spec.command == "replay") throw InputError(o.scenario + ": no command '" + spec.command + "' to replay");
    io::check_replay_inputs(spec);
    // A scenario command reads the manifest itself; a record command its record, as given.
    const bool scenario = cmd->positional.find("SCENARIO") != std::string::npos && spec.has_scenario;
    std::vector<std::string> args = {cmd->name};
    if (!spec.positional.empty()) args.push_back(scenario ? o.scenario : spec.positional);
    args.insert(args.end(), spec.arguments.begin(), spec.arguments.end());
    args.insert(args.end(), {"--out", o.out, "--threads", std::to_string(o.threads)});
    if (o.quiet) args.push_back("--quiet");
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    return dispatch(*cmd, static_cast<int>(argv.size()), argv.data());
  };
  return c;
}

}  // namespace viaduct::cli
