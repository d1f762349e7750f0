// CRC-32 as MCAP uses it: the IEEE 802.3 / zlib polynomial (reflected
// 0xEDB88320), initial value and final xor 0xFFFFFFFF. Written here (eight
// 256-entry tables, "slicing by 8", built at compile time) rather than taken
// from zlib: it is forty lines, the layer then depends on libzstd alone, and
// it runs at a few GB/s, so checking every chunk costs little next to zstd.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace groundsim::recording {

// zlib's convention: crc32(data) of a whole buffer, or a running value
// continued piece by piece: crc32(b, crc32(a)) == crc32(a + b).
std::uint32_t crc32(std::string_view data, std::uint32_t crc = 0);
std::uint32_t crc32(const void* data, std::size_t size, std::uint32_t crc = 0);

}  // namespace groundsim::recording
