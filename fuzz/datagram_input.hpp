// The datagram fuzzer's input format: a sequence of records
//   [channel byte][length, 2 bytes little endian][payload]
// channel byte even: GROUNDSIM_REQUEST, odd: GROUNDSIM_DRIVE. A record whose
// length runs past the end takes the rest. Shared by the target and the
// seed writer so that seeds are valid inputs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace groundsim::fuzz {

enum class Channel { Request, Drive };

struct Datagram {
  Channel channel;
  const std::uint8_t* data;
  int size;
};

inline std::vector<Datagram> splitDatagrams(const std::uint8_t* data, std::size_t size) {
  std::vector<Datagram> out;
  std::size_t at = 0;
  while (at + 3 <= size) {
    const Channel ch = (data[at] & 1) ? Channel::Drive : Channel::Request;
    std::size_t len = data[at + 1] | (std::size_t(data[at + 2]) << 8);
    at += 3;
    if (len > size - at) len = size - at;
    out.push_back({ch, data + at, static_cast<int>(len)});
    at += len;
  }
  return out;
}

inline void appendDatagram(std::string& input, Channel ch, const std::vector<std::uint8_t>& payload) {
  input.push_back(ch == Channel::Drive ? 1 : 0);
  input.push_back(static_cast<char>(payload.size() & 0xff));
  input.push_back(static_cast<char>((payload.size() >> 8) & 0xff));
  input.append(payload.begin(), payload.end());
}

}  // namespace groundsim::fuzz
