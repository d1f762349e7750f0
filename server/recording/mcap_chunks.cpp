// McapReader's chunks: loading one (zstd, CRC), its message indexes, the
// message counts, and readMessages(), which merges the selected chunks'
// messages into log time order.
#include <zstd.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "recording/crc32.hpp"
#include "recording/mcap_reader.hpp"
#include "recording/mcap_reader_detail.hpp"

namespace groundsim::recording {

using namespace mcap;
using namespace mcap_detail;  // the reader's own helpers (mcap_reader_detail.hpp)

namespace {

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

}  // namespace

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

// One readMessages() call: selects the chunks, then merges their messages
// into log time order, loading a chunk when it may hold the next message.
class McapReader::Delivery {
 public:
  Delivery(McapReader& reader, const std::function<void(const McapMessage&)>& f,
           const std::set<std::uint16_t>& channels, std::uint64_t t0, std::uint64_t t1)
      : r_(reader), f_(f), channels_(channels), t0_(t0), t1_(t1) {}

  void run() { merge(selectChunks()); }

 private:
  using Heap = std::vector<std::unique_ptr<Loaded>>;

  bool wanted(std::uint16_t ch) const { return channels_.empty() || channels_.count(ch) > 0; }
  bool keep(std::uint16_t ch, std::uint64_t t) const { return wanted(ch) && t >= t0_ && t <= t1_; }

  // The chunks (and loose messages) that may hold a wanted message, by
  // start time (ties: file order).
  std::vector<const ChunkRef*> selectChunks() const {
    std::vector<const ChunkRef*> sel;
    for (const auto& r : r_.refs_) {
      if (r.end < t0_ || r.start > t1_) continue;
      if (r.loose && !wanted(r.loose_channel)) continue;
      if (!r.loose && !channels_.empty() && r.indexed &&
          std::none_of(r.index_offsets.begin(), r.index_offsets.end(),
                       [&](const auto& kv) { return channels_.count(kv.first) > 0; }))
        continue;
      sel.push_back(&r);
    }
    std::stable_sort(sel.begin(), sel.end(), [](const ChunkRef* a, const ChunkRef* b) {
      return a->start != b->start ? a->start < b->start : a->offset < b->offset;
    });
    return sel;
  }

  // The entries of one chunk to deliver, or nullptr: nothing in it.
  std::unique_ptr<Loaded> load(const ChunkRef& r) {
    auto l = std::make_unique<Loaded>();
    l->order = r.offset;
    if (r.loose) {
      l->raw = r_.readAt(r.offset, r.length, "Message");
      l->records = l->raw;
      if (keep(r.loose_channel, r.start)) l->entries.emplace_back(r.start, 0);
    } else if (!channels_.empty() && r.indexed) {
      if (!entriesFromIndexes(r, *l)) return nullptr;
    } else {
      if (!entriesByScanning(r, *l)) return nullptr;
    }
    std::sort(l->entries.begin(), l->entries.end());
    return l;
  }

  // The wanted channels' message indexes first: a chunk may be skipped
  // without decompressing it. False: nothing to deliver (not loaded).
  bool entriesFromIndexes(const ChunkRef& r, Loaded& l) const {
    for (const auto& [ch, off] : r.index_offsets) {
      if (!channels_.count(ch)) continue;
      for (const auto& e : r_.readMessageIndex(off, ch))
        if (e.first >= t0_ && e.first <= t1_) l.entries.push_back(e);
    }
    if (l.entries.empty()) return false;
    r_.loadChunk(r, l);
    return true;
  }

