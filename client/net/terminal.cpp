#include "terminal.hpp"

#include <unistd.h>

namespace groundsim::cli {

RawTerminal::RawTerminal(int fd) : fd_(fd) {
  if (tcgetattr(fd_, &saved_) != 0) return;
  termios raw = saved_;
  // keys arrive one by one without echo; ISIG stays on so Ctrl-C still stops
  raw.c_lflag &= ~static_cast<tcflag_t>(ICANON | ECHO);
  raw.c_cc[VMIN] = 0;
  raw.c_cc[VTIME] = 0;
  active_ = tcsetattr(fd_, TCSANOW, &raw) == 0;
}

RawTerminal::~RawTerminal() {
  if (active_) tcsetattr(fd_, TCSANOW, &saved_);
}

std::string::size_type nextKey(const std::string& b, std::string::size_type i, KeyPress* out) {
  if (b[i] == '\033' && i + 2 < b.size() && b[i + 1] == '[') {
    switch (b[i + 2]) {
      case 'A': *out = {Key::Up, 0}; return i + 3;
      case 'B': *out = {Key::Down, 0}; return i + 3;
      case 'C': *out = {Key::Right, 0}; return i + 3;
      case 'D': *out = {Key::Left, 0}; return i + 3;
      default: *out = {Key::None, 0}; return i + 3;
    }
  }
  *out = {Key::Char, b[i]};
  return i + 1;
}

}  // namespace groundsim::cli
