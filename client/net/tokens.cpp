#include "tokens.hpp"

#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

namespace groundsim::cli {
namespace fs = std::filesystem;
namespace {

nlohmann::json readStore(const std::string& path) {
  std::ifstream in(path);
  if (!in) return nlohmann::json::object();
  std::stringstream ss;
  ss << in.rdbuf();
  auto j = nlohmann::json::parse(ss.str(), nullptr, /*allow_exceptions=*/false);
  return j.is_object() ? j : nlohmann::json::object();
}

// Runs fn on the store's contents under an exclusive lock, then writes the result.
void update(const std::string& path, const std::function<void(nlohmann::json&)>& fn) {
  const fs::path p(path);
  if (p.has_parent_path()) {
    fs::create_directories(p.parent_path());
    ::chmod(p.parent_path().c_str(), 0700);
  }
  const std::string lock_path = path + ".lock";
  const int lock = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
  if (lock < 0) throw std::runtime_error("cannot open " + lock_path);
  ::flock(lock, LOCK_EX);
  try {
    nlohmann::json j = readStore(path);
    fn(j);
    const std::string tmp = path + ".tmp." + std::to_string(::getpid());
    {
      const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
      if (fd < 0) throw std::runtime_error("cannot write " + tmp);
      const std::string text = j.dump(2) + "\n";
      const bool ok = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
      ::close(fd);
      if (!ok) throw std::runtime_error("cannot write " + tmp);
    }
    fs::rename(tmp, path);
  } catch (...) {
    ::flock(lock, LOCK_UN);
    ::close(lock);
    throw;
  }
  ::flock(lock, LOCK_UN);
  ::close(lock);
}

}  // namespace

std::string defaultTokenFile() {
  if (const char* x = std::getenv("XDG_STATE_HOME"); x && *x) return std::string(x) + "/groundsim/tokens.json";
  if (const char* h = std::getenv("HOME"); h && *h) return std::string(h) + "/.local/state/groundsim/tokens.json";
  return "groundsim-tokens.json";
}

std::optional<std::string> TokenStore::get(const std::string& session_id) const {
  const nlohmann::json j = readStore(path_);
  auto it = j.find(session_id);
  if (it == j.end() || !it->is_object() || !it->contains("token") || !(*it)["token"].is_string()) return std::nullopt;
  return (*it)["token"].get<std::string>();
}

void TokenStore::put(const std::string& session_id, const std::string& token, const std::string& lcm_url) {
  update(path_, [&](nlohmann::json& j) {
    j[session_id] = {{"token", token}, {"lcm_url", lcm_url}, {"created", static_cast<long long>(std::time(nullptr))}};
  });
}

void TokenStore::erase(const std::string& session_id) {
  update(path_, [&](nlohmann::json& j) { j.erase(session_id); });
}

}  // namespace groundsim::cli
