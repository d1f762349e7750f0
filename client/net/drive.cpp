// `groundsim drive SESSION`: drive one vehicle. On a terminal the keyboard
// drives (w/s or up/down: throttle, a/d or left/right: turn, i.e. torque
// split between the left and right wheels plus front steering; space: brake;
// x: release everything; q: quit). Without a terminal, commands are read
// from stdin lines so drives can be scripted and tested:
//   throttle T | brake B | turn X | wheels D0 D1 D2 D3 [B0..B3 [S0..S3]] | release | wait S | quit
// The command in force is re-sent at --hz so that the server's command
// timeout only fires when this client goes away.
// A road car (kind "road_car") takes normalized controls instead (controls_t,
// keys and script lines in car_drive.hpp) and shows speed in km/h, gear and
// rpm from car_state_t. --controls auto tells the two apart from the
// session's first states (a road car's come with a car_state_t); a session
// that publishes nothing (lockstep, paused) needs --controls car.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <poll.h>
#include <unistd.h>

#include "physics/build/vehicle.hpp"
#include "protocol/channels.hpp"
#include "protocol/codec.hpp"
#include "protocol/names.hpp"
#include "protocol/text.hpp"
#include <groundsim/car_state_t.hpp>

#include "car_drive.hpp"
#include "common.hpp"
#include "terminal.hpp"

namespace groundsim::cli {
namespace {

using SteadyClock = std::chrono::steady_clock;

struct DriveOpts {
  NetOptions net;
  std::string session;
  int vehicle = 0;
  int wheels = 4;
  double torque_step = 0.5;   // N m per key press
  double max_torque = 5.0;    // N m the keyboard reaches
  double brake = 5.0;         // N m of the brake key
  double max_steer = kFullLockRad;  // rad at full turn
  double hz = 20.0;
  bool hold = false;
  std::string controls = "auto";  // auto | car | wheels
};

// The driver's intent, turned into per-wheel controls. Wheels are in the
// vehicle's telemetry order (front-left, front-right, rear-left, rear-right):
// even indices are on the left.
struct Intent {
  double throttle = 0.0;  // N m, mean drive torque per wheel
  double turn = 0.0;      // [-1, 1], positive turns left
  double brake = 0.0;     // N m per wheel
  bool raw = false;       // explicit per-wheel values below
  std::vector<double> drive, brakes, steer;

