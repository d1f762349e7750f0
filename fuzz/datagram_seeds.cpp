// Writes the datagram fuzzer's seed corpus: encoded request_t and drive_t
// messages in the target's input format (datagram_input.hpp), one datagram
// per file, each twice: whole ("-full", fingerprint included) and as a body
// the target prefixes with the fingerprint ("-body"; mutations of it reach
// the decoder). The seeds: a list, a create per scenario file given (every
// mode), every session op and drives on an unknown session (ids and tokens
// are random, so a fuzzer's session ops are refusals), and refusals (wrong
// wheel count, non-finite torque, a drive on the request channel, a
// truncated request).
//   datagram_seeds <out dir> <scenario.json>...
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <groundsim/asset_part_t.hpp>
#include <groundsim/drive_t.hpp>
#include <groundsim/request_t.hpp>

#include "datagram_input.hpp"

namespace {

using groundsim::fuzz::makeInput;

template <class T>
std::vector<std::uint8_t> encode(const T& msg) {
  std::vector<std::uint8_t> buf(msg.getEncodedSize());
  msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
  return buf;
}

groundsim::request_t request(int8_t op, const std::string& session = "s0123456789") {
  groundsim::request_t r{};
  r.utime = 1;
  r.seq = 1;
  r.request_id = 7;
  r.client_id = "seed";
  r.session_id = session;
  r.token = session.empty() ? "" : "0123456789abcdef";
  r.op = op;
  return r;
}

groundsim::drive_t drive(int nwheels, double torque) {
  groundsim::drive_t d{};
  d.client_id = "seed";
  d.session_id = "s0123456789";
  d.token = "0123456789abcdef";
  d.vehicle = 0;
  d.nwheels = static_cast<int8_t>(nwheels);
  d.drive_torque.assign(nwheels, torque);
  d.brake_torque.assign(nwheels, 0.0);
  d.steer.assign(nwheels, 0.1);
  return d;
}

bool writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary);
  f << bytes;
  return static_cast<bool>(f);
}

// one datagram, as both input forms
bool write(const std::string& dir, const std::string& name, bool drive, const std::vector<std::uint8_t>& encoded) {
  return writeFile(dir + "/" + name + "-full", makeInput(drive, false, encoded)) &&
         writeFile(dir + "/" + name + "-body", makeInput(drive, true, encoded));
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

  ok &= write(dir, "list", false, encode(request(R::OP_LIST, "")));

  const int8_t modes[] = {R::MODE_LOCKSTEP, R::MODE_REALTIME, R::MODE_FAST};
  for (int i = 2; i < argc; ++i) {
    R c = request(R::OP_CREATE, "");
    c.scenario_json = readFile(argv[i]);
    c.mode = modes[i % 3];
    c.duration = i % 4 ? 0.0 : -1.0;
    c.rate = 2.0;
    c.publish_rate = 25.0;
    ok &= write(dir, "create-" + std::to_string(i - 1), false, encode(c));
  }

  // every session op (on a session the fuzzer cannot know: refusals)
  R step = request(R::OP_STEP);
  step.steps = 20;
  ok &= write(dir, "step", false, encode(step));
  ok &= write(dir, "stop", false, encode(request(R::OP_STOP)));
  ok &= write(dir, "reset", false, encode(request(R::OP_RESET)));
  ok &= write(dir, "pause", false, encode(request(R::OP_PAUSE)));
  ok &= write(dir, "resume", false, encode(request(R::OP_RESUME)));
  R mode = request(R::OP_SET_MODE);
  mode.mode = R::MODE_FAST;
  mode.rate = 4.0;
  mode.publish_rate = 100.0;
  ok &= write(dir, "set-mode", false, encode(mode));
  ok &= write(dir, "drive", true, encode(drive(4, 5.0)));
  // one file part (asset_part_t on GROUNDSIM_ASSET), whole and as a body
  {
    groundsim::asset_part_t a{};
    a.client_id = "fuzz";
    a.name = "terrain/hills.png";
    a.sha256 = std::string(64, 'a');
    a.data.assign(64, 7);
    a.nbytes = 64;
    a.size = 64;
    a.part = 0;
    a.nparts = 1;
    const std::vector<std::uint8_t> e = encode(a);
    for (bool body : {false, true}) {
      std::string in = makeInput(false, body, e);
      in[0] = static_cast<char>(in[0] | groundsim::fuzz::kAssetBit);
      ok &= writeFile(dir + "/asset-part" + (body ? "-body" : "-full"), in);
    }
  }

  // refusals: a drive with the wrong wheel count, a non-finite torque, a
  // drive on the request channel (wrong fingerprint), a truncated request
  ok &= write(dir, "drive-3-wheels", true, encode(drive(3, 1.0)));
  ok &= write(dir, "drive-nan", true, encode(drive(4, std::numeric_limits<double>::quiet_NaN())));
  ok &= write(dir, "drive-on-request", false, encode(drive(4, 1.0)));
  std::vector<std::uint8_t> cut = encode(step);
  cut.resize(cut.size() / 2);
  ok &= write(dir, "step-truncated", false, cut);

  if (!ok) std::fprintf(stderr, "datagram_seeds: cannot write to %s\n", dir.c_str());
  return ok ? 0 : 1;
}
