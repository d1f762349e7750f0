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

// What the server publishes of the session: its newest state and, for a
// road car, its newest car state.
struct Telemetry {
  groundsim::state_t state;
  bool have_state = false;
  groundsim::car_state_t car_state;
  bool have_car = false;
  int vehicle = 0;

  void onState(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    if (net::decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), state, "groundsim.state_t").ok())
      have_state = true;
  }
  void onCar(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    if (net::decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), car_state, "groundsim.car_state_t").ok())
      have_car = true;
  }
  const groundsim::road_car_state_t* car() const {
    for (const auto& c : car_state.cars)
      if (c.vehicle == vehicle) return &c;
    return nullptr;
  }
};

// How the driver's input becomes commands: per-wheel torques (drive_t) or a
// road car's normalized controls (controls_t).
class ControlModel {
 public:
  virtual ~ControlModel() = default;
  virtual const char* message() const = 0;  // what it sends
  virtual const char* keys() const = 0;      // the keyboard's help
  // one script line: seconds to wait (0 none), < 0 to quit; throws invalid_argument
  virtual double applyLine(const std::string& line) = 0;
  virtual bool applyKey(const KeyPress& k) = 0;  // false: quit
  virtual void tick(double /*dt*/) {}
  virtual void send(NetClient& client, const std::string& token, bool release) const = 0;
  virtual std::string status(const Telemetry& t) const = 0;  // the terminal's line
  virtual void summary(const Telemetry& /*t*/, const std::string& /*session*/, bool /*tty*/) const {}
};

class WheelTorques final : public ControlModel {
 public:
  explicit WheelTorques(const DriveOpts& o) : o_(o) {}
  const char* message() const override { return "drive_t"; }
  const char* keys() const override {
    return "w/s or up/down throttle, a/d or left/right turn, space brake, x release, q quit";
  }
  double applyLine(const std::string& line) override { return cli::applyLine(line, intent_); }
  bool applyKey(const KeyPress& k) override { return cli::applyKey(k, intent_, o_); }
  void send(NetClient& client, const std::string& token, bool release) const override {
    groundsim::drive_t m = (release ? Intent{} : intent_).toMessage(o_);
    m.token = token;
    client.send(m);
  }
  std::string status(const Telemetry& t) const override {
    const auto v = static_cast<size_t>(o_.vehicle);
    const double speed = t.state.vehicles.size() > v ? t.state.vehicles[v].speed : 0.0;
    char buf[200];
    std::snprintf(buf, sizeof buf, "throttle %5.2f N m  turn %+4.1f  brake %4.1f | t=%.2f s speed %.2f m/s %s",
                  intent_.throttle, intent_.turn, intent_.brake, t.state.t, speed, net::statusName(t.state.status));
    return buf;
  }

 private:
  const DriveOpts& o_;
  Intent intent_;
};

class RoadCarControls final : public ControlModel {
 public:
  explicit RoadCarControls(const DriveOpts& o) : o_(o) {}
  const char* message() const override { return "controls_t"; }
  const char* keys() const override {
    return "road car: w/s or up/down throttle/brake, a/d or left/right steer (held while pressed, back to 0 when "
           "released), space full brake, h handbrake, 0 auto, 1-9 gear, r reverse, n neutral, x release, q quit";
  }
  double applyLine(const std::string& line) override { return applyCarLine(line, intent_); }
  bool applyKey(const KeyPress& k) override { return applyCarKey(k, intent_); }
  void tick(double dt) override { intent_.tick(dt); }
  void send(NetClient& client, const std::string& token, bool release) const override {
    groundsim::controls_t m = (release ? CarIntent{} : intent_).toMessage(o_.session, o_.vehicle);
    m.token = token;
    client.send(m);
  }
  std::string status(const Telemetry& t) const override {
    const auto* c = t.car();
    char buf[300];
    std::snprintf(buf, sizeof buf, "%s | t=%.2f s %5.1f km/h gear %s %5.0f rpm %s", intent_.describe().c_str(),
                  t.state.t, c ? c->speed * 3.6 : 0.0, c ? gearName(c->gear).c_str() : "-", c ? c->engine_rpm : 0.0,
                  net::statusName(t.state.status));
    return buf;
  }
  void summary(const Telemetry& t, const std::string& session, bool tty) const override {
    const auto* c = t.have_car ? t.car() : nullptr;
    if (!c) return;
    std::fprintf(stderr, "%sdrive %s: t=%.2f s speed %.1f km/h gear %s %.0f rpm\n", tty ? "\n" : "",
                 net::printable(session).c_str(), t.car_state.t, c->speed * 3.6, gearName(c->gear).c_str(),
                 c->engine_rpm);
  }