  groundsim::drive_t toMessage(const DriveOpts& o) const {
    groundsim::drive_t m{};
    m.session_id = o.session;
    m.vehicle = o.vehicle;
    m.nwheels = static_cast<int8_t>(o.wheels);
    m.drive_torque.assign(o.wheels, 0.0);
    m.brake_torque.assign(o.wheels, 0.0);
    m.steer.assign(o.wheels, 0.0);
    for (int k = 0; k < o.wheels; ++k) {
      if (raw) {
        m.drive_torque[k] = k < static_cast<int>(drive.size()) ? drive[k] : 0.0;
        m.brake_torque[k] = k < static_cast<int>(brakes.size()) ? brakes[k] : 0.0;
        m.steer[k] = k < static_cast<int>(steer.size()) ? steer[k] : 0.0;
        continue;
      }
      const bool left = k % 2 == 0;
      m.drive_torque[k] = throttle * (left ? 1.0 - turn : 1.0 + turn);
      m.brake_torque[k] = brake;
      m.steer[k] = k < 2 ? turn * o.max_steer : 0.0;  // the server clamps to each wheel's lock
    }
    return m;
  }
};

std::vector<double> numbers(std::istringstream& in) {
  std::vector<double> v;
  std::string tok;
  while (in >> tok) {
    char* end = nullptr;
    const double x = std::strtod(tok.c_str(), &end);  // accepts nan and inf: the server judges them
    if (end == tok.c_str() || *end) throw std::invalid_argument("not a number: " + net::quoted(tok));
    v.push_back(x);
  }
  return v;
}

// Applies one script line; returns seconds to wait (0 for none), or < 0 to quit.
double applyLine(const std::string& line, Intent& in) {
  std::istringstream ss(line);
  std::string word;
  if (!(ss >> word) || word[0] == '#') return 0.0;
  const std::vector<double> v = numbers(ss);
  auto one = [&]() {
    if (v.size() != 1) throw std::invalid_argument(word + " takes one number");
    return v[0];
  };
  if (word == "throttle" || word == "torque") in.throttle = one(), in.raw = false;
  else if (word == "brake") in.brake = one(), in.raw = false;
  else if (word == "turn") in.turn = one(), in.raw = false;
  else if (word == "release") in = Intent{};
  else if (word == "wheels") {
    if (v.size() != 4 && v.size() != 8 && v.size() != 12)
      throw std::invalid_argument("wheels takes 4 drive torques, then optionally 4 brakes and 4 steering angles");
    in.raw = true;
    in.drive.assign(v.begin(), v.begin() + 4);
    in.brakes.assign(v.size() >= 8 ? v.begin() + 4 : v.end(), v.size() >= 8 ? v.begin() + 8 : v.end());
    in.steer.assign(v.size() >= 12 ? v.begin() + 8 : v.end(), v.end());
  } else if (word == "wait") return std::max(0.0, one());
  else if (word == "quit") return -1.0;
  else throw std::invalid_argument("unknown command " + net::quoted(word));
  return 0.0;
}

// Keyboard: returns false to quit.
bool applyKey(const KeyPress& k, Intent& in, const DriveOpts& o) {
  const char c = k.key == Key::Char ? static_cast<char>(std::tolower(static_cast<unsigned char>(k.ch))) : 0;
  if (k.key == Key::Up || c == 'w') in.throttle = std::min(o.max_torque, in.throttle + o.torque_step);
  else if (k.key == Key::Down || c == 's') in.throttle = std::max(-o.max_torque, in.throttle - o.torque_step);
  else if (k.key == Key::Left || c == 'a') in.turn = std::min(1.0, in.turn + 0.1);
  else if (k.key == Key::Right || c == 'd') in.turn = std::max(-1.0, in.turn - 0.1);
  else if (c == ' ') in.brake = in.brake > 0 ? 0.0 : o.brake, in.throttle = 0.0;
  else if (c == 'x') in = Intent{};
  else if (c == 'q' || c == 3 || c == 4) return false;
  in.raw = false;
  return true;
}

void run(const DriveOpts& o) {
  installStopSignals();
  NetClient client(o.net.url);
  const std::string token = tokenFor(o.net, o.session);
  if (token.empty())
    std::fprintf(stderr, "groundsim: warning: no token for session %s (the server will refuse)\n",
                 net::printable(o.session).c_str());
  const bool tty = ::isatty(STDIN_FILENO);
  std::optional<RawTerminal> term;
  if (tty) term.emplace(STDIN_FILENO);

  groundsim::state_t latest;
  bool have_state = false;
  auto on_state = [&](const lcm::ReceiveBuffer* rbuf, const std::string&) {
    if (net::decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), latest, "groundsim.state_t").ok())
      have_state = true;
  };
  client.lcm().subscribeFunction(
      net::stateChannel(o.session),
      +[](const lcm::ReceiveBuffer* rbuf, const std::string& ch, decltype(on_state)* h) { (*h)(rbuf, ch); }, &on_state);

