#pragma once
// Output files written atomically: the text goes to a hidden temporary file in the target's
// directory, which replaces the target by rename() only once it is complete and closed. An
// interrupted or failed run leaves the old file (or none), never a cut one; a full disk leaves
// the earlier result in place.

#include <cstddef>
#include <cstdio>
#include <string>

#include "sha256_stream.hpp"

namespace viaduct::io::detail {

class AtomicFile {
 public:
  /// Opens ".<name>.tmp-<pid>-<n>" beside `path`; SolverError when it cannot.
  explicit AtomicFile(std::string path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  /// Removes the temporary file unless commit() succeeded.
  ~AtomicFile();

  /// The file to write to (its checksum is then computed from the file for the manifest).
  std::FILE* get() const {
    raw_ = true;
    return f_;
  }
  /// n bytes written and hashed as they go: a file written only this way gives the manifest its
  /// checksum without reading it back (output_checksum, output_dir.hpp). Does not throw (a write
  /// error shows at commit()).
  void write(const char* p, std::size_t n);
  /// Flushes, closes and renames over the target; SolverError (temporary file removed) when any
  /// write, the close or the rename failed.
  void commit();

 private:
  std::string path_, tmp_;
  std::FILE* f_ = nullptr;
  bool committed_ = false;
  mutable bool raw_ = false;  // written through get(): no checksum of its own
  Sha256Stream sum_;
};

/// `text` as the whole content of `path`, atomically.
void write_text_atomically(const std::string& path, const std::string& text);

}  // namespace viaduct::io::detail
