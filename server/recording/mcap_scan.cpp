// McapReader::scan(): a file without a usable summary (a crashed or cut
// file, or an unchunked one) read by walking its data section's record
// headers once: chunks and loose messages become ChunkRefs, attachments and
// metadata their index entries, schemas and channels are read whole.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>

#include "recording/mcap_reader.hpp"
#include "recording/mcap_reader_detail.hpp"

namespace groundsim::recording {

using namespace mcap;
using namespace mcap_detail;  // the reader's own helpers (mcap_reader_detail.hpp)

class McapReader::Scanner {
 public:
  Scanner(McapReader& reader, std::uint64_t end) : r_(reader), end_(end), pos_(reader.data_start_) {}

  void run() {
    while (pos_ < end_ && nextRecord()) {
    }
    // pending_: nothing followed the last chunk's indexes, so the end may have
    // cut some; it is read as unindexed (decompressed to filter and count)
    r_.end_note_ = note();
  }

 private:
  // Reads the record at pos_ and moves past it. False: the scan stops here
  // (stop_ says why).
  bool nextRecord() {
    std::uint8_t op = 0;
    std::uint64_t len = 0;
    if (!readPrefix(op, len)) return false;
    if (pending_ != SIZE_MAX && op != static_cast<std::uint8_t>(Op::MessageIndex)) closePendingChunk();
    const bool data_end = take(op, len);
    pos_ += kRecordPrefix + len;
    if (data_end) {
      stop_ = "the data section is whole (DataEnd at offset " + num(r_.data_end_offset_) + "), the summary is not";
      return false;
    }
    return true;
  }

  // The opcode and content length of the record at pos_. False: no whole
  // record there.
  bool readPrefix(std::uint8_t& op, std::uint64_t& len) {
    if (end_ - pos_ < kRecordPrefix) {
      stop_ = num(end_ - pos_) + " bytes of a cut record ignored (offset " + num(pos_) + ")";
      return false;
    }
    const std::string p = r_.readAt(pos_, kRecordPrefix, "record");
    op = static_cast<std::uint8_t>(p[0]);
    len = loadU64(p.data() + 1);
    if (op == 0) {  // not a record: e.g. the zeros a crash can leave in a file's last blocks
      stop_ = num(end_ - pos_) + " bytes from offset " + num(pos_) + " ignored (opcode 0 is not a record)";
      return false;
    }
    if (len > end_ - pos_ - kRecordPrefix) {
      stop_ = num(end_ - pos_) + " bytes of a cut record ignored (" + opName(op) + " at offset " + num(pos_) +
              ", claims " + num(len) + " bytes)";
      return false;
    }
    return true;
  }

  // A record after the chunk's indexes: they are all there.
  void closePendingChunk() {
    ChunkRef& r = r_.refs_[pending_];
    r.indexed = r.counts_known = !r.index_offsets.empty();
    pending_ = SIZE_MAX;
  }

  // Takes the record at pos_ into the reader. True: it was the DataEnd.
  bool take(std::uint8_t op, std::uint64_t len) {
    switch (static_cast<Op>(op)) {
      case Op::Schema:
      case Op::Channel: schemaOrChannel(op, len); break;
      case Op::Chunk: chunk(len); break;
      case Op::MessageIndex: messageIndex(len); break;
      case Op::Message: message(len); break;
      // where the whole record stands (a scan reads no name)
      case Op::Attachment: r_.attachment_refs_.push_back({.offset = pos_, .length = kRecordPrefix + len}); break;
      case Op::Metadata: r_.metadata_refs_.push_back({.offset = pos_, .length = kRecordPrefix + len}); break;
      case Op::DataEnd:
        r_.data_end_offset_ = pos_;
        return true;
      default: break;  // records of later versions, private records: skipped
    }
    return false;
  }

  std::uint64_t body() const { return pos_ + kRecordPrefix; }
  [[noreturn]] void fail(const char* record, const std::string& why) const {
    Cursor(std::string_view(), record, pos_).fail(why);
  }

