// The MCAP container format, version "0" (https://mcap.dev/spec): magic,
// opcodes, little-endian encoding and the summary records both the writer
// and the reader handle. One place holds the byte layout; mcap_writer.cpp
// and mcap_reader.cpp only decide what to write and what to trust.
//
// Every record is <opcode u8><content length u64><content>; strings are a
// u32 byte length and the bytes, maps and arrays a u32 byte length and the
// packed entries; integers are little-endian whatever the host.
#pragma once

#include <cstdint>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>

namespace groundsim::recording::mcap {

// 0x89 'M' 'C' 'A' 'P' then the major version '0' (0x30) and \r\n, at the
// start and at the end of a finished file.
inline constexpr std::string_view kMagic{"\x89MCAP0\r\n", 8};

enum class Op : std::uint8_t {
  Header = 0x01,
  Footer = 0x02,
  Schema = 0x03,
  Channel = 0x04,
  Message = 0x05,
  Chunk = 0x06,
  MessageIndex = 0x07,
  ChunkIndex = 0x08,
  Attachment = 0x09,
  AttachmentIndex = 0x0A,
  Statistics = 0x0B,
  Metadata = 0x0C,
  MetadataIndex = 0x0D,
  SummaryOffset = 0x0E,
  DataEnd = 0x0F,
};

inline constexpr std::size_t kRecordPrefix = 9;       // opcode + u64 content length
inline constexpr std::size_t kFooterContent = 20;     // summary_start, summary_offset_start, crc
inline constexpr std::size_t kFooterRecord = kRecordPrefix + kFooterContent;
inline constexpr std::size_t kDataEndRecord = kRecordPrefix + 4;
inline constexpr std::size_t kMessageFixed = 2 + 4 + 8 + 8;  // channel, sequence, log, publish

// What a reader holds in memory at once for one record (a chunk's compressed
// or uncompressed records, an attachment, the summary): a hostile length can
// make it fail with a reason, never allocate more.
inline constexpr std::uint64_t kMaxLoadBytes = std::uint64_t{1} << 30;

// ---- writing: append to a std::string --------------------------------------

inline void putU8(std::string& s, std::uint8_t v) { s.push_back(static_cast<char>(v)); }
inline void putU16(std::string& s, std::uint16_t v) {
  for (int i = 0; i < 2; ++i) s.push_back(static_cast<char>(v >> (8 * i)));
}
inline void putU32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s.push_back(static_cast<char>(v >> (8 * i)));
}
inline void putU64(std::string& s, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) s.push_back(static_cast<char>(v >> (8 * i)));
}
inline void patchU64(std::string& s, std::size_t at, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) s[at + i] = static_cast<char>(v >> (8 * i));
}
inline void patchU32(std::string& s, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s[at + i] = static_cast<char>(v >> (8 * i));
}
// u32-prefixed bytes (strings, a schema's data): longer ones cannot be encoded
inline void putStr(std::string& s, std::string_view v) {
  if (v.size() > UINT32_MAX) throw std::length_error("mcap: string or bytes longer than 4 GiB");
  putU32(s, static_cast<std::uint32_t>(v.size()));
  s.append(v);
}
inline void putStringMap(std::string& s, const std::map<std::string, std::string>& m) {
  const std::size_t at = s.size();
  putU32(s, 0);
  for (const auto& [k, v] : m) {
    putStr(s, k);
    putStr(s, v);
  }
  if (s.size() - at - 4 > UINT32_MAX) throw std::length_error("mcap: map longer than 4 GiB");
  patchU32(s, at, static_cast<std::uint32_t>(s.size() - at - 4));
}
template <class V>
void putIdMap(std::string& s, const std::map<std::uint16_t, V>& m) {  // Map<uint16, uint64>
  putU32(s, static_cast<std::uint32_t>(m.size() * (2 + 8)));
  for (const auto& [k, v] : m) {
    putU16(s, k);
    putU64(s, v);
  }
}

