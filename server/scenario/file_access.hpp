// Which files a scenario may name (heightfields, friction maps), and where
// they are looked for. The runner reads a file's neighbours; a server reads
// the assets a client sent with the scenario (content-addressed, checked by
// hash before they get here) and, for server-side libraries, files inside
// the terrain directory it was given, since its scenarios come from remote
// clients; a scenario parsed from bare text reads no files.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace groundsim::scenario {

// The bytes of a scenario's files, by the name the scenario gives them.
using AssetBytes = std::map<std::string, std::shared_ptr<const std::string>>;

struct FileAccess {
  enum class Mode {
    None,      // no file may be named (inline data only)
    Local,     // relative paths against dir; absolute paths as they are
    Confined,  // relative paths inside dir only: no absolute path, no "..", no symlink leading out
    Assets,    // the bytes in `assets` by name (a file not there: dir as Confined, when dir is set)
    Collect,   // nothing is read: each name is appended to `collected` (a client finding what to send)
  };
  Mode mode = Mode::None;
  std::string dir;
  std::shared_ptr<const AssetBytes> assets;
  std::shared_ptr<std::vector<std::string>> collected;

  static FileAccess none() { return {}; }
  // The runner: dir is the scenario file's directory.
  static FileAccess local(std::string dir) { return {Mode::Local, std::move(dir), nullptr, nullptr}; }
  // A server: dir is its terrain directory (--terrain-dir).
  static FileAccess confined(std::string dir) { return {Mode::Confined, std::move(dir), nullptr, nullptr}; }
  // A server: the assets sent with the create; terrain_dir ("": none) for names not among them.
  static FileAccess fromAssets(std::shared_ptr<const AssetBytes> assets, std::string terrain_dir = "") {
    return {Mode::Assets, std::move(terrain_dir), std::move(assets), nullptr};
  }
  static FileAccess collect() {
    return {Mode::Collect, "", nullptr, std::make_shared<std::vector<std::string>>()};
  }
};

}  // namespace groundsim::scenario