 private:
  const DriveOpts& o_;
  CarIntent intent_;
};

// --controls, or with auto what the session's first states say: a road
// car's state_t comes with a car_state_t of the same seq
std::unique_ptr<ControlModel> chooseControlModel(const DriveOpts& o, NetClient& client, const Telemetry& t) {
  bool car = o.controls == "car";
  if (o.controls == "auto") {
    const auto give_up = SteadyClock::now() + std::chrono::seconds(2);
    while (!t.have_state && SteadyClock::now() < give_up && !stopRequested()) client.pump(50);
    for (const auto settle = SteadyClock::now() + std::chrono::milliseconds(200);
         t.have_state && !t.have_car && SteadyClock::now() < settle;)
      client.pump(20);
    car = t.have_car && t.car() != nullptr;
    if (!t.have_state)
      std::fprintf(stderr, "drive %s: no state within 2 s (lockstep or paused?): per-wheel torques; "
                           "use --controls car for a road car\n", net::printable(o.session).c_str());
  }
  if (car) return std::make_unique<RoadCarControls>(o);
  return std::make_unique<WheelTorques>(o);
}

// The drive: input (keys, or script lines and their waits) into the
// control model, its command re-sent at --hz, the server's refusals and
// the session's end watched.
class Drive {
 public:
  Drive(const DriveOpts& o, NetClient& client, const Telemetry& t, ControlModel& model, std::string token)
      : o_(o), client_(client), t_(t), model_(model), token_(std::move(token)), tty_(::isatty(STDIN_FILENO)) {}

  void run() {
    if (tty_) std::fprintf(stderr, "drive %s: %s\n", net::printable(o_.session).c_str(), model_.keys());
    std::fprintf(stderr, "drive %s: sending %s on %s\n", net::printable(o_.session).c_str(), model_.message(),
                 client_.url().c_str());
    while (!quit_ && !stopRequested()) {
      if (sessionGone()) break;
      runScriptLines();
      sendDue();
      if (quit_) break;
      reportRefusals();
      showStatus();
      if (sessionEnded() || scriptDone()) break;
      waitForInput();
    }
    if (!o_.hold) model_.send(client_, token_, true);
    collectLastRefusals();
    model_.summary(t_, o_.session, tty_);
    reportRefusals();
    if (tty_) std::fprintf(stderr, "\n");
    if (refusals_ > 0) fail(kExitRefused, std::to_string(refusals_) + " drive command(s) refused");
  }

 private:
  // commands into the void help nobody: a silent server ends the drive
  bool sessionGone() {
    if (client_.server().lost()) fail(kExitNoServer, client_.server().lostMessage(client_.url()));
    const auto info = client_.server().session(o_.session);
    if (!info || !net::isFinal(info->status) || t_.have_state) return false;
    std::fprintf(stderr, "drive %s: session %s (from the server's heartbeat)\n", net::printable(o_.session).c_str(),
                 net::statusName(info->status));
    return true;
  }

  // script lines run in order; a wait holds back the ones after it
  void runScriptLines() {
    while (!tty_ && !quit_ && SteadyClock::now() >= wait_until_) {
      auto nl = pending_.find('\n');
      if (nl == std::string::npos) {
        if (input_open_ || pending_.empty()) break;
        pending_ += '\n';  // last line without a newline
        continue;
      }
      const std::string line = pending_.substr(0, nl);
      pending_.erase(0, nl + 1);
      ++line_no_;
      double wait = 0.0;
      try {
        wait = model_.applyLine(line);
      } catch (const std::invalid_argument& e) {
        fail(kExitRefused, "stdin line " + std::to_string(line_no_) + ": " + e.what());
      }
      dirty_ = true;
      if (wait < 0) quit_ = true;
      if (wait > 0)
        wait_until_ = SteadyClock::now() +
                      std::chrono::duration_cast<SteadyClock::duration>(std::chrono::duration<double>(wait));
    }
  }

  void sendDue() {
    const auto now = SteadyClock::now();
    model_.tick(std::chrono::duration<double>(now - last_tick_).count());
    last_tick_ = now;
    if (!dirty_ && now < next_send_) return;
    model_.send(client_, token_, false);
    next_send_ = now + period_;
    dirty_ = false;
  }