// Opens a record in s; endRecord writes its content length once known.
inline std::size_t beginRecord(std::string& s, Op op) {
  putU8(s, static_cast<std::uint8_t>(op));
  putU64(s, 0);
  return s.size();
}
inline void endRecord(std::string& s, std::size_t content_start) {
  patchU64(s, content_start - 8, s.size() - content_start);
}

// ---- reading: little-endian loads and a bounds-checked cursor ---------------

// A malformed record (McapReader adds the file's path to the message).
struct FormatError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

inline std::uint16_t loadU16(const char* p) {
  const auto* u = reinterpret_cast<const unsigned char*>(p);
  return static_cast<std::uint16_t>(u[0] | u[1] << 8);
}
inline std::uint32_t loadU32(const char* p) {
  const auto* u = reinterpret_cast<const unsigned char*>(p);
  return std::uint32_t(u[0]) | std::uint32_t(u[1]) << 8 | std::uint32_t(u[2]) << 16 |
         std::uint32_t(u[3]) << 24;
}
inline std::uint64_t loadU64(const char* p) {
  return std::uint64_t(loadU32(p)) | std::uint64_t(loadU32(p + 4)) << 32;
}

// Reads the fields of one record's content. Every length is checked against
// what is left of the record, so a corrupt length fails here, naming the
// record and its file offset, instead of reading past it or allocating it.
class Cursor {
 public:
  Cursor(std::string_view content, const char* record, std::uint64_t file_offset)
      : s_(content), record_(record), offset_(file_offset) {}

  std::uint8_t u8() { return static_cast<std::uint8_t>(take(1, "u8")[0]); }
  std::uint16_t u16() { return loadU16(take(2, "u16").data()); }
  std::uint32_t u32() { return loadU32(take(4, "u32").data()); }
  std::uint64_t u64() { return loadU64(take(8, "u64").data()); }
  std::string_view str() { return take(u32(), "string or u32-length bytes"); }
  std::string_view bytes(std::uint64_t n, const char* what = "bytes") { return take(n, what); }
  std::map<std::string, std::string> stringMap() {
    Cursor m(take(u32(), "map"), record_, offset_);
    std::map<std::string, std::string> out;
    while (m.remaining() > 0) {
      std::string k(m.str());
      out[std::move(k)] = std::string(m.str());
    }
    return out;
  }
  std::map<std::uint16_t, std::uint64_t> idMap() {
    Cursor m(take(u32(), "map"), record_, offset_);
    std::map<std::uint16_t, std::uint64_t> out;
    while (m.remaining() > 0) {
      const std::uint16_t k = m.u16();
      out[k] = m.u64();
    }
    return out;
  }
  std::string_view rest() { return take(remaining(), "rest"); }
  std::size_t remaining() const { return s_.size() - pos_; }
  std::size_t position() const { return pos_; }

  [[noreturn]] void fail(const std::string& why) const {
    throw FormatError(std::string(record_) + " record at offset " +
                             std::to_string(offset_) + ": " + why);
  }

 private:
  std::string_view take(std::uint64_t n, const char* what) {
    if (n > remaining())
      fail(std::string(what) + " of " + std::to_string(n) + " bytes runs past the record end (" +
           std::to_string(remaining()) + " bytes left)");
    const std::string_view v = s_.substr(pos_, static_cast<std::size_t>(n));
    pos_ += static_cast<std::size_t>(n);
    return v;
  }
  std::string_view s_;
  std::size_t pos_ = 0;
  const char* record_;
  std::uint64_t offset_;
};

// ---- the summary records (encode: writer, decode: reader) -------------------

struct ChunkIndex {
  std::uint64_t message_start_time = 0, message_end_time = 0;
  std::uint64_t chunk_start_offset = 0, chunk_length = 0;  // the whole Chunk record
  std::map<std::uint16_t, std::uint64_t> message_index_offsets;  // channel -> its MessageIndex record
  std::uint64_t message_index_length = 0;  // all MessageIndex records after the chunk
  std::string compression;                 // "zstd" or "" (none)
  std::uint64_t compressed_size = 0, uncompressed_size = 0;  // of the chunk's records field
};

