# Run after lcm-gen on every generated header (cmake -P, HEADERS=a;b;c).
# lcm-gen 1.3's C++ decoders trust two numbers a datagram carries:
# - a string's length is checked only against the bytes left, then `len - 1`
#   is taken in int32: a length of -2147483648 wraps to 2147483647 and the
#   decoder copies 2 GB past the datagram (found by fuzz/datagram_fuzz.cpp);
#   a length of 0 or below asks std::string for SIZE_MAX bytes;
# - an array's count is not checked at all before `resize(count)`: a count of
#   10^8 allocates and zero-fills gigabytes before the decode fails.
# This adds the missing checks: a string length must be in [1, bytes left],
# an array count in [0, bytes left] (every element takes at least one byte).
# The wire format and the fingerprints are unchanged.
foreach(h ${HEADERS})
  file(READ ${h} text)
  string(REGEX REPLACE
    "if\\((__[A-Za-z0-9_]+) > maxlen - pos\\) return -1;"
    "if(\\1 < 1 || \\1 > maxlen - pos) return -1;"
    text "${text}")
  string(REGEX REPLACE
    "(this->[A-Za-z0-9_]+)\\.resize\\((this->[A-Za-z0-9_]+)\\);"
    "if(\\2 < 0 || \\2 > maxlen - pos) return -1; \\1.resize(\\2);"
    text "${text}")
  file(WRITE ${h} "${text}")
endforeach()
