// MCAP files written by McapWriter and read back by McapReader: what goes
// in comes out bit for bit and in log-time order, one session's chunks are
// all a reader of that session touches, zstd compresses, a file left by a
// crash (flushed, then copied or cut anywhere) still yields what was
// flushed, and corrupt or hostile files fail with a reason.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "sample_json.hpp"
#include "recording/crc32.hpp"
#include "recording/mcap_format.hpp"
#include "recording/mcap_reader.hpp"
#include "recording/mcap_writer.hpp"

namespace fs = std::filesystem;
using namespace groundsim::recording;

namespace {

using groundsim::recording::test::smoothJson;

struct Written {
  std::uint16_t channel;
  std::uint32_t sequence;
  std::uint64_t log_time, publish_time;
  std::string data;
  int group;
};

using Key = std::pair<std::uint16_t, std::uint32_t>;  // (channel, sequence): unique in these tests

class Mcap : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("groundsim_mcap_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

std::string slurp(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void spit(const std::string& p, std::string_view bytes) {
  // a new file, not a truncated one: ext4 writes a truncated file out at
  // close (auto_da_alloc), which made the damage loop below I/O-bound
  fs::remove(p);
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::vector<McapMessage> readAll(McapReader& r, const std::set<std::uint16_t>& channels = {},
                                 std::uint64_t t0 = 0, std::uint64_t t1 = UINT64_MAX) {
  std::vector<McapMessage> out;
  r.readMessages([&](const McapMessage& m) { out.push_back(m); }, channels, t0, t1);
  return out;
}

bool inLogTimeOrder(const std::vector<McapMessage>& v) {
  return std::is_sorted(v.begin(), v.end(),
                        [](const McapMessage& a, const McapMessage& b) { return a.log_time < b.log_time; });
}


std::map<Key, const Written*> byKey(const std::vector<Written>& w) {
  std::map<Key, const Written*> m;
  for (const auto& x : w) m[{x.channel, x.sequence}] = &x;
  return m;
}

// Every message read is one written, bit for bit.
void expectAllWritten(const std::vector<McapMessage>& got, const std::map<Key, const Written*>& written) {
  for (const auto& m : got) {
    const auto it = written.find({m.channel, m.sequence});
    ASSERT_NE(it, written.end()) << "channel " << m.channel << " sequence " << m.sequence;
    EXPECT_EQ(m.log_time, it->second->log_time);
    EXPECT_EQ(m.publish_time, it->second->publish_time);
    EXPECT_EQ(m.data, it->second->data);
  }
}

std::set<Key> keys(const std::vector<McapMessage>& v) {
  std::set<Key> s;
  for (const auto& m : v) s.insert({m.channel, m.sequence});
  return s;
}

std::map<std::uint16_t, std::uint64_t> countsOf(const std::vector<McapMessage>& v) {
  std::map<std::uint16_t, std::uint64_t> c;
  for (const auto& m : v) ++c[m.channel];
  return c;
}

template <class F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

// ---- round trip ----------------------------------------------------------

struct RoundTripFile {
  std::vector<Written> messages;
  std::map<std::uint16_t, McapChannelInfo> channels;
  std::vector<std::pair<std::string, std::string>> attachments;
  std::map<std::string, std::map<std::string, std::string>> metadata;
  std::uint64_t bytes_written = 0;
};

RoundTripFile writeRoundTrip(const std::string& file, WriterOptions o) {
  RoundTripFile f;
  McapWriter w(file, o);
  const std::string schema_text = R"({"type":"object","properties":{"t":{"type":"number"}}})";
  const std::uint16_t state_schema = w.addSchema("groundsim.State", "jsonschema", schema_text);
  std::vector<std::array<std::uint16_t, 2>> ch(3);
  for (int g = 0; g < 3; ++g) {
    const std::map<std::string, std::string> md{{"session", std::to_string(g)}, {"units", "SI"}};
    ch[g][0] = w.addChannel(state_schema, "/session/" + std::to_string(g) + "/state", "json", md);
    ch[g][1] = w.addChannel(0, "/session/" + std::to_string(g) + "/raw", "application/octet-stream");
    f.channels[ch[g][0]] = {ch[g][0], state_schema, "/session/" + std::to_string(g) + "/state", "json", md};
    f.channels[ch[g][1]] = {ch[g][1], 0, "/session/" + std::to_string(g) + "/raw", "application/octet-stream", {}};
  }
  std::mt19937 rng(7);
  std::map<std::uint16_t, std::uint32_t> seq;
  for (int i = 0; i < 1000; ++i) {
    for (int g = 0; g < 3; ++g) {
      Written m;
      m.group = g;
      m.channel = ch[g][i % 2];
      m.sequence = seq[m.channel]++;
      // interleaved sessions, and a few messages logged late (out of order)
      m.log_time = 1'000'000'000ull + i * 1'000'000ull + g * 333 - (i % 7 == 3 ? 1'500'000 : 0);
      m.publish_time = m.log_time - 17;
      if (i % 2 == 0) {
        m.data = smoothJson(g, i);
      } else {
        m.data.resize(rng() % 200);  // binary, zeros included; some empty
        for (auto& c : m.data) c = static_cast<char>(rng() % 4 == 0 ? 0 : rng());
      }
      w.write(m.channel, m.sequence, m.log_time, m.publish_time, m.data, g);
      f.messages.push_back(std::move(m));
    }
    if (i == 500) {
      std::string blob(100'000, '\0');
      for (auto& c : blob) c = static_cast<char>(rng());
      w.attach("blob.bin", "application/octet-stream", 1'500'000'000ull, blob);
      f.attachments.emplace_back("blob.bin", blob);
      w.metadata("session", {{"seed", "42"}, {"scenario", "cosine"}});
      f.metadata["session"] = {{"seed", "42"}, {"scenario", "cosine"}};
    }
  }
  w.attach("scenario.json", "application/json", 2'000'000'000ull, R"({"ground":"cosine"})");
  f.attachments.emplace_back("scenario.json", R"({"ground":"cosine"})");
  w.metadata("build", {});
  f.metadata["build"] = {};
  w.close();
  f.bytes_written = w.bytesWritten();
  return f;
}

TEST_F(Mcap, RoundTripIsBitExactInLogTimeOrder) {
  WriterOptions o;
  o.chunk_bytes = 16 << 10;  // many chunks
  const RoundTripFile f = writeRoundTrip(path("rt.mcap"), o);
  EXPECT_EQ(f.bytes_written, fs::file_size(path("rt.mcap")));

  McapReader r(path("rt.mcap"));
  EXPECT_TRUE(r.complete());
  EXPECT_EQ(r.endNote(), "complete");
  ASSERT_EQ(r.schemas().size(), 1u);
  const McapSchemaInfo& s = r.schemas().begin()->second;
  EXPECT_EQ(s.name, "groundsim.State");
  EXPECT_EQ(s.encoding, "jsonschema");
  EXPECT_EQ(s.data, R"({"type":"object","properties":{"t":{"type":"number"}}})");
  ASSERT_EQ(r.channels().size(), f.channels.size());
  for (const auto& [id, c] : f.channels) {
    const McapChannelInfo& got = r.channels().at(id);
    EXPECT_EQ(got.id, id);
    EXPECT_EQ(got.schema_id, c.schema_id);
    EXPECT_EQ(got.topic, c.topic);
    EXPECT_EQ(got.message_encoding, c.message_encoding);
    EXPECT_EQ(got.metadata, c.metadata);
  }

  std::map<std::uint16_t, std::uint64_t> written_counts;
  for (const auto& m : f.messages) ++written_counts[m.channel];
  EXPECT_EQ(r.messageCounts(), written_counts);

  const auto got = readAll(r);
  ASSERT_EQ(got.size(), f.messages.size());
  EXPECT_TRUE(inLogTimeOrder(got));
  expectAllWritten(got, byKey(f.messages));
  EXPECT_EQ(keys(got).size(), f.messages.size());

  EXPECT_EQ(r.attachments(), f.attachments);
  EXPECT_EQ(r.metadata(), f.metadata);
  EXPECT_NO_THROW(r.verify());
  EXPECT_GT(r.chunks().size(), 3u);
}

TEST_F(Mcap, ChannelAndTimeFiltersReadOnlyWhatTheyNeed) {
  WriterOptions o;
  o.chunk_bytes = 16 << 10;
  const RoundTripFile f = writeRoundTrip(path("rt.mcap"), o);
  const std::uint64_t t0 = 1'200'000'000ull, t1 = 1'300'000'000ull;
  const std::uint16_t channel = f.channels.begin()->first;

  McapReader all(path("rt.mcap"));
  const std::uint64_t opened = all.bytesRead();
  readAll(all);
  const std::uint64_t read_all = all.bytesRead() - opened;

  McapReader r(path("rt.mcap"));
  const auto got = readAll(r, {channel}, t0, t1);
  std::vector<const Written*> want;
  for (const auto& m : f.messages)
    if (m.channel == channel && m.log_time >= t0 && m.log_time <= t1) want.push_back(&m);
  ASSERT_EQ(got.size(), want.size());
  ASSERT_FALSE(want.empty());
  EXPECT_TRUE(inLogTimeOrder(got));
  expectAllWritten(got, byKey(f.messages));
  for (const auto& m : got) {
    EXPECT_EQ(m.channel, channel);
    EXPECT_GE(m.log_time, t0);
    EXPECT_LE(m.log_time, t1);
  }
  // a tenth of the time of one of six channels: a small part of the chunks
  EXPECT_LT(r.bytesRead() - opened, read_all / 5);

  // a window with nothing in it reads no chunk
  McapReader none(path("rt.mcap"));
  const std::uint64_t before = none.bytesRead();
  EXPECT_TRUE(readAll(none, {}, 5'000'000'000ull, 6'000'000'000ull).empty());
  EXPECT_EQ(none.bytesRead(), before);
}

// ---- one session per group ----------------------------------------------

TEST_F(Mcap, OneSessionOfAHundredReadsUnderFivePercentOfTheFile) {
  const int groups = 100, per_group = 10'000;
  McapWriter w(path("many.mcap"));
  const std::uint16_t schema = w.addSchema("groundsim.State", "jsonschema", "{}");
  std::vector<std::array<std::uint16_t, 2>> ch(groups);
  std::map<std::uint16_t, int> group_of;
  for (int g = 0; g < groups; ++g) {
    ch[g][0] = w.addChannel(schema, "/session/" + std::to_string(g) + "/state", "json");
    ch[g][1] = w.addChannel(schema, "/session/" + std::to_string(g) + "/events", "json");
    group_of[ch[g][0]] = group_of[ch[g][1]] = g;
  }
  std::uint64_t raw = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < per_group; ++i)
    for (int g = 0; g < groups; ++g) {
      const std::string d = smoothJson(g, i);
      const std::uint64_t t = 1'000'000'000ull + i * 10'000'000ull + g;
      w.write(ch[g][i % 10 == 0 ? 1 : 0], static_cast<std::uint32_t>(i), t, t, d, g);
      raw += d.size();
    }
  w.close();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::uint64_t size = fs::file_size(path("many.mcap"));

  McapReader r(path("many.mcap"));
  ASSERT_TRUE(r.complete());
  for (const McapChunkInfo& c : r.chunks()) {  // chunks hold one group only
    ASSERT_FALSE(c.channels.empty());
    for (std::uint16_t id : c.channels) EXPECT_EQ(group_of.at(id), group_of.at(c.channels.front()));
  }
  const int g = 37;
  const auto got = readAll(r, {ch[g][0], ch[g][1]});
  ASSERT_EQ(got.size(), static_cast<std::size_t>(per_group));
  EXPECT_TRUE(inLogTimeOrder(got));
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].sequence, i);
    ASSERT_EQ(got[i].data, smoothJson(g, static_cast<int>(i)));
  }
  EXPECT_LT(r.bytesRead(), size / 20);
  EXPECT_LT(size, raw);
  std::cout << "100 sessions x 10k messages: raw payload " << raw << " B, file " << size << " B ("
            << r.chunks().size() << " chunks), written in " << seconds << " s; one session read "
            << r.bytesRead() << " B (" << 100.0 * r.bytesRead() / size << " % of the file)\n";
}

// ---- compression ----------------------------------------------------------

TEST_F(Mcap, ZstdCompressesAndLevelZeroWritesPlainChunks) {
  std::uint64_t raw = 0;
  auto write = [&](const std::string& file, int level, std::size_t chunk_bytes, bool random) {
    WriterOptions o;
    o.zstd_level = level;
    o.chunk_bytes = chunk_bytes;
    McapWriter w(file, o);
    const std::uint16_t c = w.addChannel(0, "/state", "json");
    std::mt19937 rng(3);
    raw = 0;
    for (int i = 0; i < 2000; ++i) {
      std::string d = smoothJson(0, i);
      if (random)
        for (auto& x : d) x = static_cast<char>(rng());
      w.write(c, static_cast<std::uint32_t>(i), 1000 + i, 1000 + i, d);
      raw += d.size();
    }
    w.close();
    return fs::file_size(file);
  };
  const auto zstd = write(path("zstd.mcap"), 3, 64 << 10, false);
  const auto plain = write(path("plain.mcap"), 0, 64 << 10, false);
  // one random message per chunk: zstd's frame would be larger than the record
  const auto noise = write(path("noise.mcap"), 3, 1, true);
  EXPECT_LT(zstd, raw / 3);  // smooth text compresses severalfold
  EXPECT_GT(plain, raw);     // level 0: the payload and the framing
  EXPECT_GT(noise, raw);

  McapReader z(path("zstd.mcap")), p(path("plain.mcap")), n(path("noise.mcap"));
  for (const auto& c : z.chunks()) {
    EXPECT_EQ(c.compression, "zstd");
    EXPECT_LT(c.compressed_size, c.uncompressed_size);
  }
  EXPECT_EQ(n.chunks().size(), 2000u);
  for (McapReader* r : {&p, &n})  // level 0, and chunks zstd cannot shrink
    for (const auto& c : r->chunks()) {
      EXPECT_EQ(c.compression, "");
      EXPECT_EQ(c.compressed_size, c.uncompressed_size);
    }
  const auto a = readAll(z), b = readAll(p);
  ASSERT_EQ(a.size(), 2000u);
  ASSERT_EQ(b.size(), 2000u);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].data, smoothJson(0, static_cast<int>(i)));
    EXPECT_EQ(b[i].data, a[i].data);
  }
  EXPECT_EQ(readAll(n).size(), 2000u);
  EXPECT_NO_THROW(p.verify());
  EXPECT_NO_THROW(n.verify());
}

