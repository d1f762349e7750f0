// Keyboard input for `groundsim drive`: the terminal in non-canonical,
// no-echo mode for as long as the object lives (restored on every exit
// path, including exceptions), and decoding of arrow-key escape sequences.
#pragma once

#include <string>

#include <termios.h>

namespace groundsim::cli {

enum class Key { None, Up, Down, Left, Right, Char };

struct KeyPress {
  Key key = Key::None;
  char ch = 0;  // Key::Char
};

class RawTerminal {
 public:
  explicit RawTerminal(int fd);
  ~RawTerminal();
  RawTerminal(const RawTerminal&) = delete;
  RawTerminal& operator=(const RawTerminal&) = delete;

 private:
  int fd_;
  termios saved_{};
  bool active_ = false;
};

// Splits a chunk of terminal input into key presses (arrows arrive as ESC [ A..D).
std::string::size_type nextKey(const std::string& bytes, std::string::size_type pos, KeyPress* out);

}  // namespace groundsim::cli
