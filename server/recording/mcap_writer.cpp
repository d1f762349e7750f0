#include "recording/mcap_writer.hpp"

#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "recording/crc32.hpp"

namespace groundsim::recording {

using namespace mcap;

namespace {

ZSTD_CCtx* cctx(void* p) { return static_cast<ZSTD_CCtx*>(p); }

// chunk_bytes and one message stay under this: a chunk then stays under
// the 1 GiB a reader loads at once (mcap::kMaxLoadBytes), ours included
constexpr std::size_t kMaxChunkBytes = std::size_t{256} << 20;

}  // namespace

McapWriter::McapWriter(const std::string& path, WriterOptions o) : path_(path), opt_(std::move(o)) {
  if (opt_.zstd_level < 0 || opt_.zstd_level > ZSTD_maxCLevel())
    throw std::invalid_argument("McapWriter: zstd_level " + std::to_string(opt_.zstd_level) +
                                " outside 0.." + std::to_string(ZSTD_maxCLevel()));
  if (opt_.chunk_bytes == 0) opt_.chunk_bytes = 1;
  if (opt_.chunk_bytes > kMaxChunkBytes)
    throw std::invalid_argument("McapWriter: chunk_bytes " + std::to_string(opt_.chunk_bytes) +
                                " over 256 MiB: readers could not load such chunks");
  file_ = std::fopen(path.c_str(), "wb");
  if (!file_)
    throw std::runtime_error("McapWriter: cannot create " + path + ": " + std::strerror(errno));
  if (opt_.zstd_level > 0) {
    zstd_ = ZSTD_createCCtx();
    if (!zstd_) {
      std::fclose(file_);
      throw std::runtime_error("McapWriter: " + path + ": ZSTD_createCCtx failed");
    }
  }
  channel_counts_.assign(1, 0);
  std::string s(kMagic);
  const std::size_t at = beginRecord(s, Op::Header);
  putStr(s, opt_.profile);
  putStr(s, opt_.library);
  endRecord(s, at);
  try {
    put(s);
  } catch (...) {
    std::fclose(file_);
    ZSTD_freeCCtx(cctx(zstd_));
    throw;
  }
}

McapWriter::~McapWriter() {
  try {
    close();
  } catch (...) {
    // documented: close() explicitly to see the error
  }
  if (file_) std::fclose(file_);
  ZSTD_freeCCtx(cctx(zstd_));
}

void McapWriter::requireOpen(const char* what) const {
  if (!file_) throw std::logic_error(std::string("McapWriter::") + what + " after close: " + path_);
  if (failed_)
    throw std::runtime_error(std::string("McapWriter::") + what + ": an earlier write to " + path_ +
                             " failed");
}

void McapWriter::put(std::string_view bytes) {
  if (bytes.empty()) return;
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) {
    failed_ = true;
    throw std::runtime_error("McapWriter: writing " + path_ + ": " + std::strerror(errno));
  }
  offset_ += bytes.size();
  crc_ = crc32(bytes, crc_);
}

std::uint16_t McapWriter::addSchema(const std::string& name, const std::string& encoding,
                                    std::string_view data) {
  requireOpen("addSchema");
  if (schema_records_.size() >= UINT16_MAX)
    throw std::length_error("McapWriter: more than 65535 schemas in " + path_);
  const auto id = static_cast<std::uint16_t>(schema_records_.size() + 1);
  std::string s;
  const std::size_t at = beginRecord(s, Op::Schema);
  putU16(s, id);
  putStr(s, name);
  putStr(s, encoding);
  putStr(s, data);
  endRecord(s, at);
  put(s);
  schema_records_.push_back(std::move(s));
  stats_.schema_count = static_cast<std::uint16_t>(schema_records_.size());
  return id;
}

std::uint16_t McapWriter::addChannel(std::uint16_t schema_id, const std::string& topic,
                                     const std::string& message_encoding,
                                     const std::map<std::string, std::string>& metadata) {
  requireOpen("addChannel");
  if (schema_id > schema_records_.size())
    throw std::invalid_argument("McapWriter::addChannel: unknown schema id " +
                                std::to_string(schema_id) + " for topic " + topic);
  if (channel_records_.size() >= UINT16_MAX)
    throw std::length_error("McapWriter: more than 65535 channels in " + path_);
  const auto id = static_cast<std::uint16_t>(channel_records_.size() + 1);
  std::string s;
  const std::size_t at = beginRecord(s, Op::Channel);
  putU16(s, id);
  putU16(s, schema_id);
  putStr(s, topic);
  putStr(s, message_encoding);
  putStringMap(s, metadata);
  endRecord(s, at);
  put(s);
  channel_records_.push_back(std::move(s));
  channel_counts_.push_back(0);
  stats_.channel_count = static_cast<std::uint32_t>(channel_records_.size());
  return id;
}