// ---- crash safety -----------------------------------------------------------

TEST_F(Mcap, FlushedFileCopiedOrCutStillYieldsWhatWasFlushed) {
  WriterOptions o;
  o.chunk_bytes = 8 << 10;
  o.chunk_seconds = 0;  // only size and flush() close chunks: deterministic
  std::vector<Written> written;
  std::set<Key> flushed;
  std::uint64_t flushed_size = 0;
  std::string as_is;
  {
    McapWriter w(path("live.mcap"), o);
    const std::uint16_t schema = w.addSchema("s", "jsonschema", "{}");
    std::vector<std::uint16_t> ch;
    for (int g = 0; g < 3; ++g) ch.push_back(w.addChannel(schema, "/session/" + std::to_string(g), "json"));
    auto write = [&](int from, int to) {
      for (int i = from; i < to; ++i)
        for (int g = 0; g < 3; ++g) {
          Written m{ch[g], static_cast<std::uint32_t>(i), 1'000'000ull * i + g, 1'000'000ull * i + g,
                    smoothJson(g, i), g};
          w.write(m.channel, m.sequence, m.log_time, m.publish_time, m.data, g);
          written.push_back(std::move(m));
        }
    };
    write(0, 600);
    w.flush();
    flushed_size = w.bytesWritten();
    for (const auto& m : written) flushed.insert({m.channel, m.sequence});
    write(600, 900);  // some of these chunks reach the file by size, the rest are open
    EXPECT_GT(w.bytesWritten(), flushed_size);
    as_is = slurp(path("live.mcap"));  // what a crash here would leave
    w.close();
  }
  const auto all = byKey(written);
  ASSERT_GE(as_is.size(), flushed_size);

  struct Read {
    std::vector<McapMessage> messages;
    std::string note;
  };
  auto readCut = [&](const std::string& bytes, std::uint64_t cut) {
    spit(path("cut.mcap"), std::string_view(bytes).substr(0, cut));
    McapReader r(path("cut.mcap"));
    EXPECT_FALSE(r.complete()) << "cut at " << cut;
    EXPECT_NE(r.endNote().find("incomplete"), std::string::npos) << r.endNote();
    EXPECT_EQ(r.channels().size(), 3u);  // written before any chunk
    Read out{readAll(r), r.endNote()};
    EXPECT_TRUE(inLogTimeOrder(out.messages));
    expectAllWritten(out.messages, all);
    EXPECT_EQ(r.messageCounts(), countsOf(out.messages)) << "cut at " << cut;
    return out;
  };
  auto includesFlushed = [&](const Read& r) {
    const std::set<Key> got = keys(r.messages);
    return std::includes(got.begin(), got.end(), flushed.begin(), flushed.end());
  };

  // the file as the crash left it
  const Read left = readCut(as_is, as_is.size());
  EXPECT_TRUE(includesFlushed(left));
  EXPECT_GT(left.messages.size(), flushed.size());  // chunks closed by size after the flush too

  // cuts after the flush point: everything flushed is still there
  EXPECT_TRUE(includesFlushed(readCut(as_is, flushed_size)));
  const Read mid_record = readCut(as_is, flushed_size + 5);
  EXPECT_TRUE(includesFlushed(mid_record));
  EXPECT_NE(mid_record.note.find("cut record"), std::string::npos) << mid_record.note;

  // cuts against the chunks of the closed file: a chunk cut anywhere in its
  // record is lost whole, exactly as if the file ended where it starts; a
  // chunk whose message indexes are cut is still read (decompressed)
  const std::string full = slurp(path("live.mcap"));
  McapReader closed(path("live.mcap"));
  ASSERT_TRUE(closed.complete());
  const auto chunks = closed.chunks();
  ASSERT_GT(chunks.size(), 6u);
  for (const std::size_t k : {std::size_t{1}, chunks.size() / 2, chunks.size() - 1}) {
    const McapChunkInfo& c = chunks[k];
    const std::set<Key> before = keys(readCut(full, c.offset).messages);
    for (const std::uint64_t cut : {c.offset + 4, c.offset + 30, c.offset + c.length / 2, c.offset + c.length - 1}) {
      const Read r = readCut(full, cut);
      EXPECT_EQ(keys(r.messages), before) << "chunk " << k << " cut at " << cut;
      EXPECT_NE(r.note.find("cut record"), std::string::npos) << r.note;
      if (cut >= flushed_size) {
        EXPECT_TRUE(includesFlushed(r));
      }
    }
    const Read whole = readCut(full, c.offset + c.length);
    const Read index_cut = readCut(full, c.offset + c.length + 3);
    EXPECT_GT(whole.messages.size(), before.size());
    EXPECT_EQ(keys(index_cut.messages), keys(whole.messages));
  }

  // the summary cut off: every chunk is whole
  const Read no_summary = readCut(full, full.size() - 40);
  EXPECT_EQ(no_summary.messages.size(), written.size());
  EXPECT_NE(no_summary.note.find("DataEnd"), std::string::npos) << no_summary.note;

  // a file cut right after the header, and one cut inside it
  spit(path("h.mcap"), full.substr(0, 8 + 9 + 8 + 9));  // magic + Header{"", "groundsim"}
  {
    McapReader r(path("h.mcap"));
    EXPECT_FALSE(r.complete());
    EXPECT_TRUE(readAll(r).empty());
    EXPECT_NE(r.endNote().find("0 whole chunks"), std::string::npos) << r.endNote();
  }
  spit(path("h.mcap"), full.substr(0, 20));
  const std::string e = errorOf([&] { McapReader r(path("h.mcap")); });
  EXPECT_NE(e.find("truncated header"), std::string::npos) << e;
}

