// Where `groundsim create` keeps session tokens so that later commands find
// them: a JSON object keyed by session id, by default
// $XDG_STATE_HOME/groundsim/tokens.json (~/.local/state/groundsim/tokens.json),
// readable by its owner only. Updates are locked (flock on a sidecar file)
// and atomic (write then rename), so parallel creates do not lose entries.
#pragma once

#include <optional>
#include <string>

namespace groundsim::cli {

std::string defaultTokenFile();

class TokenStore {
 public:
  explicit TokenStore(std::string path) : path_(path.empty() ? defaultTokenFile() : std::move(path)) {}
  const std::string& path() const { return path_; }

  std::optional<std::string> get(const std::string& session_id) const;
  void put(const std::string& session_id, const std::string& token, const std::string& lcm_url);
  void erase(const std::string& session_id);

 private:
  std::string path_;
};

}  // namespace groundsim::cli
