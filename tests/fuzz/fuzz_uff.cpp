// Universal File Format dataset 58 (ASCII and binary 58b): what it returns is a clean record.
#include "harness.hpp"
#include "viaduct/io/record.hpp"
#include "record_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::as_file(data, size, ".uff");
  return fuzz::run([&] { fuzz::check_record(viaduct::io::read_uff58(path)); });
}
