// The datagram fuzzer's input format, shared by the target (datagram_fuzz.cpp)
// and the seed writer (datagram_seeds.cpp) so that seeds are valid inputs.
// One input is one datagram:
//   byte 0, bit 0: channel, 0 GROUNDSIM_REQUEST, 1 GROUNDSIM_DRIVE
//   byte 0, bit 2: GROUNDSIM_ASSET (asset_part_t) instead of either
//   byte 0, bit 1: 1 when the rest is a message body without its 8-byte type
//                  fingerprint; the target puts that channel's fingerprint
//                  back, so mutations reach the decoder and the handlers
//                  instead of stopping at the fingerprint check
//   bytes 1..:     the datagram (or the body)
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace groundsim::fuzz {

inline constexpr std::uint8_t kDriveBit = 1;
inline constexpr std::uint8_t kBodyOnlyBit = 2;
inline constexpr std::uint8_t kAssetBit = 4;

// An input that delivers `encoded` (a whole LCM encoding, fingerprint first)
// on the drive or request channel; body_only strips the fingerprint.
inline std::string makeInput(bool drive, bool body_only, const std::vector<std::uint8_t>& encoded) {
  std::string input(1, static_cast<char>((drive ? kDriveBit : 0) | (body_only ? kBodyOnlyBit : 0)));
  const std::size_t skip = body_only && encoded.size() >= 8 ? 8 : 0;
  input.append(encoded.begin() + static_cast<std::ptrdiff_t>(skip), encoded.end());
  return input;
}

}  // namespace groundsim::fuzz
