// Writes the datagram fuzzer's seed corpus: encoded request_t and drive_t
// messages in the fuzzer's input format (datagram_input.hpp), one file each:
// a list, a create per scenario file given, and sequences that drive the
// harness's session ("@") through every op.
//   datagram_seeds <out dir> <scenario.json>...
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <groundsim/drive_t.hpp>
#include <groundsim/request_t.hpp>

#include "datagram_input.hpp"

namespace {

using groundsim::fuzz::appendDatagram;
using groundsim::fuzz::Channel;

template <class T>
std::vector<std::uint8_t> encode(const T& msg) {
  std::vector<std::uint8_t> buf(msg.getEncodedSize());
  msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
  return buf;
}

groundsim::request_t request(int8_t op, const std::string& session = "@") {
  groundsim::request_t r{};
  r.utime = 1;
  r.seq = 1;
  r.request_id = 7;
  r.client_id = "seed";
  r.session_id = session;
  r.token = session.empty() ? "" : "@";
  r.op = op;
  return r;
}

groundsim::drive_t drive(int nwheels, double torque) {
  groundsim::drive_t d{};
  d.client_id = "seed";
  d.session_id = "@";
  d.token = "@";
  d.vehicle = 0;
  d.nwheels = static_cast<int8_t>(nwheels);
  d.drive_torque.assign(nwheels, torque);
  d.brake_torque.assign(nwheels, 0.0);
  d.steer.assign(nwheels, 0.1);
  return d;
}

bool write(const std::string& dir, const std::string& name, const std::string& input) {
  std::ofstream f(dir + "/" + name, std::ios::binary);
  f << input;
  return static_cast<bool>(f);
}

std::string readFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: datagram_seeds <out dir> <scenario.json>...\n");
    return 2;
  }
  const std::string dir = argv[1];
  using R = groundsim::request_t;
  bool ok = true;
  std::string in;

  in.clear();
  appendDatagram(in, Channel::Request, encode(request(R::OP_LIST, "")));
  ok &= write(dir, "list", in);

  for (int i = 2; i < argc; ++i) {
    R c = request(R::OP_CREATE, "");
    c.scenario_json = readFile(argv[i]);
    c.mode = i % 2 ? R::MODE_LOCKSTEP : R::MODE_REALTIME;
    c.duration = i % 3 ? 0.0 : -1.0;
    c.rate = 2.0;
    c.publish_rate = 25.0;
    in.clear();
    appendDatagram(in, Channel::Request, encode(c));
    ok &= write(dir, "create-" + std::to_string(i - 1), in);
  }

  // the harness's lockstep session through every op
  in.clear();
  R step = request(R::OP_STEP);
  step.steps = 20;
  appendDatagram(in, Channel::Request, encode(step));
  appendDatagram(in, Channel::Drive, encode(drive(4, 5.0)));
  appendDatagram(in, Channel::Request, encode(step));
  appendDatagram(in, Channel::Request, encode(request(R::OP_PAUSE)));
  appendDatagram(in, Channel::Request, encode(request(R::OP_RESUME)));
  appendDatagram(in, Channel::Request, encode(request(R::OP_RESET)));
  R mode = request(R::OP_SET_MODE);
  mode.mode = R::MODE_FAST;
  mode.rate = 4.0;
  mode.publish_rate = 100.0;
  appendDatagram(in, Channel::Request, encode(mode));
  appendDatagram(in, Channel::Request, encode(request(R::OP_STOP)));
  appendDatagram(in, Channel::Request, encode(step));
  ok &= write(dir, "session-ops", in);

  // refusals: a drive with the wrong wheel count, a wrong token, a drive on
  // the request channel (fingerprint), a truncated request
  in.clear();
  appendDatagram(in, Channel::Drive, encode(drive(3, 1.0)));
  groundsim::drive_t wrong = drive(4, 1e9);
  wrong.token = "0123456789abcdef";
  appendDatagram(in, Channel::Drive, encode(wrong));
  appendDatagram(in, Channel::Request, encode(drive(4, 1.0)));
  std::vector<std::uint8_t> cut = encode(request(R::OP_STEP));
  cut.resize(cut.size() / 2);
  appendDatagram(in, Channel::Request, cut);
  ok &= write(dir, "refusals", in);

  if (!ok) std::fprintf(stderr, "datagram_seeds: cannot write to %s\n", dir.c_str());
  return ok ? 0 : 1;
}