  // Decompresses the chunk and walks its records: the wanted messages become
  // entries, schemas and channels (other writers put them in chunks) are
  // taken. False: nothing to deliver.
  bool entriesByScanning(const ChunkRef& r, Loaded& l) {
    const std::string_view recs = r_.loadChunk(r, l);
    for (std::size_t pos = 0; pos < recs.size();) {
      if (recs.size() - pos < kRecordPrefix)
        r_.fail("chunk at offset " + num(r.offset) + ": a cut record at offset " + num(pos) + " inside it");
      const auto op = static_cast<std::uint8_t>(recs[pos]);
      const std::uint64_t len = loadU64(recs.data() + pos + 1);
      if (len > recs.size() - pos - kRecordPrefix)
        r_.fail("chunk at offset " + num(r.offset) + ": the record at offset " + num(pos) +
                " inside it runs past its records");
      const std::string_view body = recs.substr(pos + kRecordPrefix, static_cast<std::size_t>(len));
      if (op == static_cast<std::uint8_t>(Op::Message)) {
        if (len < kMessageFixed)
          r_.fail("chunk at offset " + num(r.offset) + ": a Message record too short at offset " + num(pos));
        const std::uint64_t t = loadU64(body.data() + 6);
        if (keep(loadU16(body.data()), t)) l.entries.emplace_back(t, pos);
      } else if (op == static_cast<std::uint8_t>(Op::Schema) || op == static_cast<std::uint8_t>(Op::Channel)) {
        Cursor c(body, opName(op), r.offset);
        op == static_cast<std::uint8_t>(Op::Schema) ? r_.addSchema(c) : r_.addChannel(c);
      }
      pos += kRecordPrefix + static_cast<std::size_t>(len);
    }
    return !l.entries.empty();
  }

  // The heap's order: a min-heap of the loaded chunks by their next message.
  static bool later(const std::unique_ptr<Loaded>& a, const std::unique_ptr<Loaded>& b) {
    const auto& ea = a->entries[a->next];
    const auto& eb = b->entries[b->next];
    if (ea.first != eb.first) return ea.first > eb.first;
    if (a->order != b->order) return a->order > b->order;
    return ea.second > eb.second;
  }

  void merge(const std::vector<const ChunkRef*>& sel) {
    Heap heap;
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
      decode(l, m);
      if (++l.next < l.entries.size())
        std::push_heap(heap.begin(), heap.end(), later);
      else
        heap.pop_back();  // frees the chunk
      f_(m);
    }
  }

  // l's next message into m, checked against its index entry.
  void decode(const Loaded& l, McapMessage& m) const {
    const auto [t, off] = l.entries[l.next];
    const std::string_view recs = l.records;
    if (off > recs.size() || recs.size() - off < kRecordPrefix + kMessageFixed ||
        static_cast<std::uint8_t>(recs[off]) != static_cast<std::uint8_t>(Op::Message))
      r_.fail("chunk at offset " + num(l.order) + ": no Message record at offset " + num(off) +
              " inside it, where its message index points");
    const std::uint64_t len = loadU64(recs.data() + off + 1);
    if (len < kMessageFixed || len > recs.size() - off - kRecordPrefix)
      r_.fail("chunk at offset " + num(l.order) + ": the Message record at offset " + num(off) +
              " inside it runs past its records");
    const char* b = recs.data() + off + kRecordPrefix;
    m.channel = loadU16(b);
    m.sequence = loadU32(b + 2);
    m.log_time = loadU64(b + 6);
    m.publish_time = loadU64(b + 14);
    if (m.log_time != t || !wanted(m.channel))
      r_.fail("chunk at offset " + num(l.order) + ": the message at offset " + num(off) +
              " inside it does not match its message index entry");
    m.data.assign(b + kMessageFixed, static_cast<std::size_t>(len - kMessageFixed));
  }

  McapReader& r_;
  const std::function<void(const McapMessage&)>& f_;
  const std::set<std::uint16_t>& channels_;
  const std::uint64_t t0_, t1_;
};

void McapReader::readMessages(const std::function<void(const McapMessage&)>& f,
                              const std::set<std::uint16_t>& channels, std::uint64_t t0, std::uint64_t t1) {
  withPath(path_, [&] {
    if (t0 > t1) return;
    Delivery(*this, f, channels, t0, t1).run();
  });
}

}  // namespace groundsim::recording