TEST_F(Mcap, AChunkOpenLongerThanChunkSecondsIsFlushedAtTheNextWrite) {
  WriterOptions o;
  o.chunk_seconds = 0.05;
  McapWriter w(path("slow.mcap"), o);
  const std::uint16_t c = w.addChannel(0, "/slow", "json");
  for (std::uint32_t i = 0; i < 10; ++i) w.write(c, i, i, i, "{}", i % 2);
  const std::uint64_t before = w.bytesWritten();
  std::this_thread::sleep_for(std::chrono::milliseconds(80));
  w.write(c, 10, 10, 10, "{}", 0);
  EXPECT_GT(w.bytesWritten(), before);
  fs::copy_file(path("slow.mcap"), path("copy.mcap"));
  McapReader r(path("copy.mcap"));
  EXPECT_FALSE(r.complete());
  EXPECT_EQ(readAll(r).size(), 10u);  // both groups' chunks; the 11th is in a new open chunk
  EXPECT_EQ(r.chunks().size(), 2u);
}

// ---- corruption -----------------------------------------------------------

TEST_F(Mcap, AFlippedByteIsReportedWithItsOffset) {
  for (const int level : {0, 3}) {
    WriterOptions o;
    o.chunk_bytes = 16 << 10;
    o.zstd_level = level;
    writeRoundTrip(path("good.mcap"), o);
    const std::string good = slurp(path("good.mcap"));
    McapReader r(path("good.mcap"));
    const auto chunks = r.chunks();
    const McapChunkInfo& c = chunks[chunks.size() / 2];

    std::string bad = good;
    bad[c.offset + c.length - 100] ^= 0x20;  // inside the records field
    spit(path("bad.mcap"), bad);
    McapReader b(path("bad.mcap"));  // the index is intact
    const std::string e = errorOf([&] { readAll(b); });
    EXPECT_NE(e.find("chunk at offset " + std::to_string(c.offset)), std::string::npos) << e;
    if (level == 0) {
      EXPECT_NE(e.find("CRC mismatch"), std::string::npos) << e;
    }
    EXPECT_NE(errorOf([&] { b.verify(); }).find("CRC mismatch"), std::string::npos);
  }

  const std::string good = slurp(path("good.mcap"));
  {  // the schema record, outside chunks: only the data section CRC sees it
    std::string bad = good;
    const std::size_t at = bad.find("groundsim.State");
    bad[at] ^= 1;
    spit(path("bad.mcap"), bad);
    McapReader b(path("bad.mcap"));
    EXPECT_EQ(readAll(b).size(), 3000u);
    const std::string e = errorOf([&] { b.verify(); });
    EXPECT_NE(e.find("data section CRC mismatch"), std::string::npos) << e;
  }
  {  // an attachment's data
    std::string bad = good;
    bad[bad.find("{\"ground\":\"cosine\"}") + 3] ^= 1;
    spit(path("bad.mcap"), bad);
    McapReader b(path("bad.mcap"));
    const std::string e = errorOf([&] { b.attachments(); });
    EXPECT_NE(e.find("attachment 'scenario.json' at offset"), std::string::npos) << e;
    EXPECT_NE(e.find("CRC mismatch"), std::string::npos) << e;
  }
  {  // the summary
    std::string bad = good;
    bad[bad.size() - 60] ^= 1;
    spit(path("bad.mcap"), bad);
    const std::string e = errorOf([&] { McapReader b(path("bad.mcap")); });
    EXPECT_NE(e.find("summary CRC mismatch"), std::string::npos) << e;
  }
}

