#pragma once

namespace viaduct::cli {

/// Where the plot scripts are: the installed ones (cmake --install), and the checkout the tool was
/// built from (its scripts/plot). Defined in build_paths.cpp, the one source of the command
/// compiled with these paths: a clone elsewhere recompiles that small file alone, and a compiler
/// cache reuses the other objects (scripts/test.sh).
const char* installed_scripts_dir();
const char* built_source_dir();

}  // namespace viaduct::cli
