#pragma once
/// \file An output directory holds the files of one run, never of two without saying so (issue
/// #36): a command starts by removing the manifest an earlier run left (begin_outputs), writes
/// its files (each atomically), and writes manifest.toml last, listing every file it wrote with
/// its SHA-256 ([[outputs]]). A run killed between leaves a directory without a manifest: its
/// files are not a result. Whatever reads an output directory checks it first (check_output_dir).

#include <string>
#include <vector>

namespace viaduct::io {

/// Creates `dir` (with its parents), removes a manifest.toml an earlier run left there, and
/// starts the list of the files this process writes into it. SolverError when it cannot.
void begin_outputs(const std::string& dir);

/// The files committed into `dir` (io::detail::AtomicFile) since begin_outputs(dir), in the order
/// written, each once (paths as written).
std::vector<std::string> outputs_written(const std::string& dir);

/// Records that `path` was written (AtomicFile::commit calls it), with the SHA-256 of what was
/// written when the writer computed it as it wrote (empty: not known).
void note_output(const std::string& path, const std::string& sha256 = std::string());

/// The SHA-256 note_output recorded for `path` (the path as written), or empty.
std::string output_checksum(const std::string& path);

/// Checks an output directory before it is read: a manifest.toml, and every file its
/// [[outputs]] list present with the checksum written. InputError naming the directory and the
/// file otherwise ("written by a run that did not finish", "changed since").
void check_output_dir(const std::string& dir);

}  // namespace viaduct::io