// ---- hostile files ----------------------------------------------------------

using namespace groundsim::recording::mcap;

// magic, Header, the data records, DataEnd (CRC 0), the summary records,
// Footer (CRC 0: not checked), magic; `data` and `summary` may use the
// offsets dataAt() gives.
struct Hostile {
  std::string data, summary;
  static std::uint64_t dataAt() { return 8 + 9 + 4 + 4; }  // after an empty-string Header
  std::string bytes() const {
    std::string s(kMagic);
    const std::size_t h = beginRecord(s, Op::Header);
    putStr(s, "");
    putStr(s, "");
    endRecord(s, h);
    s += data;
    const std::size_t d = beginRecord(s, Op::DataEnd);
    putU32(s, 0);
    endRecord(s, d);
    const std::uint64_t summary_start = s.size();
    s += summary;
    const std::size_t f = beginRecord(s, Op::Footer);
    putU64(s, summary.empty() ? 0 : summary_start);
    putU64(s, 0);
    putU32(s, 0);
    endRecord(s, f);
    s += kMagic;
    return s;
  }
};

std::string chunkRecord(std::uint64_t usize, const std::string& compression, const std::string& records) {
  std::string s;
  const std::size_t at = beginRecord(s, Op::Chunk);
  putU64(s, 1);
  putU64(s, 2);
  putU64(s, usize);
  putU32(s, 0);
  putStr(s, compression);
  putU64(s, records.size());
  s += records;
  endRecord(s, at);
  return s;
}

