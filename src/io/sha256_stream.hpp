#pragma once
// SHA-256 of bytes given piece by piece (sha256.cpp; sha256_hex and sha256_file are the whole-text
// and whole-file forms in viaduct/io/results.hpp). Private to src/io: AtomicFile hashes what it
// writes through it.

#include <cstddef>
#include <memory>
#include <string>

namespace viaduct::io::detail {

class Sha256Stream {
 public:
  Sha256Stream();
  ~Sha256Stream();
  Sha256Stream(const Sha256Stream&) = delete;
  Sha256Stream& operator=(const Sha256Stream&) = delete;
  void update(const void* p, std::size_t n);
  /// The digest of everything given, as 64 lowercase hex digits (once: it pads the stream).
  std::string hex();

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace viaduct::io::detail
