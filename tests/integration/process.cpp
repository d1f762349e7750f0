#include "process.hpp"

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace groundsim::itest {
namespace {

std::string tempPath(const char* what) {
  static int counter = 0;
  const char* dir = std::getenv("TMPDIR");
  return std::string(dir && *dir ? dir : "/tmp") + "/gs-itest-" + std::to_string(getpid()) + "-" +
         std::to_string(counter++) + "." + what;
}

}  // namespace

std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Process::Process(const std::vector<std::string>& argv, const std::string& stdin_text)
    : out_path_(tempPath("out")), err_path_(tempPath("err")), in_path_(tempPath("in")) {
  std::ofstream(in_path_) << stdin_text;
  pid_ = fork();
  if (pid_ < 0) throw std::runtime_error("fork failed");
  if (pid_ == 0) {
    const int in = open(in_path_.c_str(), O_RDONLY);
    const int out = open(out_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    const int err = open(err_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    dup2(in, 0);
    dup2(out, 1);
    dup2(err, 2);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
}

Process::~Process() {
  if (!done_) {
    signal(SIGKILL);
    wait(5.0);
  }
  unlink(out_path_.c_str());
  unlink(err_path_.c_str());
  unlink(in_path_.c_str());
}

void Process::signal(int sig) {
  if (!done_ && pid_ > 0) kill(pid_, sig);
}

std::string Process::out() const { return readText(out_path_); }

bool Process::waitForOutput(const std::string& text, double timeout_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < end) {
    if (out().find(text) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

bool Process::waitForError(const std::string& text, double timeout_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < end) {
    if (readText(err_path_).find(text) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

Result Process::wait(double timeout_s) {
  if (done_) return result_;
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  int st = 0;
  for (;;) {
    const pid_t r = waitpid(pid_, &st, WNOHANG);
    if (r == pid_) break;
    if (std::chrono::steady_clock::now() > end) {
      kill(pid_, SIGKILL);
      waitpid(pid_, &st, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  done_ = true;
  result_.status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
  result_.out = readText(out_path_);
  result_.err = readText(err_path_);
  return result_;
}

Result run(const std::vector<std::string>& argv, const std::string& stdin_text, double timeout_s) {
  Process p(argv, stdin_text);
  return p.wait(timeout_s);
}

}  // namespace groundsim::itest