std::string chunkIndexFor(std::uint64_t offset, std::uint64_t length) {
  ChunkIndex ci;
  ci.message_start_time = 1;
  ci.message_end_time = 2;
  ci.chunk_start_offset = offset;
  ci.chunk_length = length;
  std::string s;
  encode(s, ci);
  return s;
}

std::string messageRecord(std::uint16_t channel, std::uint64_t t, std::string_view data) {
  std::string s;
  const std::size_t at = beginRecord(s, Op::Message);
  putU16(s, channel);
  putU32(s, 0);
  putU64(s, t);
  putU64(s, t);
  s += data;
  endRecord(s, at);
  return s;
}

TEST_F(Mcap, HostileFilesFailWithAReason) {
  auto openError = [&](std::string_view bytes) {
    spit(path("h.mcap"), bytes);
    return errorOf([&] {
      McapReader r(path("h.mcap"));
      readAll(r);
      r.attachments();
      r.metadata();
      r.messageCounts();
    });
  };
  auto contains = [](const std::string& e, const std::string& what) {
    return e.find(what) != std::string::npos;
  };
  EXPECT_TRUE(contains(openError(""), "empty file"));
  EXPECT_TRUE(contains(openError("\x89MC"), "shorter than the 8-byte magic"));
  EXPECT_TRUE(contains(openError("GARBAGE!GARBAGE!GARBAGE!GARBAGE!"), "bad magic"));
  EXPECT_TRUE(contains(openError(std::string("\x89MCAP1\r\n") + std::string(40, '\0')), "unsupported"));
  {
    std::string s(kMagic);
    s += "\x01\x05";
    EXPECT_TRUE(contains(openError(s), "truncated header"));
    s = std::string(kMagic);
    putU8(s, 0x03);
    putU64(s, 0);
    EXPECT_TRUE(contains(openError(s), "not a Header"));
    s = std::string(kMagic);
    putU8(s, 0x01);
    putU64(s, std::uint64_t{1} << 62);
    s += std::string(100, 'x');
    const std::string e = openError(s);
    EXPECT_TRUE(contains(e, "truncated header") && contains(e, "claims")) << e;
    s = std::string(kMagic);
    const std::size_t h = beginRecord(s, Op::Header);
    putU32(s, 0xFFFFFFF0u);  // a profile string longer than the record
    endRecord(s, h);
    EXPECT_TRUE(contains(openError(s), "runs past the record end"));
  }

  const std::uint64_t d = Hostile::dataAt();
  {  // a chunk index pointing past the file
    Hostile f;
    f.summary = chunkIndexFor(d, std::uint64_t{1} << 60);
    EXPECT_TRUE(contains(openError(f.bytes()), "not inside the data section"));
  }
  {  // a summary record longer than the summary
    Hostile f;
    putU8(f.summary, 0x04);
    putU64(f.summary, ~std::uint64_t{0});
    EXPECT_TRUE(contains(openError(f.bytes()), "past the end of the summary"));
  }
  {  // a channel whose topic length is huge
    Hostile f;
    const std::size_t at = beginRecord(f.summary, Op::Channel);
    putU16(f.summary, 1);
    putU16(f.summary, 0);
    putU32(f.summary, 0xFFFFFFF0u);
    endRecord(f.summary, at);
    const std::string e = openError(f.bytes());
    EXPECT_TRUE(contains(e, "Channel record at offset") && contains(e, "runs past the record end")) << e;
  }
  {  // footer: summary_start beyond the file
    Hostile f;
    f.summary = chunkIndexFor(d, 10);
    std::string b = f.bytes();
    patchU64(b, b.size() - 8 - 20, std::uint64_t{1} << 40);
    EXPECT_TRUE(contains(openError(b), "summary_start"));
  }
  {  // the magic at the end, but no footer before it
    std::string b = Hostile{}.bytes();
    b[b.size() - 8 - 29] = 0x05;
    EXPECT_TRUE(contains(openError(b), "no Footer record"));
  }
  auto indexedChunk = [&](const std::string& chunk) {
    Hostile f;
    f.data = chunk;
    f.summary = chunkIndexFor(d, chunk.size());
    return openError(f.bytes());
  };
  {  // uncompressed_size over 1 GiB
    const std::string e = indexedChunk(chunkRecord(std::uint64_t{3} << 30, "zstd", "abcd"));
    EXPECT_TRUE(contains(e, "chunk at offset " + std::to_string(d)) && contains(e, "1 GiB")) << e;
  }
  {  // 512 MiB claimed, garbage instead of zstd: fails before allocating
    const std::string e = indexedChunk(chunkRecord(512u << 20, "zstd", std::string(64, 'z')));
    EXPECT_TRUE(contains(e, "chunk at offset " + std::to_string(d))) << e;
  }
  EXPECT_TRUE(contains(indexedChunk(chunkRecord(4, "lz4", "abcd")), "'lz4' is not supported"));
  EXPECT_TRUE(contains(indexedChunk(chunkRecord(5, "", "abcd")), "uncompressed_size"));
  {  // a record inside a chunk longer than the chunk
    std::string inner;
    putU8(inner, 0x05);
    putU64(inner, ~std::uint64_t{0} >> 1);
    inner += "0123456789";
    const std::string e = indexedChunk(chunkRecord(inner.size(), "", inner));
    EXPECT_TRUE(contains(e, "runs past its records")) << e;
  }
  {  // a chunk record whose records field runs past the record
    std::string c = chunkRecord(4, "", "abcd");
    patchU64(c, 9 + 8 + 8 + 8 + 4 + 4, 1000);
    const std::string e = indexedChunk(c);
    EXPECT_TRUE(contains(e, "Chunk record at offset " + std::to_string(d))) << e;
  }
  {  // a message index larger than its record
    Hostile f;
    f.data = chunkRecord(0, "", "");
    const std::uint64_t mi_at = d + f.data.size();
    const std::size_t at = beginRecord(f.data, Op::MessageIndex);
    putU16(f.data, 1);
    putU32(f.data, 0xFFFFFFF0u);
    endRecord(f.data, at);
    ChunkIndex ci;
    ci.message_start_time = 1;
    ci.message_end_time = 2;
    ci.chunk_start_offset = d;
    ci.chunk_length = mi_at - d;
    ci.message_index_offsets[1] = mi_at;
    encode(f.summary, ci);
    spit(path("h.mcap"), f.bytes());
    McapReader r(path("h.mcap"));
    EXPECT_TRUE(contains(errorOf([&] { readAll(r, {1}); }), "MessageIndex record at offset"));
  }

  // without a footer, a record running past the end is a cut one: no error,
  // whatever length it claims, and nothing allocated for it
  {
    std::string s = Hostile{}.bytes().substr(0, Hostile::dataAt());
    s += messageRecord(1, 5, "whole");
    putU8(s, 0x06);
    putU64(s, ~std::uint64_t{0});
    s += "tail";
    spit(path("h.mcap"), s);
    McapReader r(path("h.mcap"));
    EXPECT_FALSE(r.complete());
    EXPECT_NE(r.endNote().find("cut record"), std::string::npos) << r.endNote();
    const auto m = readAll(r);
    ASSERT_EQ(m.size(), 1u);  // messages outside chunks (other writers) are read too
    EXPECT_EQ(m[0].data, "whole");
    // but a whole chunk record that is malformed inside is an error
    s = Hostile{}.bytes().substr(0, Hostile::dataAt());
    std::string c = chunkRecord(4, "", "abcd");
    patchU32(c, 9 + 8 + 8 + 8 + 4, 0xFFFFFF00u);  // compression string length
    s += c;
    EXPECT_TRUE(contains(openError(s), "Chunk record at offset " + std::to_string(d)));
  }
}

