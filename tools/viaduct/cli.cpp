#include "cli.hpp"
#include "viaduct/io/output_dir.hpp"
#include "viaduct/io/results.hpp"

#include <unistd.h>

#include <boost/version.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <regex>

#include "viaduct/core/error.hpp"
#include "viaduct/core/thread_pool.hpp"

namespace viaduct::cli {

namespace {

// A library check names the options struct and field it refused ("WelchOptions::nperseg =
// 100000: violated constraint ..."); when the field is one of this command's options, the message
// names the option instead (--nperseg), and the input file the check was made against.
std::string in_option_terms(const std::string& msg, const po::options_description& opts, const Command& cmd,
                            const std::string& input) {
  static const std::regex field(R"(\b[A-Z][A-Za-z0-9]*::([a-z][a-z0-9_]*)\b)");
  std::string out;
  bool named = false;
  auto from = msg.cbegin();
  for (std::sregex_iterator it(msg.begin(), msg.end(), field), end; it != end; ++it) {
    std::string option = (*it)[1].str();
    std::replace(option.begin(), option.end(), '_', '-');
    out.append(from, (*it)[0].first);
    if (opts.find_nothrow(option, false)) {
      out += "--" + option;
      named = true;
    } else {
      out += (*it)[0].str();
    }
    from = (*it)[0].second;
  }
  out.append(from, msg.cend());
  // An error that names no file (a signal check deep in the library, a run too long for its
  // settings) is about the input the command was given; an option named in a record command's
  // error was checked against its record.
  static const std::regex a_file(R"(\.(csv|uff|unv|toml|txt|mat)\b)", std::regex::icase);
  const bool record_command = cmd.positional.find("SCENARIO") == std::string::npos;
  const bool names_a_file = std::regex_search(out, a_file) || out.rfind("--", 0) == 0;
  if (!input.empty() && out.find(input) == std::string::npos && ((named && record_command) || !names_a_file))
    out = input + ": " + out;
  return out;
}

}  // namespace

int dispatch(const Command& cmd, int argc, char** argv) {
  po::options_description opts("Options");
  opts.add_options()("help,h", "show this help")(
      "set", po::value<std::vector<std::string>>()->composing(),
      "override a scenario key: --set key=value (dotted key, TOML value; repeatable)")(
      "unset", po::value<std::vector<std::string>>()->composing(),
      "remove a scenario key, or a table with all under it (repeatable): --unset sweep.speed_min_kmh")(
      "out", po::value<std::string>()->default_value("out"), "output directory")(
      "threads", po::value<int>()->default_value(1), "worker threads (0: all cores)")(
      "quiet,q", po::bool_switch(), "print nothing but errors");
  if (cmd.add_options) cmd.add_options(opts);
  // Reading logger files (docs/records.md): shared by every command that reads records.
  std::vector<std::string> unit_overrides;
  std::string long_gaps = "split";
  io::ReadOptions read;
  if (cmd.reads_records) {
    po::options_description r("Reading record files (docs/records.md)");
    r.add_options()("time-column", po::value<std::string>(&read.time_column),
                    "the time column: header text, name or 1-based index, or 'none' (default: the column named t_s, time, Time [s], ...)")(
        "rate-hz", optional_value(read.fs_hz), "[Hz] sampling rate when the file does not declare one (with a time column: checked against it)")(
        "unit", list_value(unit_overrides), "CHANNEL=UNIT for a channel named without its unit, e.g. --unit strain_mid=ue (repeatable)")(
        "fill-max-s", value(read.fill_max_s), "[s] missing samples (NaN, empty cells, time gaps) up to this long are interpolated linearly")(
        "long-gaps", value(long_gaps), "longer ones: 'split' leaves them missing in their own channel (a command takes the longest piece "
                                       "where the channels it uses have values; reported), 'refuse' stops")(
        "header-line", value(read.header_line), "the header's line (1-based), when the file's preamble misleads the finder")(
        "skip-lines", value(read.skip_lines), "lines at the top of the file not read at all");
    opts.add(r);
  }
  po::options_description hidden;
  hidden.add_options()("scenario", po::value<std::string>(), "scenario file")(
      "more", po::value<std::vector<std::string>>(), "further positional arguments");
  po::options_description all;
  all.add(opts).add(hidden);
  po::positional_options_description pos;
  pos.add("scenario", 1);
  if (cmd.many_positionals) pos.add("more", -1);
  const std::string prefix = "viaduct " + cmd.name + ": ";
  po::variables_map vm;
  std::vector<std::string> replay;  // what a replay passes again (Common::replay_arguments)
  try {
    const po::parsed_options parsed = po::command_line_parser(argc, argv).options(all).positional(pos).run();
    for (const auto& opt : parsed.options) {
      const bool general = opt.string_key == "set" || opt.string_key == "unset" || opt.string_key == "out" ||
                           opt.string_key == "threads" || opt.string_key == "quiet" || opt.string_key == "scenario";
      if (!general) replay.insert(replay.end(), opt.original_tokens.begin(), opt.original_tokens.end());
    }
    po::store(parsed, vm);
    po::notify(vm);
  } catch (const po::error& e) {
    std::cerr << prefix << "error: " << e.what() << "\n(see 'viaduct " << cmd.name << " --help')\n";
    return usage_error;
  }
  if (vm.count("help")) {
    std::cout << "viaduct " << cmd.name << " — " << cmd.summary << "\n\n"
              << "Usage: viaduct " << cmd.name << " " << cmd.positional << " [options]\n\n"
              << opts << "\n"
              << cmd.usage_and_samples;
    return ok;
  }
  if (cmd.needs_scenario && !vm.count("scenario")) {
    std::cerr << prefix << "error: " << cmd.positional << " is required\n(see 'viaduct " << cmd.name << " --help')\n";
    return usage_error;
  }
  Common c;
  if (vm.count("scenario")) c.scenario = vm["scenario"].as<std::string>();
  if (vm.count("more")) c.more = vm["more"].as<std::vector<std::string>>();
  if (vm.count("set")) c.set = vm["set"].as<std::vector<std::string>>();
  if (vm.count("unset")) c.unset = vm["unset"].as<std::vector<std::string>>();
  c.out = vm["out"].as<std::string>();
  c.threads = vm["threads"].as<int>();
  c.quiet = vm["quiet"].as<bool>();
  c.command = cmd.name;
  c.replay_arguments = replay;
  c.command_line = "viaduct " + cmd.name;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool plain = !a.empty() && a.find_first_of(" \t\n'\"\\$`*?[]{}();&|<>!#~") == std::string::npos;
    std::string quoted = "'";
    for (char ch : a) quoted += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    c.command_line += " " + (plain ? a : quoted + "'");
  }
  if ((!c.set.empty() || !c.unset.empty()) && cmd.positional.find("SCENARIO") == std::string::npos) {
    std::cerr << prefix << "error: --set and --unset change scenario keys; viaduct " << cmd.name << " takes no scenario\n";
    return usage_error;
  }
  if (c.threads < 0) {
    std::cerr << prefix << "error: --threads must be >= 0\n";
    return usage_error;
  }
  if (c.threads == 0) c.threads = hardware_threads();
  try {
    if (cmd.reads_records) {
      for (const auto& u : unit_overrides) {
        const auto eq = u.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == u.size()) throw InputError("--unit needs CHANNEL=UNIT, got '" + u + "'");
        read.units.emplace_back(u.substr(0, eq), u.substr(eq + 1));
      }
      if (long_gaps != "split" && long_gaps != "refuse") throw InputError("--long-gaps must be split or refuse, got '" + long_gaps + "'");
      require_non_negative(read.fill_max_s, "--fill-max-s");
      if (read.header_line < 0) throw InputError("--header-line must be a line number >= 1");
      if (read.skip_lines < 0) throw InputError("--skip-lines must be >= 0");
      if (read.fs_hz) require_positive(*read.fs_hz, "--rate-hz");
      read.split_long_gaps = long_gaps == "split";
      c.read = read;
    }
    return cmd.run(c);
  } catch (const InputError& e) {
    std::cerr << prefix << "error: " << in_option_terms(e.what(), opts, cmd, c.scenario) << "\n";
    return usage_error;
  } catch (const po::error& e) {
    std::cerr << prefix << "error: " << e.what() << "\n";
    return usage_error;
  } catch (const std::exception& e) {
    std::cerr << prefix << "failed: " << e.what() << "\n";
    return runtime_failure;
  }
}