  void schemaOrChannel(std::uint8_t op, std::uint64_t len) {
    const std::string b = r_.readAt(body(), len, opName(op));
    Cursor c(b, opName(op), pos_);
    op == static_cast<std::uint8_t>(Op::Schema) ? r_.addSchema(c) : r_.addChannel(c);
  }

  void chunk(std::uint64_t len) {
    // start, end, uncompressed_size, crc, compression length: 32 bytes
    if (len < 32 + 8) fail("Chunk", "too short (" + num(len) + " bytes)");
    const std::string h = r_.readAt(body(), 32, "Chunk");
    const std::uint32_t clen = loadU32(h.data() + 28);
    if (clen > len - 40) fail("Chunk", "compression string runs past the record");
    const std::string comp = r_.readAt(body() + 32, clen + 8, "Chunk");
    const std::uint64_t records = loadU64(comp.data() + clen);
    if (records != len - 40 - clen) fail("Chunk", "records field of " + num(records) + " bytes does not fill the record");
    ChunkRef r;
    r.offset = pos_;
    r.length = kRecordPrefix + len;
    r.start = loadU64(h.data());
    r.end = loadU64(h.data() + 8);
    r.uncompressed_size = loadU64(h.data() + 16);
    r.compression = comp.substr(0, clen);
    r.compressed_size = records;
    r_.refs_.push_back(std::move(r));
    pending_ = r_.refs_.size() - 1;
  }

  void messageIndex(std::uint64_t len) {
    if (pending_ == SIZE_MAX) return;  // not after a chunk: nothing to index
    if (len < 6) fail("MessageIndex", "too short");
    const std::string h = r_.readAt(body(), 6, "MessageIndex");
    const std::uint32_t bytes = loadU32(h.data() + 2);
    if (bytes > len - 6 || bytes % 16 != 0) fail("MessageIndex", "entries of " + num(bytes) + " bytes do not fit");
    ChunkRef& r = r_.refs_[pending_];
    r.index_offsets[loadU16(h.data())] = pos_;
    r.counts[loadU16(h.data())] += bytes / 16;
  }

  void message(std::uint64_t len) {
    if (len < kMessageFixed) fail("Message", "too short");
    const std::string h = r_.readAt(body(), kMessageFixed, "Message");
    ChunkRef r;
    r.offset = pos_;
    r.length = kRecordPrefix + len;
    r.start = r.end = loadU64(h.data() + 6);
    r.loose = true;
    r.loose_channel = loadU16(h.data());
    r_.refs_.push_back(std::move(r));
    ++loose_;
  }

  // e.g. "12 whole chunks up to log time 29.98 s, 3411 bytes of a cut record
  // ignored (offset ...)"
  std::string note() const {
    std::size_t whole = 0;
    std::uint64_t last = 0;
    for (const auto& r : r_.refs_) {
      if (r.loose) continue;
      ++whole;
      last = std::max(last, r.end);
    }
    char t[64];
    std::snprintf(t, sizeof t, "%.2f", static_cast<double>(last) * 1e-9);
    std::string out = num(whole) + (whole == 1 ? " whole chunk" : " whole chunks");
    if (whole > 0) out += std::string(" up to log time ") + t + " s";
    if (loose_ > 0) out += ", " + num(loose_) + " messages outside chunks";
    if (!stop_.empty()) out += ", " + stop_;
    return out;
  }

  McapReader& r_;
  const std::uint64_t end_;
  std::uint64_t pos_;              // the record being read
  std::size_t pending_ = SIZE_MAX;  // the last chunk, while its MessageIndex records follow
  std::string stop_;               // why the scan stopped before end_, if it did
  std::size_t loose_ = 0;          // Message records outside chunks
};

void McapReader::scan(std::uint64_t end) { Scanner(*this, end).run(); }

}  // namespace groundsim::recording