// Other writers may leave messages outside chunks, with a summary but no
// chunk index: they are found by scanning.
TEST_F(Mcap, AnUnchunkedFileWithASummaryIsReadByScanning) {
  Hostile f;
  const std::size_t at = beginRecord(f.data, Op::Channel);
  putU16(f.data, 4);
  putU16(f.data, 0);
  putStr(f.data, "/loose");
  putStr(f.data, "raw");
  putU32(f.data, 0);
  endRecord(f.data, at);
  f.summary = f.data;  // the channel, repeated
  f.data += messageRecord(4, 30, "third") + messageRecord(4, 10, "first") + messageRecord(4, 20, "second");
  Statistics st;
  st.message_count = 3;
  st.channel_count = 1;
  st.channel_message_counts[4] = 3;
  encode(f.summary, st);
  spit(path("loose.mcap"), f.bytes());
  McapReader r(path("loose.mcap"));
  EXPECT_TRUE(r.complete());
  EXPECT_NE(r.endNote().find("3 messages outside chunks"), std::string::npos) << r.endNote();
  const auto m = readAll(r);
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m[0].data, "first");
  EXPECT_EQ(m[1].data, "second");
  EXPECT_EQ(m[2].data, "third");
  EXPECT_EQ(readAll(r, {4}, 15, 25).size(), 1u);
  EXPECT_EQ(r.messageCounts(), (std::map<std::uint16_t, std::uint64_t>{{4, 3}}));
}