io::Record read_record(const std::string& path, const Common& o) {
  io::ImportReport rep;
  io::Record r = io::read_record(path, o.read, &rep);
  print_import_report(path, rep, o);
  return r;
}

io::Record usable(const io::Record& r, const std::vector<std::size_t>& used, const Common& o) {
  std::vector<std::string> notes;
  io::Record out = io::valid_span(r, used, "viaduct " + o.command, &notes);
  for (const auto& n : notes) std::cerr << "viaduct " << o.command << ": warning: " << n << "\n";
  return out;
}

void print_import_report(const std::string& path, const io::ImportReport& rep, const Common& o) {
  if (!rep.plain) {
    const std::string prefix = "viaduct " + o.command + ": ";
    std::string text;
    const auto lines = io::describe(rep);  // the repairs come last
    const std::size_t n_notes = lines.size() - rep.repairs.size();
    for (std::size_t i = 0; i < lines.size(); ++i)
      if (i >= n_notes) text += prefix + "warning: " + path + ": " + lines[i] + "\n";
      else if (!o.quiet) text += prefix + path + ": " + lines[i] + "\n";
    std::cerr << text;
  }
}

double speed_of(const study::Scenario& sc, const std::optional<double>& speed_kmh) {
  return study::passage_speed(sc, speed_kmh, "--speed-kmh");
}

