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

namespace groundsim::recording {

using namespace mcap;

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

namespace {

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

std::string hex(std::uint64_t v, int digits = 2) {
  char b[24];
  std::snprintf(b, sizeof b, "0x%0*llx", digits, static_cast<unsigned long long>(v));
  return b;
}

std::string num(std::uint64_t v) { return std::to_string(v); }

ZSTD_DCtx* dctx(void* p) { return static_cast<ZSTD_DCtx*>(p); }

// What the zstd frames in [p, p + n) say they decompress to, read from their
// headers (ZSTD_findDecompressedSize is not in zstd's stable API):
// ZSTD_CONTENTSIZE_ERROR when they are not frames, ..._UNKNOWN when a frame
// does not say.
unsigned long long zstdContentSize(const char* p, std::size_t n) {
  unsigned long long total = 0;
  while (n > 0) {
    const unsigned long long frame = ZSTD_getFrameContentSize(p, n);
    if (frame == ZSTD_CONTENTSIZE_ERROR) return ZSTD_CONTENTSIZE_ERROR;
    const std::size_t length = ZSTD_findFrameCompressedSize(p, n);
    if (ZSTD_isError(length) || length == 0 || length > n) return ZSTD_CONTENTSIZE_ERROR;
    if (frame == ZSTD_CONTENTSIZE_UNKNOWN) return ZSTD_CONTENTSIZE_UNKNOWN;
    if (frame > ~0ull - total) return ZSTD_CONTENTSIZE_ERROR;
    total += frame;
    p += length;
    n -= length;
  }
  return total;
}

// Runs f, giving format errors (mcap::Cursor's) the file's path.
template <class F>
auto withPath(const std::string& path, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const FormatError& e) {
    throw std::runtime_error("McapReader: " + path + ": " + e.what());
  }
}

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

void McapReader::scan(std::uint64_t end) {
  std::uint64_t pos = data_start_;
  std::size_t pending = SIZE_MAX;  // the last chunk, while its MessageIndex records follow
  std::string stop;
  std::size_t loose = 0;
  while (pos < end) {
    if (end - pos < kRecordPrefix) {
      stop = num(end - pos) + " bytes of a cut record ignored (offset " + num(pos) + ")";
      break;
    }
    const std::string p = readAt(pos, kRecordPrefix, "record");
    const auto op = static_cast<std::uint8_t>(p[0]);
    const std::uint64_t len = loadU64(p.data() + 1);
    if (op == 0) {  // not a record: e.g. the zeros a crash can leave in a file's last blocks
      stop = num(end - pos) + " bytes from offset " + num(pos) + " ignored (opcode 0 is not a record)";
      break;
    }
    if (len > end - pos - kRecordPrefix) {
      stop = num(end - pos) + " bytes of a cut record ignored (" + opName(op) + " at offset " + num(pos) +
             ", claims " + num(len) + " bytes)";
      break;
    }
    const std::uint64_t body = pos + kRecordPrefix;
    if (pending != SIZE_MAX && op != static_cast<std::uint8_t>(Op::MessageIndex)) {
      // a record after the chunk's indexes: they are all there
      ChunkRef& r = refs_[pending];
      r.indexed = r.counts_known = !r.index_offsets.empty();
      pending = SIZE_MAX;
    }
    bool data_end = false;
    switch (static_cast<Op>(op)) {
      case Op::Schema:
      case Op::Channel: {
        const std::string b = readAt(body, len, opName(op));
        Cursor c(b, opName(op), pos);
        op == static_cast<std::uint8_t>(Op::Schema) ? addSchema(c) : addChannel(c);
        break;
      }
      case Op::Chunk: {
        // start, end, uncompressed_size, crc, compression length: 32 bytes
        if (len < 32 + 8) Cursor(std::string_view(), "Chunk", pos).fail("too short (" + num(len) + " bytes)");
        const std::string h = readAt(body, 32, "Chunk");
        const std::uint32_t clen = loadU32(h.data() + 28);
        if (clen > len - 40) Cursor(std::string_view(), "Chunk", pos).fail("compression string runs past the record");
        const std::string comp = readAt(body + 32, clen + 8, "Chunk");
        const std::uint64_t records = loadU64(comp.data() + clen);
        if (records != len - 40 - clen)
          Cursor(std::string_view(), "Chunk", pos)
              .fail("records field of " + num(records) + " bytes does not fill the record");
        ChunkRef r;
        r.offset = pos;
        r.length = kRecordPrefix + len;
        r.start = loadU64(h.data());
        r.end = loadU64(h.data() + 8);
        r.uncompressed_size = loadU64(h.data() + 16);
        r.compression = comp.substr(0, clen);
        r.compressed_size = records;
        refs_.push_back(std::move(r));
        pending = refs_.size() - 1;
        break;
      }
      case Op::MessageIndex: {
        if (pending == SIZE_MAX) break;  // not after a chunk: nothing to index
        if (len < 6) Cursor(std::string_view(), "MessageIndex", pos).fail("too short");
        const std::string h = readAt(body, 6, "MessageIndex");
        const std::uint32_t bytes = loadU32(h.data() + 2);
        if (bytes > len - 6 || bytes % 16 != 0)
          Cursor(std::string_view(), "MessageIndex", pos).fail("entries of " + num(bytes) + " bytes do not fit");
        ChunkRef& r = refs_[pending];
        r.index_offsets[loadU16(h.data())] = pos;
        r.counts[loadU16(h.data())] += bytes / 16;
        break;
      }
      case Op::Message: {
        if (len < kMessageFixed) Cursor(std::string_view(), "Message", pos).fail("too short");
        const std::string h = readAt(body, kMessageFixed, "Message");
        ChunkRef r;
        r.offset = pos;
        r.length = kRecordPrefix + len;
        r.start = r.end = loadU64(h.data() + 6);
        r.loose = true;
        r.loose_channel = loadU16(h.data());
        refs_.push_back(std::move(r));
        ++loose;
        break;
      }
      case Op::Attachment: {
        AttachmentIndex a;
        a.offset = pos;
        a.length = kRecordPrefix + len;
        attachment_refs_.push_back(std::move(a));
        break;
      }
      case Op::Metadata: {
        MetadataIndex m;
        m.offset = pos;
        m.length = kRecordPrefix + len;
        metadata_refs_.push_back(std::move(m));
        break;
      }
      case Op::DataEnd:
        data_end_offset_ = pos;
        data_end = true;
        break;
      default: break;  // records of later versions, private records: skipped
    }
    pos = body + len;
    if (data_end) {
      stop = "the data section is whole (DataEnd at offset " + num(data_end_offset_) + "), the summary is not";
      break;
    }
  }
  // pending: nothing followed the last chunk's indexes, so the end may have
  // cut some; it is read as unindexed (decompressed to filter and count)

  std::size_t whole = 0;
  std::uint64_t last = 0;
  for (const auto& r : refs_) {
    if (r.loose) continue;
    ++whole;
    last = std::max(last, r.end);
  }
  char t[64];
  std::snprintf(t, sizeof t, "%.2f", static_cast<double>(last) * 1e-9);
  end_note_ = num(whole) + (whole == 1 ? " whole chunk" : " whole chunks");
  if (whole > 0) end_note_ += std::string(" up to log time ") + t + " s";
  if (loose > 0) end_note_ += ", " + num(loose) + " messages outside chunks";
  if (!stop.empty()) end_note_ += ", " + stop;
}

std::string_view McapReader::loadChunk(const ChunkRef& r, Loaded& out) const {
  out.raw = readAt(r.offset, r.length, "Chunk");
  const std::string& raw = out.raw;
  if (raw.size() < kRecordPrefix || static_cast<std::uint8_t>(raw[0]) != static_cast<std::uint8_t>(Op::Chunk))
    fail("no Chunk record at offset " + num(r.offset) + " (opcode " +
         hex(raw.empty() ? 0 : static_cast<unsigned char>(raw[0])) + ")");
  if (loadU64(raw.data() + 1) != r.length - kRecordPrefix)
    fail("Chunk record at offset " + num(r.offset) + ": its length does not match its index");
  Cursor c(std::string_view(raw).substr(kRecordPrefix), "Chunk", r.offset);
  c.u64();  // message_start_time
  c.u64();  // message_end_time
  const std::uint64_t usize = c.u64();
  const std::uint32_t crc = c.u32();
  const std::string_view compression = c.str();
  const std::string_view records = c.bytes(c.u64(), "records");
  if (usize > kMaxLoadBytes)
    fail("chunk at offset " + num(r.offset) + ": uncompressed_size " + num(usize) +
         " is over the reader's 1 GiB limit");
  if (compression.empty()) {
    if (records.size() != usize)
      fail("chunk at offset " + num(r.offset) + ": uncompressed, but " + num(records.size()) +
           " bytes of records against an uncompressed_size of " + num(usize));
    out.records = records;
  } else if (compression == "zstd") {
    const unsigned long long stated = zstdContentSize(records.data(), records.size());
    if (stated == ZSTD_CONTENTSIZE_ERROR)
      fail("chunk at offset " + num(r.offset) + ": its records are not zstd frames");
    if (stated != ZSTD_CONTENTSIZE_UNKNOWN && stated != usize)
      fail("chunk at offset " + num(r.offset) + ": the zstd frames hold " + num(stated) +
           " bytes, uncompressed_size says " + num(usize));
    if (!zstd_) {
      zstd_ = ZSTD_createDCtx();
      if (!zstd_) fail("ZSTD_createDCtx failed");
    }
    // not zero-filled: the pages are touched only as zstd writes them, so a
    // lying uncompressed_size costs address space, not memory
    out.decompressed.reset(new char[usize > 0 ? usize : 1]);
    const std::size_t n =
        ZSTD_decompressDCtx(dctx(zstd_), out.decompressed.get(), usize, records.data(), records.size());
    if (ZSTD_isError(n))
      fail("chunk at offset " + num(r.offset) + ": zstd: " + ZSTD_getErrorName(n) + " (corrupt chunk)");
    if (n != usize)
      fail("chunk at offset " + num(r.offset) + ": decompressed to " + num(n) + " bytes, uncompressed_size says " +
           num(usize));
    out.records = std::string_view(out.decompressed.get(), usize);
  } else {
    fail("chunk at offset " + num(r.offset) + ": compression '" + std::string(compression) +
         "' is not supported (zstd or none)");
  }
  if (crc != 0) {
    const std::uint32_t got = crc32(out.records);
    if (got != crc)
      fail("chunk at offset " + num(r.offset) + ": CRC mismatch (stored " + hex(crc, 8) + ", computed " +
           hex(got, 8) + "): the chunk is corrupt");
  }
  return out.records;
}

std::vector<std::pair<std::uint64_t, std::uint64_t>> McapReader::readMessageIndex(std::uint64_t offset,
                                                                                  std::uint16_t channel) const {
  const std::string p = readAt(offset, kRecordPrefix, "MessageIndex");
  if (static_cast<std::uint8_t>(p[0]) != static_cast<std::uint8_t>(Op::MessageIndex))
    fail("the index of channel " + num(channel) + " points at offset " + num(offset) +
         ", which holds no MessageIndex record");
  const std::string b = readAt(offset + kRecordPrefix, loadU64(p.data() + 1), "MessageIndex");
  Cursor c(b, "MessageIndex", offset);
  if (c.u16() != channel) c.fail("it is not channel " + num(channel) + "'s, as the chunk index says");
  const std::uint32_t bytes = c.u32();
  if (bytes % 16 != 0) c.fail("entries of " + num(bytes) + " bytes, not a multiple of 16");
  const std::string_view e = c.bytes(bytes, "entries");
  std::vector<std::pair<std::uint64_t, std::uint64_t>> out(bytes / 16);
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = {loadU64(e.data() + 16 * i), loadU64(e.data() + 16 * i + 8)};
  return out;
}

std::map<std::uint16_t, std::uint64_t> McapReader::countChunk(const ChunkRef& r) const {
  if (r.loose) return {{r.loose_channel, 1}};
  if (r.counts_known) return r.counts;
  std::map<std::uint16_t, std::uint64_t> out;
  if (r.indexed) {  // the index headers say it: 15 bytes a channel
    for (const auto& [ch, off] : r.index_offsets) {
      const std::string h = readAt(off, kRecordPrefix + 6, "MessageIndex");
      if (static_cast<std::uint8_t>(h[0]) != static_cast<std::uint8_t>(Op::MessageIndex) ||
          loadU16(h.data() + 9) != ch)
        fail("the index of channel " + num(ch) + " points at offset " + num(off) +
             ", which holds no MessageIndex record of that channel");
      out[ch] += loadU32(h.data() + 11) / 16;
    }
    return out;
  }
  Loaded l;
  const std::string_view recs = loadChunk(r, l);
  for (std::size_t pos = 0; pos < recs.size();) {
    if (recs.size() - pos < kRecordPrefix) fail("chunk at offset " + num(r.offset) + ": a cut record inside it");
    const std::uint64_t len = loadU64(recs.data() + pos + 1);
    if (len > recs.size() - pos - kRecordPrefix)
      fail("chunk at offset " + num(r.offset) + ": a record inside it runs past its records");
    if (static_cast<std::uint8_t>(recs[pos]) == static_cast<std::uint8_t>(Op::Message)) {
      if (len < kMessageFixed) fail("chunk at offset " + num(r.offset) + ": a Message record too short");
      ++out[loadU16(recs.data() + pos + kRecordPrefix)];
    }
    pos += kRecordPrefix + static_cast<std::size_t>(len);
  }
  return out;
}

std::map<std::uint16_t, std::uint64_t> McapReader::messageCounts() const {
  if (complete_ && have_statistics_ && !statistics_.channel_message_counts.empty())
    return statistics_.channel_message_counts;
  if (!counted_) {
    withPath(path_, [&] {
      std::map<std::uint16_t, std::uint64_t> counts;
      for (const auto& r : refs_)
        for (const auto& [ch, n] : countChunk(r)) counts[ch] += n;
      counts_ = std::move(counts);
    });
    counted_ = true;
  }
  return counts_;
}

void McapReader::readMessages(const std::function<void(const McapMessage&)>& f,
                              const std::set<std::uint16_t>& channels, std::uint64_t t0, std::uint64_t t1) {
  withPath(path_, [&] {
    if (t0 > t1) return;
    auto wanted = [&](std::uint16_t ch) { return channels.empty() || channels.count(ch) > 0; };
    std::vector<const ChunkRef*> sel;
    for (const auto& r : refs_) {
      if (r.end < t0 || r.start > t1) continue;
      if (r.loose && !wanted(r.loose_channel)) continue;
      if (!r.loose && !channels.empty() && r.indexed &&
          std::none_of(r.index_offsets.begin(), r.index_offsets.end(),
                       [&](const auto& kv) { return channels.count(kv.first) > 0; }))
        continue;
      sel.push_back(&r);
    }
    std::stable_sort(sel.begin(), sel.end(), [](const ChunkRef* a, const ChunkRef* b) {
      return a->start != b->start ? a->start < b->start : a->offset < b->offset;
    });

    // The entries of one chunk to deliver, or nullptr: nothing in it.
    auto load = [&](const ChunkRef& r) -> std::unique_ptr<Loaded> {
      auto l = std::make_unique<Loaded>();
      l->order = r.offset;
      auto keep = [&](std::uint16_t ch, std::uint64_t t) { return wanted(ch) && t >= t0 && t <= t1; };
      if (r.loose) {
        l->raw = readAt(r.offset, r.length, "Message");
        l->records = l->raw;
        if (keep(r.loose_channel, r.start)) l->entries.emplace_back(r.start, 0);
      } else if (!channels.empty() && r.indexed) {
        // the wanted channels' message indexes first: a chunk may be skipped
        // without decompressing it
        for (const auto& [ch, off] : r.index_offsets) {
          if (!channels.count(ch)) continue;
          for (const auto& e : readMessageIndex(off, ch))
            if (e.first >= t0 && e.first <= t1) l->entries.push_back(e);
        }
        if (l->entries.empty()) return nullptr;
        loadChunk(r, *l);
      } else {
        const std::string_view recs = loadChunk(r, *l);
        for (std::size_t pos = 0; pos < recs.size();) {
          if (recs.size() - pos < kRecordPrefix)
            fail("chunk at offset " + num(r.offset) + ": a cut record at offset " + num(pos) + " inside it");
          const auto op = static_cast<std::uint8_t>(recs[pos]);
          const std::uint64_t len = loadU64(recs.data() + pos + 1);
          if (len > recs.size() - pos - kRecordPrefix)
            fail("chunk at offset " + num(r.offset) + ": the record at offset " + num(pos) +
                 " inside it runs past its records");
          const std::string_view body = recs.substr(pos + kRecordPrefix, static_cast<std::size_t>(len));
          if (op == static_cast<std::uint8_t>(Op::Message)) {
            if (len < kMessageFixed)
              fail("chunk at offset " + num(r.offset) + ": a Message record too short at offset " + num(pos));
            const std::uint64_t t = loadU64(body.data() + 6);
            if (keep(loadU16(body.data()), t)) l->entries.emplace_back(t, pos);
          } else if (op == static_cast<std::uint8_t>(Op::Schema) || op == static_cast<std::uint8_t>(Op::Channel)) {
            Cursor c(body, opName(op), r.offset);  // other writers put them in chunks
            op == static_cast<std::uint8_t>(Op::Schema) ? addSchema(c) : addChannel(c);
          }
          pos += kRecordPrefix + static_cast<std::size_t>(len);
        }
        if (l->entries.empty()) return nullptr;
      }
      std::sort(l->entries.begin(), l->entries.end());
      return l;
    };

    // a min-heap of the loaded chunks by their next message
    auto later = [](const std::unique_ptr<Loaded>& a, const std::unique_ptr<Loaded>& b) {
      const auto& ea = a->entries[a->next];
      const auto& eb = b->entries[b->next];
      if (ea.first != eb.first) return ea.first > eb.first;
      if (a->order != b->order) return a->order > b->order;
      return ea.second > eb.second;
    };
    std::vector<std::unique_ptr<Loaded>> heap;
    McapMessage m;
    std::size_t next = 0;
    while (next < sel.size() || !heap.empty()) {
      // a chunk that may hold the next message in time is loaded first
      if (next < sel.size() &&
          (heap.empty() || sel[next]->start <= heap.front()->entries[heap.front()->next].first)) {
        if (auto l = load(*sel[next])) {
          heap.push_back(std::move(l));
          std::push_heap(heap.begin(), heap.end(), later);
        }
        ++next;
        continue;
      }
      std::pop_heap(heap.begin(), heap.end(), later);
      Loaded& l = *heap.back();
      const auto [t, off] = l.entries[l.next];
      const std::string_view recs = l.records;
      if (off > recs.size() || recs.size() - off < kRecordPrefix + kMessageFixed ||
          static_cast<std::uint8_t>(recs[off]) != static_cast<std::uint8_t>(Op::Message))
        fail("chunk at offset " + num(l.order) + ": no Message record at offset " + num(off) +
             " inside it, where its message index points");
      const std::uint64_t len = loadU64(recs.data() + off + 1);
      if (len < kMessageFixed || len > recs.size() - off - kRecordPrefix)
        fail("chunk at offset " + num(l.order) + ": the Message record at offset " + num(off) +
             " inside it runs past its records");
      const char* b = recs.data() + off + kRecordPrefix;
      m.channel = loadU16(b);
      m.sequence = loadU32(b + 2);
      m.log_time = loadU64(b + 6);
      m.publish_time = loadU64(b + 14);
      if (m.log_time != t || !wanted(m.channel))
        fail("chunk at offset " + num(l.order) + ": the message at offset " + num(off) +
             " inside it does not match its message index entry");
      m.data.assign(b + kMessageFixed, static_cast<std::size_t>(len - kMessageFixed));
      if (++l.next < l.entries.size())
        std::push_heap(heap.begin(), heap.end(), later);
      else
        heap.pop_back();  // frees the chunk
      f(m);
    }
  });
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