  void reportRefusals() {
    for (const auto& e : client_.takeEvents()) {
      ++refusals_;
      std::fprintf(stderr, "%sgroundsim: refused: %s\n", tty_ ? "\r\033[K" : "", net::printable(e.reason, 1000).c_str());
    }
  }

  void showStatus() const {
    if (tty_ && t_.have_state) std::fprintf(stderr, "\r\033[K%s", model_.status(t_).c_str());
  }

  bool sessionEnded() const {
    if (!t_.have_state || !net::isFinal(t_.state.status)) return false;
    std::fprintf(stderr, "%sdrive %s: session %s\n", tty_ ? "\n" : "", net::printable(o_.session).c_str(),
                 net::statusName(t_.state.status));
    return true;
  }

  bool scriptDone() const { return !input_open_ && pending_.empty() && SteadyClock::now() >= wait_until_; }

  // the bus and stdin until the next send (or the end of a wait)
  void waitForInput() {
    pollfd fds[2] = {{client_.lcm().getFileno(), POLLIN, 0}, {STDIN_FILENO, POLLIN, 0}};
    auto until = next_send_;
    if (wait_until_ > SteadyClock::now()) until = std::min(until, wait_until_);
    const int ms = static_cast<int>(std::max<long long>(
        0, std::chrono::duration_cast<std::chrono::milliseconds>(until - SteadyClock::now()).count()));
    if (::poll(fds, input_open_ ? 2 : 1, ms) < 0) return;  // EINTR: the loop checks the stop flag
    if (fds[0].revents & POLLIN) client_.lcm().handleTimeout(0);
    if (!input_open_ || !(fds[1].revents & (POLLIN | POLLHUP))) return;
    char buf[4096];
    const ssize_t n = ::read(STDIN_FILENO, buf, sizeof buf);
    if (n <= 0) {
      input_open_ = false;
      return;
    }
    if (!tty_) {
      pending_.append(buf, static_cast<size_t>(n));
      return;
    }
    const std::string bytes(buf, static_cast<size_t>(n));
    for (std::string::size_type i = 0; i < bytes.size();) {
      KeyPress k;
      i = nextKey(bytes, i, &k);
      if (!model_.applyKey(k)) quit_ = true;
    }
    dirty_ = true;
  }

  // The server handles datagrams in the order they come, on one thread, and
  // publishes a command's refusal as it handles it, so once a request sent
  // after the last command is answered every refusal of ours is in (a fixed
  // 150 ms lost them on a busy machine).
  void collectLastRefusals() {
    groundsim::request_t barrier{};
    barrier.op = groundsim::request_t::OP_LIST;
    try {
      client_.call(barrier, o_.net.timeout);
    } catch (const NetError&) {
      // no answer in time: the refusals that came are counted all the same
    }
  }

  const DriveOpts& o_;
  NetClient& client_;
  const Telemetry& t_;
  ControlModel& model_;
  const std::string token_;
  const bool tty_;
  const SteadyClock::duration period_ =
      std::chrono::duration_cast<SteadyClock::duration>(std::chrono::duration<double>(1.0 / o_.hz));
  SteadyClock::time_point last_tick_ = SteadyClock::now(), next_send_ = SteadyClock::now(), wait_until_{};
  bool input_open_ = true, quit_ = false, dirty_ = true;
  std::string pending_;  // partial script line
  long line_no_ = 0;
  int refusals_ = 0;
};

void run(const DriveOpts& o) {
  installStopSignals();
  NetClient client(o.net.url);
  const std::string token = tokenFor(o.net, o.session);
  if (token.empty())
    std::fprintf(stderr, "groundsim: warning: no token for session %s (the server will refuse)\n",
                 net::printable(o.session).c_str());
  std::optional<RawTerminal> term;  // keys one by one, from the start
  if (::isatty(STDIN_FILENO)) term.emplace(STDIN_FILENO);
  Telemetry telemetry;
  telemetry.vehicle = o.vehicle;
  client.lcm().subscribe(net::stateChannel(o.session), &Telemetry::onState, &telemetry);
  client.lcm().subscribe(net::carStateChannel(o.session), &Telemetry::onCar, &telemetry);
  const std::unique_ptr<ControlModel> model = chooseControlModel(o, client, telemetry);
  Drive(o, client, telemetry, *model, token).run();
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
