// A real etcd for the fleet tests: one member on 127.0.0.1 of the test's own
// network namespace (etcd_lab.sh made it), data in a temporary directory,
// ports from the process id. kill() is SIGKILL; start() (again) reuses the
// data, like a member that comes back.
#pragma once

#include <string>

#include <sys/types.h>

namespace groundsim::fleet::test {

class EtcdProcess {
 public:
  // Starts it and waits until it answers (throws after 20 s, with its log).
  EtcdProcess();
  ~EtcdProcess();  // kills it and removes its data
  EtcdProcess(const EtcdProcess&) = delete;
  EtcdProcess& operator=(const EtcdProcess&) = delete;

  std::string endpoint() const { return "http://127.0.0.1:" + std::to_string(client_port_); }
  void start();
  void kill();  // SIGKILL, and waits for it
  bool running() const { return pid_ > 0; }
  std::string log() const;

 private:
  std::string dir_;
  int client_port_ = 0, peer_port_ = 0;
  pid_t pid_ = -1;
};

// The ports nobody listens on in the test's namespace (connections refused).
std::string deadEndpoint();

}  // namespace groundsim::fleet::test
