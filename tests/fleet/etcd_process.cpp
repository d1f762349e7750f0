#include "etcd_process.hpp"

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "fleet/etcd_client.hpp"

namespace groundsim::fleet::test {

namespace fs = std::filesystem;

EtcdProcess::EtcdProcess() {
  char tmpl[] = "/tmp/groundsim-etcd-XXXXXX";
  if (mkdtemp(tmpl) == nullptr) throw std::runtime_error("mkdtemp failed");
  dir_ = tmpl;
  // a private namespace: any port is free; vary them anyway (pid)
  client_port_ = 20000 + static_cast<int>(getpid() % 10000) * 2;
  peer_port_ = client_port_ + 1;
  start();
}

EtcdProcess::~EtcdProcess() {
  kill();
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

std::string EtcdProcess::log() const {
  std::ifstream in(dir_ + "/etcd.log");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void EtcdProcess::start() {
  if (pid_ > 0) return;
  const char* bin = std::getenv("GROUNDSIM_ETCD");
  std::string exe = bin && *bin ? bin : "/usr/bin/etcd";
  std::string client = "http://127.0.0.1:" + std::to_string(client_port_);
  std::string peer = "http://127.0.0.1:" + std::to_string(peer_port_);
  std::vector<std::string> args = {exe,
                                   "--name", "solo",
                                   "--data-dir", dir_ + "/data",
                                   "--listen-client-urls", client,
                                   "--advertise-client-urls", client,
                                   "--listen-peer-urls", peer,
                                   "--initial-advertise-peer-urls", peer,
                                   "--initial-cluster", "solo=" + peer,
                                   "--log-level", "warn"};
  // everything the child needs is made before fork(): the test has threads
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string log_path = dir_ + "/etcd.log";
  pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    // dies with the test, even one that crashed or was killed by its timeout
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    int fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
    }
    int null = open("/dev/null", O_RDONLY);
    if (null >= 0) dup2(null, 0);
    execv(argv[0], argv.data());
    _exit(127);
  }
  pid_ = pid;
  EtcdClient probe({endpoint()}, EtcdClient::Options{std::chrono::milliseconds(300)});
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    int status;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      throw std::runtime_error("etcd exited at start:\n" + log());
    }
    try {
      probe.revision();
      return;
    } catch (const EtcdError&) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  kill();
  throw std::runtime_error("etcd did not answer within 20 s:\n" + log());
}

void EtcdProcess::kill() {
  if (pid_ <= 0) return;
  ::kill(pid_, SIGKILL);
  int status;
  waitpid(pid_, &status, 0);
  pid_ = -1;
}

std::string deadEndpoint() { return "http://127.0.0.1:9"; }  // discard: nothing listens in the namespace

}  // namespace groundsim::fleet::test
