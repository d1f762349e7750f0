// McapReader: opening a file (header, footer, summary), its attachments and
// metadata, verify(). The scan of a file without a usable summary is in
// mcap_scan.cpp, chunks and readMessages() in mcap_chunks.cpp.
#include "recording/mcap_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "recording/crc32.hpp"
#include "recording/mcap_reader_detail.hpp"

namespace groundsim::recording {

using namespace mcap;
using namespace mcap_detail;  // the reader's own helpers (mcap_reader_detail.hpp)

namespace mcap_detail {

const char* opName(std::uint8_t op) {
  switch (static_cast<Op>(op)) {
    case Op::Header: return "Header";
    case Op::Footer: return "Footer";
    case Op::Schema: return "Schema";
    case Op::Channel: return "Channel";
    case Op::Message: return "Message";
    case Op::Chunk: return "Chunk";
    case Op::MessageIndex: return "MessageIndex";
    case Op::ChunkIndex: return "ChunkIndex";
    case Op::Attachment: return "Attachment";
    case Op::AttachmentIndex: return "AttachmentIndex";
    case Op::Statistics: return "Statistics";
    case Op::Metadata: return "Metadata";
    case Op::MetadataIndex: return "MetadataIndex";
    case Op::SummaryOffset: return "SummaryOffset";
    case Op::DataEnd: return "DataEnd";
  }
  return op >= 0x80 ? "private" : "unknown";
}

std::string hex(std::uint64_t v, int digits) {
  char b[24];
  std::snprintf(b, sizeof b, "0x%0*llx", digits, static_cast<unsigned long long>(v));
  return b;
}

}  // namespace mcap_detail

namespace {

ZSTD_DCtx* dctx(void* p) { return static_cast<ZSTD_DCtx*>(p); }

}  // namespace

McapReader::McapReader(const std::string& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error("McapReader: cannot open " + path + ": " + std::strerror(errno));
  try {
    struct stat st {};
    if (::fstat(fd_, &st) != 0) fail(std::string("fstat: ") + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) fail("not a regular file");
    size_ = static_cast<std::uint64_t>(st.st_size);
    withPath(path_, [&] {
      readHeader();
      if (readFooterAndSummary()) {
        complete_ = true;
        if (end_note_.empty()) end_note_ = "complete";
      }
    });
  } catch (...) {
    ::close(fd_);
    ZSTD_freeDCtx(dctx(zstd_));
    throw;
  }
}

McapReader::~McapReader() {
  if (fd_ >= 0) ::close(fd_);
  ZSTD_freeDCtx(dctx(zstd_));
}

void McapReader::fail(const std::string& why) const {
  throw std::runtime_error("McapReader: " + path_ + ": " + why);
}

void McapReader::readInto(char* dst, std::uint64_t offset, std::uint64_t n) const {
  while (n > 0) {
    const ssize_t got = ::pread(fd_, dst, static_cast<std::size_t>(std::min<std::uint64_t>(n, 1 << 30)),
                                static_cast<off_t>(offset));
    if (got < 0) {
      if (errno == EINTR) continue;
      fail("reading at offset " + num(offset) + ": " + std::strerror(errno));
    }
    if (got == 0) fail("the file ended at offset " + num(offset) + " while reading (did it shrink?)");
    dst += got;
    offset += static_cast<std::uint64_t>(got);
    n -= static_cast<std::uint64_t>(got);
    bytes_read_ += static_cast<std::uint64_t>(got);
  }
}

std::string McapReader::readAt(std::uint64_t offset, std::uint64_t n, const char* what) const {
  if (offset > size_ || n > size_ - offset)
    fail(std::string(what) + " at offset " + num(offset) + ": " + num(n) +
         " bytes run past the end of the file (" + num(size_) + " bytes)");
  if (n > kMaxLoadBytes)
    fail(std::string(what) + " at offset " + num(offset) + ": " + num(n) +
         " bytes, over the reader's 1 GiB limit for one record");
  std::string s(static_cast<std::size_t>(n), '\0');
  readInto(s.data(), offset, n);
  return s;
}

void McapReader::readHeader() {
  if (size_ == 0) fail("empty file (0 bytes), not an MCAP file");
  if (size_ < kMagic.size())
    fail("not an MCAP file: " + num(size_) + " bytes, shorter than the 8-byte magic");
  const std::string m = readAt(0, kMagic.size(), "magic");
  if (m != kMagic) {
    if (m.compare(0, 5, kMagic.substr(0, 5)) == 0)
      fail("unsupported MCAP major version byte " + hex(static_cast<unsigned char>(m[5])) +
           " (this reader reads version '0', 0x30)");
    fail("not an MCAP file (bad magic at offset 0)");
  }
  const std::uint64_t at = kMagic.size();
  if (size_ < at + kRecordPrefix)
    fail("truncated header: the file ends at byte " + num(size_) + ", inside the Header record at offset 8");
  const std::string p = readAt(at, kRecordPrefix, "Header");
  if (static_cast<std::uint8_t>(p[0]) != static_cast<std::uint8_t>(Op::Header))
    fail("the record at offset 8 has opcode " + hex(static_cast<unsigned char>(p[0])) + " (" +
         opName(static_cast<std::uint8_t>(p[0])) + "), not a Header");
  const std::uint64_t len = loadU64(p.data() + 1);
  if (len > size_ - at - kRecordPrefix)
    fail("truncated header: the Header record at offset 8 claims " + num(len) +
         " content bytes, the file has " + num(size_ - at - kRecordPrefix) + " after it");
  const std::string body = readAt(at + kRecordPrefix, len, "Header");
  Cursor c(body, "Header", at);
  c.str();  // profile
  c.str();  // library
  data_start_ = at + kRecordPrefix + len;
}

bool McapReader::readFooterAndSummary() {
  const std::uint64_t tail = kFooterRecord + kMagic.size();
  if (size_ < data_start_ + tail) {
    scan(size_);
    end_note_ = "incomplete: no footer; " + end_note_;
    return false;
  }
  const std::uint64_t footer_at = size_ - tail;
  const std::string t = readAt(footer_at, tail, "Footer");
  if (std::string_view(t).substr(kFooterRecord) != kMagic) {
    scan(size_);
    end_note_ = "incomplete: no footer; " + end_note_;
    return false;
  }
  if (static_cast<std::uint8_t>(t[0]) != static_cast<std::uint8_t>(Op::Footer) ||
      loadU64(t.data() + 1) != kFooterContent)
    fail("the file ends with the magic but holds no Footer record before it (offset " + num(footer_at) +
         ")");
  const std::uint64_t summary_start = loadU64(t.data() + 9);
  const std::uint64_t summary_offset_start = loadU64(t.data() + 17);
  const std::uint32_t summary_crc = loadU32(t.data() + 25);
  if (summary_start == 0) {
    scan(footer_at);
    end_note_ = "unindexed: the footer has no summary, read by scanning; " + end_note_;
    return false;
  }
  if (summary_start < data_start_ + kDataEndRecord || summary_start > footer_at)
    fail("Footer at offset " + num(footer_at) + ": summary_start " + num(summary_start) +
         " is not between the header's end (" + num(data_start_) + ") and the footer");
  if (summary_offset_start != 0 && (summary_offset_start < summary_start || summary_offset_start > footer_at))
    fail("Footer at offset " + num(footer_at) + ": summary_offset_start " + num(summary_offset_start) +
         " is not between summary_start and the footer");
  const std::string summary = readAt(summary_start, footer_at - summary_start, "summary section");
  if (summary_crc != 0) {
    // the summary, the summary offsets and the footer up to its crc field
    const std::uint32_t got = crc32(std::string_view(t).substr(0, 25), crc32(summary));
    if (got != summary_crc)
      fail("summary CRC mismatch: the footer at offset " + num(footer_at) + " stores " + hex(summary_crc, 8) +
           ", the summary gives " + hex(got, 8));
  }
  const std::uint64_t summary_end = summary_offset_start ? summary_offset_start : footer_at;
  parseSummary(summary.substr(0, summary_end - summary_start), summary_start);
  data_end_offset_ = summary_start - kDataEndRecord;  // the spec puts DataEnd right before
  if (refs_.empty() && (!have_statistics_ || statistics_.message_count > 0)) {
    // no chunk index (other writers' unchunked files): the messages are
    // found by scanning; the summary's attachment and metadata indexes stay
    auto attachments = std::move(attachment_refs_);
    auto metadata = std::move(metadata_refs_);
    attachment_refs_.clear();
    metadata_refs_.clear();
    scan(data_end_offset_);
    if (!attachments.empty()) attachment_refs_ = std::move(attachments);
    if (!metadata.empty()) metadata_refs_ = std::move(metadata);
    end_note_ = "complete, without chunk index: read by scanning; " + end_note_;
  }
  return true;
}

void McapReader::addSchema(Cursor& c) {
  McapSchemaInfo s;
  s.id = c.u16();
  s.name = std::string(c.str());
  s.encoding = std::string(c.str());
  s.data = std::string(c.str());
  if (s.id != 0) schemas_.try_emplace(s.id, std::move(s));  // id 0 is invalid: ignored
}

void McapReader::addChannel(Cursor& c) {
  McapChannelInfo ch;
  ch.id = c.u16();
  ch.schema_id = c.u16();
  ch.topic = std::string(c.str());
  ch.message_encoding = std::string(c.str());
  ch.metadata = c.stringMap();
  channels_.try_emplace(ch.id, std::move(ch));
}

void McapReader::parseSummary(const std::string& s, std::uint64_t base) {
  std::size_t pos = 0;
  auto inData = [&](std::uint64_t offset, std::uint64_t length) {
    return offset >= data_start_ && length >= kRecordPrefix && offset <= base && length <= base - offset;
  };
  while (pos < s.size()) {
    const std::uint64_t at = base + pos;
    if (s.size() - pos < kRecordPrefix)
      fail("summary record at offset " + num(at) + " is cut (" + num(s.size() - pos) + " bytes)");
    const auto op = static_cast<std::uint8_t>(s[pos]);
    const std::uint64_t len = loadU64(s.data() + pos + 1);
    if (len > s.size() - pos - kRecordPrefix)
      fail(std::string(opName(op)) + " record at offset " + num(at) + " claims " + num(len) +
           " bytes, past the end of the summary");
    Cursor c(std::string_view(s).substr(pos + kRecordPrefix, static_cast<std::size_t>(len)), opName(op), at);
    switch (static_cast<Op>(op)) {
      case Op::Schema: addSchema(c); break;
      case Op::Channel: addChannel(c); break;
      case Op::ChunkIndex: {
        const ChunkIndex ci = decodeChunkIndex(c);
        if (!inData(ci.chunk_start_offset, ci.chunk_length))
          c.fail("the chunk (offset " + num(ci.chunk_start_offset) + ", " + num(ci.chunk_length) +
                 " bytes) is not inside the data section");
        ChunkRef r;
        r.offset = ci.chunk_start_offset;
        r.length = ci.chunk_length;
        r.start = ci.message_start_time;
        r.end = ci.message_end_time;
        r.compression = ci.compression;
        r.compressed_size = ci.compressed_size;
        r.uncompressed_size = ci.uncompressed_size;
        r.index_offsets = ci.message_index_offsets;
        r.indexed = !r.index_offsets.empty();
        refs_.push_back(std::move(r));
        break;
      }
      case Op::AttachmentIndex: {
        AttachmentIndex a = decodeAttachmentIndex(c);
        if (!inData(a.offset, a.length))
          c.fail("the attachment (offset " + num(a.offset) + ", " + num(a.length) +
                 " bytes) is not inside the data section");
        attachment_refs_.push_back(std::move(a));
        break;
      }
      case Op::MetadataIndex: {
        MetadataIndex m = decodeMetadataIndex(c);
        if (!inData(m.offset, m.length))
          c.fail("the metadata (offset " + num(m.offset) + ", " + num(m.length) +
                 " bytes) is not inside the data section");
        metadata_refs_.push_back(std::move(m));
        break;
      }
      case Op::Statistics:
        statistics_ = decodeStatistics(c);
        have_statistics_ = true;
        break;
      default: break;  // summary offsets, records of later versions, private records
    }
    pos += kRecordPrefix + static_cast<std::size_t>(len);
  }
}

std::vector<std::pair<std::string, std::string>> McapReader::attachments() {
  return withPath(path_, [&] {
    std::vector<std::pair<std::string, std::string>> out;
    for (const auto& a : attachment_refs_) {
      const std::string raw = readAt(a.offset, a.length, "Attachment");
      if (raw.size() < kRecordPrefix ||
          static_cast<std::uint8_t>(raw[0]) != static_cast<std::uint8_t>(Op::Attachment) ||
          loadU64(raw.data() + 1) != a.length - kRecordPrefix)
        fail("no Attachment record of " + num(a.length) + " bytes at offset " + num(a.offset));
      const std::string_view body = std::string_view(raw).substr(kRecordPrefix);
      Cursor c(body, "Attachment", a.offset);
      c.u64();  // log_time
      c.u64();  // create_time
      std::string name(c.str());
      c.str();  // media_type
      std::string data(c.bytes(c.u64(), "data"));
      const std::size_t covered = c.position();
      const std::uint32_t crc = c.u32();
      if (crc != 0) {
        const std::uint32_t got = crc32(body.substr(0, covered));
        if (got != crc)
          fail("attachment '" + name + "' at offset " + num(a.offset) + ": CRC mismatch (stored " + hex(crc, 8) +
               ", computed " + hex(got, 8) + ")");
      }
      out.emplace_back(std::move(name), std::move(data));
    }
    return out;
  });
}

std::map<std::string, std::map<std::string, std::string>> McapReader::metadata() {
  return withPath(path_, [&] {
    std::map<std::string, std::map<std::string, std::string>> out;
    for (const auto& m : metadata_refs_) {
      const std::string raw = readAt(m.offset, m.length, "Metadata");
      if (raw.size() < kRecordPrefix || static_cast<std::uint8_t>(raw[0]) != static_cast<std::uint8_t>(Op::Metadata) ||
          loadU64(raw.data() + 1) != m.length - kRecordPrefix)
        fail("no Metadata record of " + num(m.length) + " bytes at offset " + num(m.offset));
      Cursor c(std::string_view(raw).substr(kRecordPrefix), "Metadata", m.offset);
      std::string name(c.str());
      out[std::move(name)] = c.stringMap();
    }
    return out;
  });
}

std::vector<McapChunkInfo> McapReader::chunks() const {
  std::vector<McapChunkInfo> out;
  for (const auto& r : refs_) {
    if (r.loose) continue;
    McapChunkInfo c;
    c.offset = r.offset;
    c.length = r.length;
    c.message_start_time = r.start;
    c.message_end_time = r.end;
    c.compression = r.compression;
    c.compressed_size = r.compressed_size;
    c.uncompressed_size = r.uncompressed_size;
    if (r.indexed)
      for (const auto& kv : r.index_offsets) c.channels.push_back(kv.first);
    out.push_back(std::move(c));
  }
  return out;
}

void McapReader::verify() {
  withPath(path_, [&] {
    if (data_end_offset_ != 0) {
      const std::string d = readAt(data_end_offset_, kDataEndRecord, "DataEnd");
      if (static_cast<std::uint8_t>(d[0]) != static_cast<std::uint8_t>(Op::DataEnd) ||
          loadU64(d.data() + 1) != 4)
        fail("no DataEnd record at offset " + num(data_end_offset_) + ", right before the summary");
      const std::uint32_t stored = loadU32(d.data() + 9);
      if (stored != 0) {
        std::uint32_t crc = 0;
        std::string block(std::min<std::uint64_t>(data_end_offset_, 4 << 20), '\0');
        for (std::uint64_t at = 0; at < data_end_offset_;) {
          const std::uint64_t n = std::min<std::uint64_t>(block.size(), data_end_offset_ - at);
          readInto(block.data(), at, n);
          crc = crc32(block.data(), static_cast<std::size_t>(n), crc);
          at += n;
        }
        if (crc != stored)
          fail("data section CRC mismatch: DataEnd at offset " + num(data_end_offset_) + " stores " +
               hex(stored, 8) + ", the bytes before it give " + hex(crc, 8));
      }
    }
    for (const auto& r : refs_) {
      if (r.loose) continue;
      Loaded l;
      loadChunk(r, l);
    }
  });
  attachments();
}

}  // namespace groundsim::recording
