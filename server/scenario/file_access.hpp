// Which files a scenario may name (heightfields, friction maps), and where
// they are looked for. The runner reads a file's neighbours; a server reads
// only inside the terrain directory it was given, since its scenarios come
// from remote clients; a scenario parsed from bare text reads no files.
#pragma once

#include <string>

namespace groundsim::scenario {

struct FileAccess {
  enum class Mode {
    None,      // no file may be named (inline data only)
    Local,     // relative paths against dir; absolute paths as they are
    Confined,  // relative paths inside dir only: no absolute path, no "..", no symlink leading out
  };
  Mode mode = Mode::None;
  std::string dir;

  static FileAccess none() { return {}; }
  // The runner: dir is the scenario file's directory.
  static FileAccess local(std::string dir) { return {Mode::Local, std::move(dir)}; }
  // A server: dir is its terrain directory (--terrain-dir).
  static FileAccess confined(std::string dir) { return {Mode::Confined, std::move(dir)}; }
};

}  // namespace groundsim::scenario