  groundsim::car_state_t latest_car;
  bool have_car = false;
  auto on_car = [&](const lcm::ReceiveBuffer* rbuf, const std::string&) {
    if (net::decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), latest_car, "groundsim.car_state_t").ok())
      have_car = true;
  };
  client.lcm().subscribeFunction(
      net::carStateChannel(o.session),
      +[](const lcm::ReceiveBuffer* rbuf, const std::string& ch, decltype(on_car)* h) { (*h)(rbuf, ch); }, &on_car);
  auto carOf = [&]() -> const groundsim::road_car_state_t* {
    for (const auto& c : latest_car.cars)
      if (c.vehicle == o.vehicle) return &c;
    return nullptr;
  };

  bool car = o.controls == "car";
  if (o.controls == "auto") {
    // a road car's state_t comes with a car_state_t of the same seq
    const auto give_up = SteadyClock::now() + std::chrono::seconds(2);
    while (!have_state && SteadyClock::now() < give_up && !stopRequested()) client.pump(50);
    for (const auto settle = SteadyClock::now() + std::chrono::milliseconds(200);
         have_state && !have_car && SteadyClock::now() < settle;)
      client.pump(20);
    car = have_car && carOf() != nullptr;
    if (!have_state)
      std::fprintf(stderr, "drive %s: no state within 2 s (lockstep or paused?): per-wheel torques; "
                           "use --controls car for a road car\n", net::printable(o.session).c_str());
  }
  if (!car && tty)
    std::fprintf(stderr, "drive %s: w/s or up/down throttle, a/d or left/right turn, space brake, x release, q quit\n",
                 net::printable(o.session).c_str());
  if (car && tty)
    std::fprintf(stderr, "drive %s: road car: w/s or up/down throttle/brake, a/d or left/right steer (held while "
                         "pressed, back to 0 when released), space full brake, h handbrake, 0 auto, 1-9 gear, "
                         "r reverse, n neutral, x release, q quit\n", net::printable(o.session).c_str());

  std::fprintf(stderr, "drive %s: sending %s on %s\n", net::printable(o.session).c_str(),
               car ? "controls_t" : "drive_t", client.url().c_str());
  Intent intent;
  CarIntent car_intent;
  auto last_tick = SteadyClock::now();
  auto sendNow = [&](bool release) {
    if (car) {
      groundsim::controls_t m = (release ? CarIntent{} : car_intent).toMessage(o.session, o.vehicle);
      m.token = token;
      client.send(m);
    } else {
      groundsim::drive_t m = (release ? Intent{} : intent).toMessage(o);
      m.token = token;
      client.send(m);
    }
  };
  int refusals = 0;
  const auto period = std::chrono::duration_cast<SteadyClock::duration>(std::chrono::duration<double>(1.0 / o.hz));
  auto next_send = SteadyClock::now();
  auto wait_until = SteadyClock::time_point{};
  bool input_open = true, quit = false, dirty = true;
  std::string pending;  // partial script line
  long line_no = 0;

  while (!quit && !stopRequested()) {
    // commands into the void help nobody: a silent server ends the drive
    if (client.server().lost()) fail(kExitNoServer, client.server().lostMessage(client.url()));
    if (const auto info = client.server().session(o.session); info && net::isFinal(info->status) && !have_state) {
      std::fprintf(stderr, "drive %s: session %s (from the server's heartbeat)\n", net::printable(o.session).c_str(),
                   net::statusName(info->status));
      break;
    }
    // script lines run in order; a wait holds back the ones after it
    while (!tty && !quit && SteadyClock::now() >= wait_until) {
      auto nl = pending.find('\n');
      if (nl == std::string::npos) {
        if (input_open || pending.empty()) break;
        pending += '\n';  // last line without a newline
        continue;
      }
      const std::string line = pending.substr(0, nl);
      pending.erase(0, nl + 1);
      ++line_no;
      double wait = 0.0;
      try {
        wait = car ? applyCarLine(line, car_intent) : applyLine(line, intent);
      } catch (const std::invalid_argument& e) {
        fail(kExitRefused, "stdin line " + std::to_string(line_no) + ": " + e.what());
      }
      dirty = true;
      if (wait < 0) quit = true;
      if (wait > 0) wait_until = SteadyClock::now() + std::chrono::duration_cast<SteadyClock::duration>(std::chrono::duration<double>(wait));
    }
    const auto now = SteadyClock::now();
    car_intent.tick(std::chrono::duration<double>(now - last_tick).count());
    last_tick = now;
    if (dirty || now >= next_send) {
      sendNow(false);
      next_send = now + period;
      dirty = false;
    }
    if (quit) break;
    for (const auto& e : client.takeEvents()) {
      ++refusals;
      std::fprintf(stderr, "%sgroundsim: refused: %s\n", tty ? "\r\033[K" : "", net::printable(e.reason, 1000).c_str());
    }
    if (tty && have_state && car) {
      const auto* c = carOf();
      std::fprintf(stderr, "\r\033[K%s | t=%.2f s %5.1f km/h gear %s %5.0f rpm %s", car_intent.describe().c_str(),
                   latest.t, c ? c->speed * 3.6 : 0.0, c ? gearName(c->gear).c_str() : "-", c ? c->engine_rpm : 0.0,
                   net::statusName(latest.status));
    } else if (tty && have_state) {
      const double speed = latest.vehicles.size() > static_cast<size_t>(o.vehicle) ? latest.vehicles[o.vehicle].speed : 0.0;
      std::fprintf(stderr, "\r\033[Kthrottle %5.2f N m  turn %+4.1f  brake %4.1f | t=%.2f s speed %.2f m/s %s",
                   intent.throttle, intent.turn, intent.brake, latest.t, speed, net::statusName(latest.status));
    }
    if (have_state && net::isFinal(latest.status)) {
      std::fprintf(stderr, "%sdrive %s: session %s\n", tty ? "\n" : "", net::printable(o.session).c_str(), net::statusName(latest.status));
      break;
    }
    if (!input_open && pending.empty() && now >= wait_until) break;  // script done

    pollfd fds[2] = {{client.lcm().getFileno(), POLLIN, 0}, {STDIN_FILENO, POLLIN, 0}};
    auto until = next_send;
    if (wait_until > now) until = std::min(until, wait_until);
    const int ms = static_cast<int>(std::max<long long>(
        0, std::chrono::duration_cast<std::chrono::milliseconds>(until - SteadyClock::now()).count()));
    if (::poll(fds, input_open ? 2 : 1, ms) < 0) continue;  // EINTR: the loop checks the stop flag
    if (fds[0].revents & POLLIN) client.lcm().handleTimeout(0);
    if (!input_open || !(fds[1].revents & (POLLIN | POLLHUP))) continue;

    char buf[4096];
    const ssize_t n = ::read(STDIN_FILENO, buf, sizeof buf);
    if (n <= 0) {
      input_open = false;
      continue;
    }
    if (!tty) {
      pending.append(buf, static_cast<size_t>(n));
      continue;
    }
    const std::string bytes(buf, static_cast<size_t>(n));
    for (std::string::size_type i = 0; i < bytes.size();) {
      KeyPress k;
      i = nextKey(bytes, i, &k);
      if (!(car ? applyCarKey(k, car_intent) : applyKey(k, intent, o))) quit = true;
    }
    dirty = true;
  }
  if (!o.hold) sendNow(true);
  // Collect a last refusal, if any. The server handles datagrams in the
  // order they come, on one thread, and publishes a command's refusal as it
  // handles it, so once a request sent after the last command is answered
  // every refusal of ours is in (a fixed 150 ms lost them on a busy machine).
  {
    groundsim::request_t barrier{};
    barrier.op = groundsim::request_t::OP_LIST;
    try {
      client.call(barrier, o.net.timeout);
    } catch (const NetError&) {
      // no answer in time: the refusals that came are counted all the same
    }
  }
  if (car && have_car) {
    if (const auto* c = carOf())
      std::fprintf(stderr, "%sdrive %s: t=%.2f s speed %.1f km/h gear %s %.0f rpm\n", tty ? "\n" : "",
                   net::printable(o.session).c_str(), latest_car.t, c->speed * 3.6, gearName(c->gear).c_str(),
                   c->engine_rpm);
  }
  for (const auto& e : client.takeEvents()) {
    ++refusals;
    std::fprintf(stderr, "groundsim: refused: %s\n", net::printable(e.reason, 1000).c_str());
  }
  if (tty) std::fprintf(stderr, "\n");
  if (refusals > 0) fail(kExitRefused, std::to_string(refusals) + " drive command(s) refused");
}

}  // namespace

