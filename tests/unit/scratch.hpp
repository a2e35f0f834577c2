#pragma once
// A scratch directory for tests that write files; removed with the object.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace vt {

struct ScratchDir {
  std::filesystem::path p;
  explicit ScratchDir(const std::string& tag) {
    static int counter = 0;
    p = std::filesystem::temp_directory_path() /
        ("viaduct-" + tag + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    std::filesystem::create_directories(p);
  }
  ~ScratchDir() { std::filesystem::remove_all(p); }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  /// Writes `text` to `name` inside the directory and returns the full path.
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(p / name) << text;
    return (p / name).string();
  }
};

}  // namespace vt
