#include "car_drive.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "protocol/text.hpp"

namespace groundsim::cli {
namespace {

double towardZero(double x, double by) { return x > 0 ? std::max(0.0, x - by) : std::min(0.0, x + by); }

double parseNumber(const std::string& word, const std::string& tok) {
  char* end = nullptr;
  const double x = std::strtod(tok.c_str(), &end);  // accepts nan and inf: the server judges them
  if (tok.empty() || end == tok.c_str() || *end) throw std::invalid_argument(word + ": not a number: " + net::quoted(tok));
  return x;
}

int parseGear(const std::string& tok) {
  std::string t = tok;
  for (char& c : t) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (t == "auto" || t == "a" || t == "d") return groundsim::controls_t::GEAR_AUTO;
  if (t == "r" || t == "reverse") return groundsim::controls_t::GEAR_REVERSE;
  if (t == "n" || t == "neutral") return groundsim::controls_t::GEAR_NEUTRAL;
  char* end = nullptr;
  const long g = std::strtol(t.c_str(), &end, 10);
  if (t.empty() || *end || g < -128 || g > 127)
    throw std::invalid_argument("gear: " + net::quoted(tok) + " is not auto, r, n or a gear number");
  return static_cast<int>(g);
}

}  // namespace

void CarIntent::tick(double dt) {
  if (!decays || dt <= 0) return;
  const double by = kReturnRate * dt;
  throttle_age += dt, brake_age += dt, steer_age += dt;
  if (throttle_age > kRelease) throttle = towardZero(throttle, by);
  if (brake_age > kRelease) brake = towardZero(brake, by);
  if (steer_age > kRelease) steer = towardZero(steer, by);
}

groundsim::controls_t CarIntent::toMessage(const std::string& session, int vehicle) const {
  groundsim::controls_t m{};
  m.session_id = session;
  m.vehicle = vehicle;
  m.throttle = throttle;
  m.brake = brake;
  m.steer = steer;
  m.handbrake = handbrake;
  m.gear = static_cast<int8_t>(gear);
  return m;
}

std::string gearName(int gear) {
  if (gear == groundsim::controls_t::GEAR_AUTO) return "auto";
  if (gear == groundsim::controls_t::GEAR_REVERSE) return "R";
  if (gear == groundsim::controls_t::GEAR_NEUTRAL) return "N";
  return std::to_string(gear);
}

std::string CarIntent::describe() const {
  char buf[96];
  std::snprintf(buf, sizeof buf, "throttle %.2f brake %.2f steer %+.2f%s gear %s", throttle, brake, steer,
                handbrake ? " handbrake" : "", gearName(gear).c_str());
  return buf;
}

double applyCarLine(const std::string& line, CarIntent& in) {
  std::istringstream ss(line);
  std::string word, arg, extra;
  if (!(ss >> word) || word[0] == '#') return 0.0;
  const bool has_arg = static_cast<bool>(ss >> arg);
  if (ss >> extra) throw std::invalid_argument(word + " takes one value");
  auto need = [&]() {
    if (!has_arg) throw std::invalid_argument(word + " takes one value");
    return arg;
  };
  in.decays = false;
  if (word == "throttle") in.throttle = parseNumber(word, need());
  else if (word == "brake") in.brake = parseNumber(word, need());
  else if (word == "steer" || word == "turn") in.steer = parseNumber(word, need());
  else if (word == "handbrake") in.handbrake = parseNumber(word, need()) != 0.0;
  else if (word == "gear") in.gear = parseGear(need());
  else if (word == "release") in = CarIntent{};
  else if (word == "wait") return std::max(0.0, parseNumber(word, need()));
  else if (word == "quit") return -1.0;
  else throw std::invalid_argument("unknown command " + net::quoted(word) + " (road car: throttle, brake, steer, "
                                   "handbrake, gear, release, wait, quit)");
  return 0.0;
}

bool applyCarKey(const KeyPress& k, CarIntent& in) {
  const char c = k.key == Key::Char ? static_cast<char>(std::tolower(static_cast<unsigned char>(k.ch))) : 0;
  in.decays = true;
  if (k.key == Key::Up || c == 'w') {
    in.throttle = std::min(1.0, in.throttle + CarIntent::kPedalStep), in.throttle_age = 0.0;
    in.brake = 0.0;
  } else if (k.key == Key::Down || c == 's') {
    in.brake = std::min(1.0, in.brake + CarIntent::kPedalStep), in.brake_age = 0.0;
    in.throttle = 0.0;
  } else if (k.key == Key::Left || c == 'a') {
    in.steer = std::min(1.0, std::max(0.0, in.steer) + CarIntent::kSteerStep), in.steer_age = 0.0;
  } else if (k.key == Key::Right || c == 'd') {
    in.steer = std::max(-1.0, std::min(0.0, in.steer) - CarIntent::kSteerStep), in.steer_age = 0.0;
  } else if (c == ' ') {
    in.brake = 1.0, in.brake_age = 0.0, in.throttle = 0.0;
  } else if (c == 'h') in.handbrake = !in.handbrake;
  else if (c == 'r') in.gear = groundsim::controls_t::GEAR_REVERSE;
  else if (c == 'n') in.gear = groundsim::controls_t::GEAR_NEUTRAL;
  else if (c == '0') in.gear = groundsim::controls_t::GEAR_AUTO;
  else if (c >= '1' && c <= '9') in.gear = c - '0';
  else if (c == 'x') in = CarIntent{}, in.decays = true;
  else if (c == 'q' || c == 3 || c == 4) return false;
  return true;
}

}  // namespace groundsim::cli
