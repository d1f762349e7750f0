// A directory of this test process's own, removed when the process ends:
// two checkouts on one machine run the same tests at the same time, so a
// fixed /tmp path (or one named by gtest's random seed) is written by both.
// processTempDir() / "name" for each file a test writes.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <random>
#include <string>
#include <system_error>

namespace groundsim::test {

inline const std::filesystem::path& processTempDir() {
  struct Dir {
    std::filesystem::path path;
    Dir() {
      path = std::filesystem::temp_directory_path() /
             ("groundsim-test-" + std::to_string(::getpid()) + "-" + std::to_string(std::random_device{}()));
      std::filesystem::create_directories(path);
    }
    ~Dir() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static const Dir dir;
  return dir.path;
}

}  // namespace groundsim::test