void registerDriveCommand(CLI::App& app) {
  auto o = std::make_shared<DriveOpts>();
  auto* cmd = app.add_subcommand("drive", "drive a vehicle of a session (keyboard, or stdin lines without a terminal)");
  cmd->add_option("SESSION", o->session, "session id")->required();
  cmd->add_option("--vehicle", o->vehicle, "vehicle index in the scenario")->capture_default_str();
  cmd->add_option("--wheels", o->wheels, "wheels of that vehicle")->capture_default_str()->check(CLI::Range(1, 16));
  cmd->add_option("--torque-step", o->torque_step, "N m per throttle key press")->capture_default_str();
  cmd->add_option("--max-torque", o->max_torque, "N m the throttle keys reach")->capture_default_str();
  cmd->add_option("--brake", o->brake, "N m of the brake key")->capture_default_str();
  cmd->add_option("--max-steer", o->max_steer, "rad of steering at full turn")->capture_default_str();
  cmd->add_option("--hz", o->hz, "commands per second")->capture_default_str()->check(CLI::Range(1.0, 1000.0));
  cmd->add_option("--controls", o->controls, "auto: normalized controls (controls_t) for a road car, per-wheel "
                                             "torques (drive_t) otherwise; car; wheels")
      ->capture_default_str()->check(CLI::IsMember({"auto", "car", "wheels"}));
  cmd->add_flag("--hold", o->hold, "leave the last command in force on exit (default: release)");
  addNetOptions(cmd, o->net, true);
  cmd->callback([o] { guarded([&] { run(*o); }); });
}

}  // namespace groundsim::cli