// Random damage to a small file (complete, and cut): opening and reading
// either works or throws std::runtime_error (never another exception, a
// crash or a large allocation).
TEST_F(Mcap, RandomDamageNeverCrashes) {
  WriterOptions o;
  o.chunk_bytes = 2 << 10;
  o.zstd_level = 1;
  {
    McapWriter w(path("small.mcap"), o);
    const std::uint16_t s = w.addSchema("s", "jsonschema", "{}");
    const std::uint16_t a = w.addChannel(s, "/a", "json", {{"k", "v"}});
    const std::uint16_t b = w.addChannel(0, "/b", "raw");
    for (int i = 0; i < 200; ++i) w.write(i % 3 ? a : b, i, 1000 * i, 1000 * i, smoothJson(i % 2, i), i % 2);
    w.attach("x", "text/plain", 5, "attachment");
    w.metadata("m", {{"a", "b"}});
    w.close();
  }
  const std::string good = slurp(path("small.mcap"));
  rusage before{};
  getrusage(RUSAGE_SELF, &before);
  std::mt19937 rng(11);
  int failures = 0;
  for (int it = 0; it < 1000; ++it) {
    std::string bad = good;
    if (it % 2) bad.resize(bad.size() * 3 / 4);  // a cut file: read by scanning, no summary CRC
    const int flips = 1 + static_cast<int>(rng() % 4);
    for (int k = 0; k < flips; ++k) {
      const std::size_t at = rng() % bad.size();
      bad[at] = static_cast<char>(rng() % 3 == 0 ? 0xFF : rng());
    }
    spit(path("fuzz.mcap"), bad);
    try {
      McapReader r(path("fuzz.mcap"));
      readAll(r);
      readAll(r, {1}, 10'000, 100'000);
      r.attachments();
      r.metadata();
      r.messageCounts();
      r.verify();
    } catch (const std::runtime_error&) {
      ++failures;
    }
  }
  EXPECT_GT(failures, 100);  // the damage is seen
  rusage after{};
  getrusage(RUSAGE_SELF, &after);
  EXPECT_LT(after.ru_maxrss - before.ru_maxrss, 256 * 1024);  // KiB: no large allocation
}

