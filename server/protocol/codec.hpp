// Decoding of raw LCM datagrams with the reason for a refusal: too short,
// another type's fingerprint (e.g. an older or foreign message on our
// channel), or malformed. lcm-gen's decode() alone only says "-1" and, for
// a corrupt array length, may even throw.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

namespace groundsim::net {

enum class DecodeStatus { Ok, TooShort, Fingerprint, Malformed };

struct DecodeResult {
  DecodeStatus status = DecodeStatus::Ok;
  std::string reason;  // empty when Ok
  bool ok() const { return status == DecodeStatus::Ok; }
};

inline std::uint64_t readFingerprint(const void* data) {
  const auto* b = static_cast<const unsigned char*>(data);
  std::uint64_t h = 0;
  for (int i = 0; i < 8; ++i) h = (h << 8) | b[i];
  return h;
}

template <class T>
DecodeResult decodeMessage(const void* data, int size, T& out, const char* type_name) {
  char buf[160];
  if (!data || size < 8) {
    std::snprintf(buf, sizeof buf, "%d bytes cannot hold a %s", size, type_name);
    return {DecodeStatus::TooShort, buf};
  }
  const std::uint64_t got = readFingerprint(data);
  const auto want = static_cast<std::uint64_t>(T::getHash());
  if (got != want) {
    std::snprintf(buf, sizeof buf, "fingerprint 0x%016llx is not %s's 0x%016llx (wrong type or version)",
                  static_cast<unsigned long long>(got), type_name, static_cast<unsigned long long>(want));
    return {DecodeStatus::Fingerprint, buf};
  }
  int used = -1;
  try {
    used = out.decode(data, 0, size);
  } catch (...) {
    used = -1;  // a corrupt array length makes std::vector throw
  }
  if (used < 0) {
    std::snprintf(buf, sizeof buf, "malformed %s (%d bytes)", type_name, size);
    return {DecodeStatus::Malformed, buf};
  }
  return {};
}

}  // namespace groundsim::net