struct AttachmentIndex {
  std::uint64_t offset = 0, length = 0;  // the whole Attachment record
  std::uint64_t log_time = 0, create_time = 0, data_size = 0;
  std::string name, media_type;
};

struct MetadataIndex {
  std::uint64_t offset = 0, length = 0;  // the whole Metadata record
  std::string name;
};

struct Statistics {
  std::uint64_t message_count = 0;
  std::uint16_t schema_count = 0;
  std::uint32_t channel_count = 0, attachment_count = 0, metadata_count = 0, chunk_count = 0;
  std::uint64_t message_start_time = 0, message_end_time = 0;  // 0, 0 without messages
  std::map<std::uint16_t, std::uint64_t> channel_message_counts;
};

inline void encode(std::string& s, const ChunkIndex& c) {
  const std::size_t at = beginRecord(s, Op::ChunkIndex);
  putU64(s, c.message_start_time);
  putU64(s, c.message_end_time);
  putU64(s, c.chunk_start_offset);
  putU64(s, c.chunk_length);
  putIdMap(s, c.message_index_offsets);
  putU64(s, c.message_index_length);
  putStr(s, c.compression);
  putU64(s, c.compressed_size);
  putU64(s, c.uncompressed_size);
  endRecord(s, at);
}
inline ChunkIndex decodeChunkIndex(Cursor& c) {
  ChunkIndex r;
  r.message_start_time = c.u64();
  r.message_end_time = c.u64();
  r.chunk_start_offset = c.u64();
  r.chunk_length = c.u64();
  r.message_index_offsets = c.idMap();
  r.message_index_length = c.u64();
  r.compression = std::string(c.str());
  r.compressed_size = c.u64();
  r.uncompressed_size = c.u64();
  return r;
}

inline void encode(std::string& s, const AttachmentIndex& a) {
  const std::size_t at = beginRecord(s, Op::AttachmentIndex);
  putU64(s, a.offset);
  putU64(s, a.length);
  putU64(s, a.log_time);
  putU64(s, a.create_time);
  putU64(s, a.data_size);
  putStr(s, a.name);
  putStr(s, a.media_type);
  endRecord(s, at);
}
inline AttachmentIndex decodeAttachmentIndex(Cursor& c) {
  AttachmentIndex r;
  r.offset = c.u64();
  r.length = c.u64();
  r.log_time = c.u64();
  r.create_time = c.u64();
  r.data_size = c.u64();
  r.name = std::string(c.str());
  r.media_type = std::string(c.str());
  return r;
}

inline void encode(std::string& s, const MetadataIndex& m) {
  const std::size_t at = beginRecord(s, Op::MetadataIndex);
  putU64(s, m.offset);
  putU64(s, m.length);
  putStr(s, m.name);
  endRecord(s, at);
}
inline MetadataIndex decodeMetadataIndex(Cursor& c) {
  MetadataIndex r;
  r.offset = c.u64();
  r.length = c.u64();
  r.name = std::string(c.str());
  return r;
}

inline void encode(std::string& s, const Statistics& st) {
  const std::size_t at = beginRecord(s, Op::Statistics);
  putU64(s, st.message_count);
  putU16(s, st.schema_count);
  putU32(s, st.channel_count);
  putU32(s, st.attachment_count);
  putU32(s, st.metadata_count);
  putU32(s, st.chunk_count);
  putU64(s, st.message_start_time);
  putU64(s, st.message_end_time);
  putIdMap(s, st.channel_message_counts);
  endRecord(s, at);
}
inline Statistics decodeStatistics(Cursor& c) {
  Statistics r;
  r.message_count = c.u64();
  r.schema_count = c.u16();
  r.channel_count = c.u32();
  r.attachment_count = c.u32();
  r.metadata_count = c.u32();
  r.chunk_count = c.u32();
  r.message_start_time = c.u64();
  r.message_end_time = c.u64();
  r.channel_message_counts = c.idMap();
  return r;
}

}  // namespace groundsim::recording::mcap