const load::Train& train_of(const study::Scenario& sc, const std::optional<std::string>& name) {
  return study::passage_train(sc, name);
}

io::FlatScenario load_scenario(const Common& o) {
  for (const auto& s : o.set)
    for (const auto& u : o.unset) {
      const std::string key = s.substr(0, s.find('='));
      if (io::key_is_under(key, u))
        throw InputError("--set " + key + " and --unset " + u + ": give a key one of them (--unset removes after --set)");
    }
  return io::load_flat(o.scenario, o.set, o.unset);
}

void make_out_dir(const std::string& dir) { io::begin_outputs(dir); }

ProgressSink progress_printer(const std::string& what, bool quiet, const std::string& unit) {
  if (quiet) return {};
  const bool tty = ::isatty(::fileno(stderr)) != 0;
  auto t0 = std::make_shared<std::chrono::steady_clock::time_point>(std::chrono::steady_clock::now());
  auto last_decile = std::make_shared<std::size_t>(0);
  auto shown = std::make_shared<bool>(false);
  return [=](std::size_t done, std::size_t total) {
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - *t0).count();
    // Only work that lasts shows progress: nothing before 2 s, and no final line if nothing came before.
    if (el < 2.0 && !*shown) return;
    *shown = true;
    const double eta = done ? el * static_cast<double>(total - done) / static_cast<double>(done) : 0.0;
    if (tty) {
      std::fprintf(stderr, "\r%s: %zu/%zu %s, %.0f s elapsed, ~%.0f s left   ", what.c_str(), done, total, unit.c_str(), el, eta);
      if (done == total) std::fprintf(stderr, "\n");
    } else {
      const std::size_t decile = total ? done * 10 / total : 10;
      if (decile > *last_decile || done == total) {
        *last_decile = decile;
        std::fprintf(stderr, "%s: %zu/%zu %s, %.0f s elapsed\n", what.c_str(), done, total, unit.c_str(), el);
      }
    }
    std::fflush(stderr);
  };
}

std::vector<std::pair<std::string, std::string>> tool_versions() {
  std::string boost = BOOST_LIB_VERSION;
  for (char& c : boost)
    if (c == '_') c = '.';
  return {{"boost_program_options", boost}};
}

io::Manifest start_manifest(const Common& o, const std::string& command, std::vector<std::string> inputs) {
  io::Manifest m;
  m.command = command;
  m.inputs = std::move(inputs);
  m.command_line = o.command_line;
  m.arguments = o.replay_arguments;
  m.positional = o.scenario;
  m.versions = tool_versions();
  return m;
}

void write_record_outputs(const Common& o, const std::string& file, const io::Record& out) {
  make_out_dir(o.out);
  io::write_record_csv(o.out + "/" + file, out);
  io::write_manifest(o.out + "/manifest.toml", start_manifest(o, o.command, {o.scenario}), nullptr);
}

void write_table_outputs(const Common& o, const std::string& file, const std::vector<std::string>& header,
                         const std::vector<std::vector<std::string>>& rows, const std::vector<std::string>& warnings) {
  make_out_dir(o.out);
  io::write_table_csv(o.out + "/" + file, header, rows);
  io::Manifest m = start_manifest(o, o.command, {o.scenario});
  m.warnings = warnings;
  io::write_manifest(o.out + "/manifest.toml", m, nullptr);
}

void add_zero_option(po::options_description& d, std::string& zero, const std::string& prefix) {
  d.add_options()("zero", value(zero),
                  (prefix + "deflection and strain channels' zero: keep (the level before the train's entry kept; a warning when "
                            "it is an offset), pre-entry (its mean removed) or START:END (the mean of that window of record time)")
                      .c_str());
}

Command command(std::string name, std::string positional, std::string summary) {
  Command c;
  c.name = std::move(name);
  c.positional = std::move(positional);
  c.summary = std::move(summary);
  return c;
}

Command record_command(std::string name, std::string positional, std::string summary) {
  Command c = command(std::move(name), std::move(positional), std::move(summary));
  c.reads_records = true;
  return c;
}

void print_first_modes(const model::Structure& s, const model::Modes& m, Index n, const char* prefix) {
  for (Index j = 0; j < std::min<Index>(m.frequency_hz.size(), n); ++j) {
    const model::ModeTag t = model::tag_mode(s, m.shape.col(j));
    const model::DeckBending& b = t.bending;
    std::string where;
    if (b.span > 0)
      where = b.order == 0 ? "span " + std::to_string(b.span) + " rigid on its bearings"
                           : "span " + std::to_string(b.span) + " bending " + std::to_string(b.order);
    std::printf("%s%2ld  %9.4f Hz  %-7s  deck mass share %.2f%s%s\n", prefix, static_cast<long>(j + 1), m.frequency_hz[j],
                t.kind, t.deck_share, where.empty() ? "" : "  ", where.c_str());
  }
}