// ---- the writer's own errors ---------------------------------------------------

TEST_F(Mcap, WriterErrorsNameTheirCause) {
  const std::string missing = path("no/such/dir/x.mcap");
  const std::string e = errorOf([&] { McapWriter w(missing); });
  EXPECT_NE(e.find(missing), std::string::npos) << e;
  EXPECT_NE(e.find("No such file"), std::string::npos) << e;

  McapWriter w(path("w.mcap"));
  EXPECT_THROW(w.addChannel(3, "/t", "json"), std::invalid_argument);
  const std::uint16_t c = w.addChannel(0, "/t", "json");
  EXPECT_THROW(w.write(static_cast<std::uint16_t>(c + 1), 0, 0, 0, "x"), std::invalid_argument);
  w.write(c, 0, 0, 0, "x");
  w.close();
  w.close();  // idempotent
  EXPECT_THROW(w.write(c, 1, 1, 1, "x"), std::logic_error);
  McapReader r(path("w.mcap"));
  EXPECT_EQ(readAll(r).size(), 1u);
}

TEST(Crc32, MatchesTheIeeeCheckValue) {
  EXPECT_EQ(crc32(std::string_view("123456789")), 0xCBF43926u);
  EXPECT_EQ(crc32(std::string_view("")), 0u);
  const std::string s = "The quick brown fox jumps over the lazy dog, more than eight bytes at a time";
  EXPECT_EQ(crc32(std::string_view(s).substr(20), crc32(std::string_view(s).substr(0, 20))), crc32(s));
}

}  // namespace
