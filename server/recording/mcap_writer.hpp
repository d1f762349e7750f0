// McapWriter: records timestamped messages into an MCAP file
// (https://mcap.dev/spec), zstd-compressed chunks with message indexes and
// a summary, so that a reader finds one session's messages without reading
// the others'.
//
// Layout written:
//   magic, Header,
//   Schema and Channel records as they are added (outside chunks: a file cut
//   by a crash still names every channel its chunks use),
//   Chunk + its MessageIndex records, per group (see write()), Attachment and
//   Metadata records as they come,
//   DataEnd (CRC of everything before it),
//   summary: Schemas, Channels, Statistics, ChunkIndexes, AttachmentIndexes,
//   MetadataIndexes, then SummaryOffsets, Footer (summary CRC), magic.
//
// Memory: one open chunk per group that has one, each up to chunk_bytes of
// uncompressed records, plus the summary's indexes (about 100 bytes a chunk).
// Not thread-safe: one writer, one thread at a time.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "recording/mcap_format.hpp"

namespace groundsim::recording {

struct WriterOptions {
  // A group's chunk is closed (compressed, written) when its uncompressed
  // records reach this size: larger chunks compress better, smaller ones let
  // a reader skip more and lose less in a crash. At most 256 MiB (so is one
  // message): a chunk stays under the 1 GiB readers load at once.
  std::size_t chunk_bytes = 1 << 20;
  // zstd level 1..22; 0 writes chunks uncompressed (compression ""). A chunk
  // zstd shrinks by less than 1/32 is stored uncompressed too.
  int zstd_level = 3;
  // Crash safety: at a write, if any group's open chunk was opened longer
  // ago than this (steady clock), every open chunk is closed and the file is
  // fflush()ed first (flush()). <= 0: only size and explicit flush() close.
  double chunk_seconds = 1.0;
  std::string profile = "";          // Header.profile (e.g. "ros2"; "" for none)
  std::string library = "groundsim";  // Header.library
};

class McapWriter {
 public:
  // Creates (truncates) path and writes the magic and Header. Throws
  // std::runtime_error naming the path and the errno text;
  // std::invalid_argument for a zstd_level outside 0..22 or chunk_bytes
  // over 256 MiB.
  McapWriter(const std::string& path, WriterOptions o = {});
  // close() if not closed; never throws (an error there is lost: call
  // close() to see it).
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  // Ids are handed out from 1 upwards (schema id 0 means "no schema").
  // Both records go to the file at once, before any chunk that can use them.
  std::uint16_t addSchema(const std::string& name, const std::string& encoding, std::string_view data);
  // schema_id 0 (no schema) or one from addSchema(), else std::invalid_argument.
  std::uint16_t addChannel(std::uint16_t schema_id, const std::string& topic,
                           const std::string& message_encoding,
                           const std::map<std::string, std::string>& metadata = {});

  // One message on a channel from addChannel() (else, or for data over
  // 256 MiB, std::invalid_argument).
  // group: messages of different groups never share a chunk (one recorded
  // session per group), so a reader of one session decompresses only its
  // chunks. Each group's open chunk is closed at chunk_bytes; see also
  // WriterOptions::chunk_seconds.
  void write(std::uint16_t channel, std::uint32_t sequence, std::uint64_t log_time_ns,
             std::uint64_t publish_time_ns, std::string_view data, int group = 0);

  // An Attachment record, written at once (never inside a chunk), with its
  // CRC. create_time is written as 0 ("not available").
  void attach(const std::string& name, const std::string& media_type, std::uint64_t log_time_ns,
              std::string_view data);
  // A Metadata record (a named string map), written at once.
  void metadata(const std::string& name, const std::map<std::string, std::string>& kv);

  // Closes every open chunk, writes it with its message indexes and
  // fflush()es: everything written so far is readable if the process dies
  // (McapReader scans a file without footer). No fsync: an OS crash may
  // still lose what the kernel had not written out.
  void flush();
  // flush(), DataEnd with the data section's CRC, the summary (schemas,
  // channels, statistics with per-channel counts, chunk, attachment and
  // metadata indexes, summary offsets), Footer and magic; closes the file.
  // Idempotent. Any write after it throws std::logic_error.
  void close();

  // Bytes in the file so far (what has reached fwrite; open chunks not yet).
  std::uint64_t bytesWritten() const { return offset_; }

 private:
  struct OpenChunk {
    std::string records;  // uncompressed Message records
    std::uint64_t start = UINT64_MAX, end = 0;
    std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> index;
    std::chrono::steady_clock::time_point opened;
  };

  void put(std::string_view bytes);  // fwrite; advances offset_ and the running CRC
  void closeChunk(std::map<int, OpenChunk>::iterator it);
  void requireOpen(const char* what) const;
  void writeSummary();

  std::string path_;
  WriterOptions opt_;
  std::FILE* file_ = nullptr;
  bool failed_ = false;           // a write failed: the file's tail is unknown
  void* zstd_ = nullptr;          // ZSTD_CCtx*, reused (zstd.h stays out of this header)
  std::uint64_t offset_ = 0;
  std::uint32_t crc_ = 0;         // data section CRC, then the summary's

  std::vector<std::string> schema_records_, channel_records_;  // repeated in the summary
  std::map<int, OpenChunk> open_;                              // open chunks by group
  std::chrono::steady_clock::time_point oldest_open_;          // of open_, when not empty
  std::string scratch_;                                        // compressed chunk, reused
  std::vector<mcap::ChunkIndex> chunk_indexes_;
  std::vector<mcap::AttachmentIndex> attachment_indexes_;
  std::vector<mcap::MetadataIndex> metadata_indexes_;
  mcap::Statistics stats_;
  std::vector<std::uint64_t> channel_counts_;  // by channel id (index 0 unused)
};

}  // namespace groundsim::recording
