#include "build_paths.hpp"

namespace viaduct::cli {

const char* installed_scripts_dir() { return VIADUCT_INSTALLED_SCRIPTS; }
const char* built_source_dir() { return VIADUCT_SOURCE_DIR; }

}  // namespace viaduct::cli