std::string describe_f1(const model::Structure& s, std::vector<model::DeckMode>* modes) {
  static const char* nth[] = {"", "first", "second", "third", "fourth", "fifth"};
  try {
    const std::vector<model::DeckMode> deck = model::deck_bending_modes(s, 3);
    if (modes) *modes = deck;
    if (deck.empty()) return "f1: no deck bending mode found";
    const model::DeckMode& d = deck.front();
    char b[160];
    std::snprintf(b, sizeof b, "f1 = %.3f Hz (span %d, %s bending)", d.frequency_hz, d.bending.span,
                  d.bending.order <= 5 ? nth[d.bending.order] : "higher");
    return b;
  } catch (const std::exception& e) {
    return std::string("f1: not computed (") + e.what() + ")";
  }
}

void print_governing(const std::vector<study::GoverningRow>& gov, bool with_variant) {
  if (gov.empty()) return;
  std::printf("\ngoverning cases (largest over %strains and speeds):\n", with_variant ? "variants, " : "");
  std::printf("  %-14s %14s  %-16s %7s%s   %12s  %-16s %7s%s\n", "station", "max|acc| m/s²", "train", "km/h",
              with_variant ? "  variant" : "", "max|disp| mm", "train", "km/h", with_variant ? "  variant" : "");
  for (const auto& g : gov)
    std::printf("  %-14s %14.4f  %-16s %7.1f%s   %12.3f  %-16s %7.1f%s\n", g.station.c_str(), g.acc.value, g.acc.train.c_str(),
                g.acc.speed * 3.6, with_variant ? ("  " + g.acc.variant).c_str() : "", g.disp.value * 1e3,
                g.disp.train.c_str(), g.disp.speed * 3.6, with_variant ? ("  " + g.disp.variant).c_str() : "");
}

int sweep_exit_code(const std::string& command, const std::string& scenario, const study::SweepResult& r) {
  for (const auto& f : r.failures)
    std::fprintf(stderr, "viaduct %s: case failed: %s / %s / %.1f km/h: %s\n", command.c_str(), f.variant.c_str(),
                 f.train.c_str(), f.speed * 3.6, f.message.c_str());
  // One exit code per kind of error (docs/reliability.md): a sweep in which every case failed on
  // its input is an input error (2), as the same value is for `run`; otherwise failed cases
  // are a partial result (1, failures.csv).
  if (r.failures.empty()) return ok;
  const bool all_input =
      r.rows.empty() && std::all_of(r.failures.begin(), r.failures.end(), [](const auto& f) { return f.input_error; });
  if (all_input)
    std::fprintf(stderr, "viaduct %s: error: %s: every case failed on its input (failures.csv): %s\n", command.c_str(),
                 scenario.c_str(), r.failures.front().message.c_str());
  return all_input ? usage_error : runtime_failure;
}

void print_resonance_speeds(double f1_hz, const std::vector<load::Train>& trains, double v_min, double v_max) {
  if (!(f1_hz > 0.0) || trains.empty()) return;
  std::printf("\nresonance speeds expected from f1 = %.3f Hz, v = f1·d/j, in the speeds swept:\n", f1_hz);
  for (const auto& t : trains) {
    const double d = load::characteristic_distance(t);
    std::string speeds;
    if (d > 0.0)
      for (int j = 1; j <= 20; ++j) {
        const double v = f1_hz * d / j;
        if (v < v_min * (1 - 1e-9)) break;
        if (v > v_max * (1 + 1e-9)) continue;
        char b[48];
        std::snprintf(b, sizeof b, "%s%.1f (j=%d)", speeds.empty() ? "" : ", ", v * 3.6, j);
        speeds += b;
      }
    std::printf("  %-20s d = %6.2f m: %s\n", t.name.c_str(), d, d > 0.0 ? (speeds.empty() ? "none" : (speeds + " km/h").c_str()) : "single axle");
  }
}

void print_warnings(const std::string& command, const std::vector<std::string>& warnings) {
  for (const auto& w : warnings) std::cerr << ("viaduct " + command + ": warning: " + w + "\n");
}

LogSink log_printer(bool quiet) {
  return [quiet](LogLevel level, const std::string& msg) {
    if (quiet && level != LogLevel::warning) return;
    // One write per message: sweeps log from several threads.
    std::cerr << (std::string("viaduct: ") + (level == LogLevel::warning ? "warning: " : "") + msg + "\n");
  };
}

}  // namespace viaduct::cli