void McapWriter::write(std::uint16_t channel, std::uint32_t sequence, std::uint64_t log_time_ns,
                       std::uint64_t publish_time_ns, std::string_view data, int group) {
  requireOpen("write");
  if (channel == 0 || channel > channel_records_.size())
    throw std::invalid_argument("McapWriter::write: unknown channel id " + std::to_string(channel));
  if (data.size() > kMaxChunkBytes)
    throw std::invalid_argument("McapWriter::write: a message of " + std::to_string(data.size()) +
                                " bytes, over 256 MiB: readers could not load its chunk");
  const auto now = std::chrono::steady_clock::now();
  if (!open_.empty() && opt_.chunk_seconds > 0 &&
      std::chrono::duration<double>(now - oldest_open_).count() > opt_.chunk_seconds)
    flush();

  auto it = open_.find(group);
  if (it == open_.end()) {
    if (open_.empty()) oldest_open_ = now;
    it = open_.emplace(group, OpenChunk{}).first;
    it->second.opened = now;
  }
  OpenChunk& c = it->second;
  const std::uint64_t offset = c.records.size();
  std::string& r = c.records;
  putU8(r, static_cast<std::uint8_t>(Op::Message));
  putU64(r, kMessageFixed + data.size());
  putU16(r, channel);
  putU32(r, sequence);
  putU64(r, log_time_ns);
  putU64(r, publish_time_ns);
  r.append(data);
  c.index[channel].emplace_back(log_time_ns, offset);
  c.start = std::min(c.start, log_time_ns);
  c.end = std::max(c.end, log_time_ns);

  if (stats_.message_count == 0) {
    stats_.message_start_time = stats_.message_end_time = log_time_ns;
  } else {
    stats_.message_start_time = std::min(stats_.message_start_time, log_time_ns);
    stats_.message_end_time = std::max(stats_.message_end_time, log_time_ns);
  }
  ++stats_.message_count;
  ++channel_counts_[channel];

  if (r.size() >= opt_.chunk_bytes) {
    closeChunk(it);
    if (!open_.empty()) {  // the oldest of the chunks left
      oldest_open_ = open_.begin()->second.opened;
      for (const auto& [g, oc] : open_) oldest_open_ = std::min(oldest_open_, oc.opened);
    }
  }
}

