// Child processes for the integration tests: the real groundsim-server and
// groundsim clients, with their output captured to files.
#pragma once

#include <string>
#include <vector>

#include <sys/types.h>

namespace groundsim::itest {

struct Result {
  int status = -1;  // exit code, or 128 + signal
  std::string out, err;
};

class Process {
 public:
  // Starts argv with stdin from stdin_text (empty: /dev/null).
  Process(const std::vector<std::string>& argv, const std::string& stdin_text = "");
  ~Process();  // kills a child still running
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;

  void signal(int sig);
  // Waits up to timeout_s; kills the child after it (status then 128 + 9).
  Result wait(double timeout_s);
  // Waits until the captured stdout contains text; false on timeout.
  bool waitForOutput(const std::string& text, double timeout_s);
  // The same for stderr (the clients' ready lines: "log: recording", "watch ...: subscribed").
  bool waitForError(const std::string& text, double timeout_s);
  std::string out() const;

 private:
  pid_t pid_ = -1;
  std::string out_path_, err_path_, in_path_;
  bool done_ = false;
  Result result_;
};

// Runs to completion.
Result run(const std::vector<std::string>& argv, const std::string& stdin_text = "", double timeout_s = 60.0);

std::string readText(const std::string& path);

}  // namespace groundsim::itest
