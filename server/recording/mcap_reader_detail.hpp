// McapReader's insides, shared by its source files and by nothing else:
// mcap_reader.cpp (opening: header, footer, summary; attachments, metadata,
// verify), mcap_scan.cpp (the scan of a file without a usable summary) and
// mcap_chunks.cpp (chunks: loading, counting, delivering their messages).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "recording/mcap_format.hpp"
#include "recording/mcap_reader.hpp"

namespace groundsim::recording {

// A chunk as the summary's ChunkIndex or the scan describes it; in a
// scanned file also a Message record outside chunks (other writers).
struct McapReader::ChunkRef {
  std::uint64_t offset = 0, length = 0;  // the whole record
  std::uint64_t start = 0, end = 0;      // message log times it claims
  std::string compression;
  std::uint64_t compressed_size = 0, uncompressed_size = 0;
  std::map<std::uint16_t, std::uint64_t> index_offsets;  // channel -> MessageIndex record
  // index_offsets names every channel of the chunk: channel filters may skip
  // it, counts may come from it. False for a chunk without message indexes
  // and for the last chunk of a scan (the end may have cut its indexes).
  bool indexed = false;
  std::map<std::uint16_t, std::uint64_t> counts;  // from the scan's index headers
  bool counts_known = false;
  bool loose = false;  // a Message record outside chunks
  std::uint16_t loose_channel = 0;
};

// One chunk being delivered by readMessages().
struct McapReader::Loaded {
  std::string raw;                          // the record as read from the file
  std::unique_ptr<char[]> decompressed;     // zstd output, when compressed
  std::string_view records;                 // the uncompressed records field
  std::vector<std::pair<std::uint64_t, std::uint64_t>> entries;  // (log_time, offset), sorted
  std::size_t next = 0;
  std::uint64_t order = 0;                  // the chunk's file offset: ties in log time
};

namespace mcap_detail {

// The record's name for messages ("Chunk", "private", "unknown").
const char* opName(std::uint8_t op);
// "0x" and v in at least digits hexadecimal digits.
std::string hex(std::uint64_t v, int digits = 2);
inline std::string num(std::uint64_t v) { return std::to_string(v); }

// Runs f, giving format errors (mcap::Cursor's) the file's path.
template <class F>
auto withPath(const std::string& path, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const mcap::FormatError& e) {
    throw std::runtime_error("McapReader: " + path + ": " + e.what());
  }
}

}  // namespace mcap_detail
}  // namespace groundsim::recording