void McapWriter::closeChunk(std::map<int, OpenChunk>::iterator it) {
  OpenChunk& c = it->second;
  const std::string& records = c.records;
  const std::uint32_t records_crc = crc32(records);

  std::string_view payload = records;
  std::string compression;
  if (zstd_) {
    scratch_.resize(ZSTD_compressBound(records.size()));
    const std::size_t n = ZSTD_compressCCtx(cctx(zstd_), scratch_.data(), scratch_.size(),
                                            records.data(), records.size(), opt_.zstd_level);
    if (ZSTD_isError(n))
      throw std::runtime_error("McapWriter: " + path_ + ": zstd: " + ZSTD_getErrorName(n));
    // a chunk zstd shrinks by less than 1/32 is stored as it is: readers
    // would spend more decompressing it than the bytes save
    if (n < records.size() - records.size() / 32) {
      payload = std::string_view(scratch_.data(), n);
      compression = "zstd";
    }
  }

  std::string h;
  const std::size_t at = beginRecord(h, Op::Chunk);
  putU64(h, c.start);
  putU64(h, c.end);
  putU64(h, records.size());
  putU32(h, records_crc);
  putStr(h, compression);
  putU64(h, payload.size());
  patchU64(h, at - 8, h.size() - at + payload.size());

  ChunkIndex ci;
  ci.message_start_time = c.start;
  ci.message_end_time = c.end;
  ci.chunk_start_offset = offset_;
  ci.compression = compression;
  ci.compressed_size = payload.size();
  ci.uncompressed_size = records.size();
  put(h);
  put(payload);
  ci.chunk_length = offset_ - ci.chunk_start_offset;

  // One MessageIndex per channel, entries sorted by log time (write order
  // among equal times), right after the chunk.
  std::string mi;
  for (auto& [channel, entries] : c.index) {
    std::stable_sort(entries.begin(), entries.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    ci.message_index_offsets[channel] = offset_ + mi.size();
    const std::size_t mat = beginRecord(mi, Op::MessageIndex);
    putU16(mi, channel);
    putU32(mi, static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [t, off] : entries) {
      putU64(mi, t);
      putU64(mi, off);
    }
    endRecord(mi, mat);
  }
  ci.message_index_length = mi.size();
  put(mi);
  chunk_indexes_.push_back(std::move(ci));
  ++stats_.chunk_count;
  open_.erase(it);
}

void McapWriter::attach(const std::string& name, const std::string& media_type,
                        std::uint64_t log_time_ns, std::string_view data) {
  requireOpen("attach");
  std::string s;
  const std::size_t at = beginRecord(s, Op::Attachment);
  putU64(s, log_time_ns);
  putU64(s, 0);  // create_time: not available
  putStr(s, name);
  putStr(s, media_type);
  putU64(s, data.size());
  // the CRC covers every field before it: the content so far, then the data
  std::uint32_t crc = crc32(std::string_view(s).substr(at));
  crc = crc32(data, crc);
  patchU64(s, at - 8, s.size() - at + data.size() + 4);
  std::string tail;
  putU32(tail, crc);

  AttachmentIndex ai;
  ai.offset = offset_;
  ai.log_time = log_time_ns;
  ai.data_size = data.size();
  ai.name = name;
  ai.media_type = media_type;
  put(s);
  put(data);
  put(tail);
  ai.length = offset_ - ai.offset;
  attachment_indexes_.push_back(std::move(ai));
  ++stats_.attachment_count;
}

void McapWriter::metadata(const std::string& name, const std::map<std::string, std::string>& kv) {
  requireOpen("metadata");
  std::string s;
  const std::size_t at = beginRecord(s, Op::Metadata);
  putStr(s, name);
  putStringMap(s, kv);
  endRecord(s, at);
  MetadataIndex mi{offset_, s.size(), name};
  put(s);
  metadata_indexes_.push_back(std::move(mi));
  ++stats_.metadata_count;
}

void McapWriter::flush() {
  requireOpen("flush");
  while (!open_.empty()) closeChunk(open_.begin());
  if (std::fflush(file_) != 0) {
    failed_ = true;
    throw std::runtime_error("McapWriter: flushing " + path_ + ": " + std::strerror(errno));
  }
}

void McapWriter::writeSummary() {
  std::string d;
  const std::size_t dat = beginRecord(d, Op::DataEnd);
  putU32(d, crc_);  // everything before this record
  endRecord(d, dat);
  put(d);

  const std::uint64_t summary_start = offset_;
  crc_ = 0;  // from here: the summary CRC (summary .. footer's summary_offset_start)
  std::string offsets;  // the SummaryOffset records, one per group of records
  auto group = [&](Op op, const std::string& records) {
    if (records.empty()) return;
    const std::size_t at = beginRecord(offsets, Op::SummaryOffset);
    putU8(offsets, static_cast<std::uint8_t>(op));
    putU64(offsets, offset_);
    putU64(offsets, records.size());
    endRecord(offsets, at);
    put(records);
  };
  std::string s;
  for (const auto& r : schema_records_) s += r;
  group(Op::Schema, s);
  s.clear();
  for (const auto& r : channel_records_) s += r;
  group(Op::Channel, s);
  s.clear();
  for (std::size_t ch = 1; ch < channel_counts_.size(); ++ch)
    if (channel_counts_[ch] > 0)
      stats_.channel_message_counts[static_cast<std::uint16_t>(ch)] = channel_counts_[ch];
  encode(s, stats_);
  group(Op::Statistics, s);
  s.clear();
  for (const auto& c : chunk_indexes_) encode(s, c);
  group(Op::ChunkIndex, s);
  s.clear();
  for (const auto& a : attachment_indexes_) encode(s, a);
  group(Op::AttachmentIndex, s);
  s.clear();
  for (const auto& m : metadata_indexes_) encode(s, m);
  group(Op::MetadataIndex, s);

  const std::uint64_t summary_offset_start = offset_;
  put(offsets);
  std::string f;
  const std::size_t fat = beginRecord(f, Op::Footer);
  putU64(f, summary_start);
  putU64(f, summary_offset_start);
  endRecord(f, fat);
  patchU64(f, fat - 8, kFooterContent);
  put(f);
  std::string tail;
  putU32(tail, crc_);
  tail.append(kMagic);
  put(tail);
}

void McapWriter::close() {
  if (!file_) return;
  std::FILE* f = file_;
  if (failed_) {  // the tail is unknown: a summary would point into garbage
    file_ = nullptr;
    std::fclose(f);
    throw std::runtime_error("McapWriter::close: an earlier write to " + path_ +
                             " failed; the file has no summary");
  }
  try {
    flush();
    writeSummary();
  } catch (...) {
    file_ = nullptr;
    std::fclose(f);
    throw;
  }
  file_ = nullptr;
  if (std::fclose(f) != 0)
    throw std::runtime_error("McapWriter: closing " + path_ + ": " + std::strerror(errno));
}

}  // namespace groundsim::recording
