#include "source_dir.hpp"

const char* viaduct_test_source_dir() { return VIADUCT_SOURCE_DIR_PATH; }
