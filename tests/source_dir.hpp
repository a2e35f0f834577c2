#pragma once
// The checkout the tests were built from (their data: tests/data, data/, scenarios/). Defined in
// tests/source_dir.cpp, the one test source compiled with the path: a clone elsewhere recompiles
// that small file only, so a compiler cache reuses every other test object (scripts/test.sh).
const char* viaduct_test_source_dir();
#define VIADUCT_SOURCE_DIR viaduct_test_source_dir()
