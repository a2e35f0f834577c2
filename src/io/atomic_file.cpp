#include "atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "viaduct/core/error.hpp"
#include "viaduct/io/output_dir.hpp"

namespace viaduct::io::detail {

namespace {
std::atomic<unsigned> counter{0};  // temporary names differ between threads writing at once
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  const std::filesystem::path p(path_);
  const std::string name = "." + p.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  tmp_ = (p.has_parent_path() ? p.parent_path() / name : std::filesystem::path(name)).string();
  f_ = std::fopen(tmp_.c_str(), "w");
  if (!f_) throw SolverError("cannot write " + path_ + ": " + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
  if (f_) std::fclose(f_);
  if (!committed_) std::remove(tmp_.c_str());
}

void AtomicFile::commit() {
  const bool write_error = std::ferror(f_) != 0;
  const int closed = std::fclose(f_);
  const int close_errno = errno;
  f_ = nullptr;
  if (write_error || closed != 0) {
    std::remove(tmp_.c_str());
    throw SolverError("error writing " + path_ + (closed != 0 ? std::string(": ") + std::strerror(close_errno) : std::string()) +
                      " (an earlier file of that name is left as it was)");
  }
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    const int e = errno;
    std::remove(tmp_.c_str());
    throw SolverError("cannot replace " + path_ + ": " + std::strerror(e));
  }
  committed_ = true;
  // listed in the manifest of its output directory (output_dir.hpp), with its checksum when every
  // byte went through write()
  note_output(path_, raw_ ? std::string() : sum_.hex());
}

void AtomicFile::write(const char* p, std::size_t n) {
  std::fwrite(p, 1, n, f_);
  sum_.update(p, n);
}

void write_text_atomically(const std::string& path, const std::string& text) {
  AtomicFile f(path);
  f.write(text.data(), text.size());
  f.commit();
}

}  // namespace viaduct::io::detail
