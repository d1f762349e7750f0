// The protocol in under 100 lines (docs/protocol.md): creates a lockstep
// session from a scenario file (one that names no files), steps it and
// prints the car's speed after every 0.1 s step, then stops it. Built with
// the tree (target minimal_client); alone:
//   g++ -std=c++17 examples/minimal_client.cpp -I build/lcmtypes/include -llcm
#include <fstream>
#include <iostream>
#include <sstream>

#include <lcm/lcm-cpp.hpp>
#include <groundsim/drive_t.hpp>
#include <groundsim/reply_t.hpp>
#include <groundsim/request_t.hpp>

using groundsim::request_t;

struct Client {
  lcm::LCM lcm{"udpm://239.255.76.67:7667?ttl=0"};
  int64_t next_id = 1;
  groundsim::reply_t reply;
  bool got = false;

  Client() { lcm.subscribe("GROUNDSIM_REPLY", &Client::onReply, this); }
  void onReply(const lcm::ReceiveBuffer*, const std::string&, const groundsim::reply_t* r) {
    if (r->client_id == "example" && r->request_id == next_id - 1) reply = *r, got = true;
  }
  // Publishes a request and waits up to 2 s for its reply.
  groundsim::reply_t call(request_t req) {
    req.client_id = "example";
    req.request_id = next_id++;
    got = false;
    lcm.publish("GROUNDSIM_REQUEST", &req);
    for (int i = 0; i < 20 && !got; ++i) lcm.handleTimeout(100);
    if (!got) throw std::runtime_error("no reply: is groundsim-server running?");
    if (!reply.ok) throw std::runtime_error(reply.error);
    return reply;
  }
};

int main(int argc, char** argv) {
  if (argc != 2) return std::cerr << "usage: example SCENARIO.json\n", 2;
  std::stringstream json;
  json << std::ifstream(argv[1]).rdbuf();
  try {
    Client c;
    if (!c.lcm.good()) throw std::runtime_error("LCM: no multicast route?");

    request_t create{};
    create.op = request_t::OP_CREATE;
    create.scenario_json = json.str();
    create.mode = request_t::MODE_LOCKSTEP;
    const groundsim::reply_t created = c.call(create);
    std::cout << "session " << created.session_id << "\n";

    groundsim::drive_t drive{};  // 1 N m on each of the 4 wheels, held
    drive.client_id = "example";
    drive.session_id = created.session_id;
    drive.token = created.token;
    drive.nwheels = 4;
    drive.drive_torque.assign(4, 1.0);
    drive.brake_torque.assign(4, 0.0);
    drive.steer.assign(4, 0.0);
    c.lcm.publish("GROUNDSIM_DRIVE", &drive);

    request_t step{};
    step.op = request_t::OP_STEP;
    step.session_id = created.session_id;
    step.token = created.token;
    step.steps = 2000;  // 0.1 s at dt = 5e-5
    for (int i = 0; i < 10; ++i) {
      const groundsim::state_t& s = c.call(step).states.at(0);
      std::cout << "t=" << s.t << " s  speed=" << s.vehicles.at(0).speed << " m/s\n";
    }

    request_t stop{};
    stop.op = request_t::OP_STOP;
    stop.session_id = created.session_id;
    stop.token = created.token;
    c.call(stop);
  } catch (const std::exception& e) {
    std::cerr << "example: " << e.what() << "\n";
    return 1;
  }
}
