// record_flood_check: the accounting of a `groundsim record` file against
// what record_flood published and what record_state_counter (an
// independent subscriber) heard (issue 23: "the ledger's counts equal the
// subscriber's, every loss is listed, none silent"). Per session:
//   - the ledger starts at seq 0 and reaches the last seq published;
//   - received, repaired and lost are disjoint and together are every seq
//     published, 0 .. sent-1, each once; nothing is left missing; the
//     _count keys agree with the ranges;
//   - the file's /<session>/state messages (read back, every one: its
//     record's sequence and the JSON's own "seq" and "session_id") are
//     exactly received + repaired, none twice;
//   - every seq the subscriber heard is in the file or listed lost, and the
//     subscriber's own heard + missed equals what was published;
//   - the applied log's END entry is in the file, or named missing or
//     lost, or its frame (the last state) is listed lost;
//   - repair (issue 35: the check used to pass with a dead ring, and the
//     no-repair run checked the same): every seq the ledger lists repaired
//     is one the flood's ring resent (its final report's "resent" ranges).
// Over all sessions, the recorder must have missed some seqs live (the
// script stalls it while the flood goes on: else repair is untested), and
//   - with the ring ("ring": true): the ring answered re-requests and
//     some of those seqs were repaired;
//   - without it: nothing was resent and nothing is listed repaired, so
//     every seq missed live is listed lost.
// Prints the totals; exit 1 with a FAIL line per finding.
//
//   record_flood_check FILE.mcap FLOOD.json COUNTER.json
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "recording/mcap_reader.hpp"

namespace {

using Set = std::vector<char>;  // seq -> 0/1, sized to the seqs published

std::vector<std::string> failures;
void fail(const std::string& s) {
  if (failures.size() < 50) std::printf("FAIL: %s\n", s.c_str());
  failures.push_back(s);
}

// "0-99,102,110-200" into a set of size n; false on seqs outside [0, n),
// text that is not ranges, or a truncated list ("... (N more ranges)").
bool parseRanges(const std::string& text, std::int64_t n, Set& out, long long& count) {
  out.assign(static_cast<std::size_t>(n), 0);
  count = 0;
  std::stringstream ss(text);
  std::string part;
  while (std::getline(ss, part, ',')) {
    if (part.empty()) continue;
    const auto dash = part.find('-');
    std::int64_t a, b;
    try {
      std::size_t used = 0;
      a = std::stoll(part.substr(0, dash), &used);
      if (used != (dash == std::string::npos ? part.size() : dash)) return false;
      b = dash == std::string::npos ? a : std::stoll(part.substr(dash + 1), &used);
      if (dash != std::string::npos && used != part.size() - dash - 1) return false;
    } catch (...) {
      return false;
    }
    if (a < 0 || b < a || b >= n) return false;
    for (std::int64_t i = a; i <= b; ++i) {
      if (out[static_cast<std::size_t>(i)]) return false;  // overlapping ranges
      out[static_cast<std::size_t>(i)] = 1;
      ++count;
    }
  }
  return true;
}

std::string get(const std::map<std::string, std::string>& kv, const std::string& k) {
  auto it = kv.find(k);
  return it == kv.end() ? std::string("<absent>") : it->second;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: record_flood_check FILE.mcap FLOOD.json COUNTER.json\n");
    return 2;
  }
  nlohmann::json flood, counter;
  try {
    std::ifstream(argv[2]) >> flood;
    std::ifstream(argv[3]) >> counter;
  } catch (const std::exception& e) {
    std::printf("FAIL: the reports: %s\n", e.what());
    return 1;
  }
  std::map<std::string, std::int64_t> sent;
  for (auto& [id, n] : flood["sessions"].items()) sent[id] = n.get<std::int64_t>();
  // the flood's final report: whether its ring answered, and what it resent
  if (!flood.contains("ring") || !flood["ring"].is_boolean() || !flood.contains("answers") ||
      !flood.contains("resent")) {
    std::printf("FAIL: the flood's report has no \"ring\", \"answers\" or \"resent\": it did not exit cleanly\n");
    return 1;
  }
  const bool ring = flood["ring"].get<bool>();
  const long long answers_resent = flood["answers"]["resent"].get<long long>();
  const long long answers_requests = flood["answers"]["requests"].get<long long>();

  groundsim::recording::McapReader reader(argv[1]);
  if (!reader.complete()) fail("the file is not complete: " + reader.endNote());
  const auto meta = reader.metadata();

  // the file's states and applied entries, per session
  std::map<std::uint16_t, std::pair<std::string, bool>> channel;  // id -> (session, state?)
  for (const auto& [id, c] : reader.channels()) {
    const auto slash = c.topic.find('/', 1);
    if (c.topic.size() < 2 || slash == std::string::npos) continue;
    const std::string sid = c.topic.substr(1, slash - 1), kind = c.topic.substr(slash + 1);
    if (!sent.count(sid)) continue;
    if (kind == "state") channel[id] = {sid, true};
    else if (kind == "applied") channel[id] = {sid, false};
  }
  std::map<std::string, Set> in_file;
  std::map<std::string, long long> file_states, file_dups, applied_in_file;
  for (const auto& [sid, n] : sent) in_file[sid].assign(static_cast<std::size_t>(n), 0);
  long long bad_json = 0, outside = 0;
  reader.readMessages([&](const groundsim::recording::McapMessage& m) {
    auto it = channel.find(m.channel);
    if (it == channel.end()) return;
    const std::string& sid = it->second.first;
    if (!it->second.second) {
      ++applied_in_file[sid];
      return;
    }
    ++file_states[sid];
    // the JSON says the same seq and session as the record
    const std::string want_seq = "\"seq\":" + std::to_string(m.sequence) + ",";
    if (m.data.find(want_seq) == std::string::npos || m.data.find("\"session_id\":\"" + sid + "\"") == std::string::npos)
      ++bad_json;
    Set& s = in_file[sid];
    if (m.sequence >= s.size()) {
      ++outside;
      return;
    }
    if (s[m.sequence]) ++file_dups[sid];
    s[m.sequence] = 1;
  });
  if (bad_json) fail(std::to_string(bad_json) + " state messages whose JSON seq or session_id is not the record's");
  if (outside) fail(std::to_string(outside) + " state messages with a seq never published");

  long long t_sent = 0, t_rec = 0, t_rep = 0, t_lost = 0, t_file = 0, t_heard = 0, t_heard_lost = 0,
            t_counter_missed = 0, t_heard_not_recv = 0, t_resent = 0;
  int sessions_lossy = 0;
  const auto& csessions = counter["sessions"];
  for (const auto& [sid, n] : sent) {
    t_sent += n;
    auto mit = meta.find("ledger/" + sid);
    if (mit == meta.end()) {
      fail(sid + ": no ledger in the file (" + std::to_string(n) + " states published)");
      continue;
    }
    const auto& kv = mit->second;
    if (get(kv, "state_first") != "0") fail(sid + ": the ledger starts at " + get(kv, "state_first") + ", not 0");
    if (get(kv, "state_newest") != std::to_string(n - 1))
      fail(sid + ": the ledger's newest is " + get(kv, "state_newest") + ", the last published " + std::to_string(n - 1));
    if (!get(kv, "state_missing").empty()) fail(sid + ": still missing at the end: " + get(kv, "state_missing"));
    Set rec, rep, lost;
    long long nrec = 0, nrep = 0, nlost = 0;
    if (!parseRanges(get(kv, "state_received"), n, rec, nrec)) fail(sid + ": state_received is not ranges of 0.." + std::to_string(n - 1));
    if (!parseRanges(get(kv, "state_repaired"), n, rep, nrep)) fail(sid + ": state_repaired is not ranges of 0.." + std::to_string(n - 1));
    if (!parseRanges(get(kv, "state_lost"), n, lost, nlost)) fail(sid + ": state_lost is not ranges of 0.." + std::to_string(n - 1));
    if (std::to_string(nrec) != get(kv, "state_received_count") || std::to_string(nrep) != get(kv, "state_repaired_count") ||
        std::to_string(nlost) != get(kv, "state_lost_count"))
      fail(sid + ": the _count keys disagree with the ranges");
    // every seq published: in exactly one of received, repaired, lost; in
    // the file exactly when received or repaired
    const Set& file = in_file[sid];
    long long unaccounted = 0, twice = 0, lost_but_in_file = 0, kept_not_in_file = 0;
    std::int64_t first_bad = -1;
    for (std::int64_t i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      const int ways = rec[k] + rep[k] + lost[k];
      if (ways == 0) ++unaccounted;
      if (ways > 1) ++twice;
      if (lost[k] && file[k]) ++lost_but_in_file;
      if ((rec[k] || rep[k]) && !file[k]) ++kept_not_in_file;
      if ((ways != 1 || (lost[k] && file[k]) || ((rec[k] || rep[k]) && !file[k])) && first_bad < 0) first_bad = i;
    }
    if (unaccounted) fail(sid + ": " + std::to_string(unaccounted) + " seqs published are in no ledger range (silent), first " + std::to_string(first_bad));
    if (twice) fail(sid + ": " + std::to_string(twice) + " seqs in two ledger ranges");
    if (lost_but_in_file) fail(sid + ": " + std::to_string(lost_but_in_file) + " seqs listed lost are in the file");
    if (kept_not_in_file) fail(sid + ": " + std::to_string(kept_not_in_file) + " seqs listed received or repaired are not in the file");
    if (file_dups[sid]) fail(sid + ": " + std::to_string(file_dups[sid]) + " states written twice");
    if (file_states[sid] != nrec + nrep)
      fail(sid + ": " + std::to_string(file_states[sid]) + " states in the file, the ledger says " + std::to_string(nrec + nrep));
    // every repair is a seq the ring resent
    Set resent(static_cast<std::size_t>(n), 0);
    long long nresent = 0;
    if (flood["resent"].contains(sid) &&
        !parseRanges(flood["resent"][sid].get<std::string>(), n, resent, nresent))
      fail(sid + ": the flood's resent seqs are not ranges of 0.." + std::to_string(n - 1));
    long long repaired_not_resent = 0;
    std::int64_t first_unsent = -1;
    for (std::int64_t i = 0; i < n; ++i)
      if (rep[static_cast<std::size_t>(i)] && !resent[static_cast<std::size_t>(i)]) {
        if (first_unsent < 0) first_unsent = i;
        ++repaired_not_resent;
      }
    if (repaired_not_resent)
      fail(sid + ": " + std::to_string(repaired_not_resent) + " seqs listed repaired that the ring never resent, first " +
           std::to_string(first_unsent));
    t_resent += nresent;
    // the END entry of the applied log (one entry, seq 0, with the last frame)
    const bool end_listed_missing = kv.count("applied_end_missing") > 0;
    const std::string applied_lost = get(kv, "applied_lost");
    // (its frame, the last state, listed lost takes it along: the recorder
    // owes an END entry only for an ending state it heard)
    const bool end_frame_lost = n > 0 && lost[static_cast<std::size_t>(n - 1)];
    if (applied_in_file[sid] != 1 && !end_listed_missing && applied_lost != "0" && !end_frame_lost)
      fail(sid + ": the applied END entry is neither in the file nor named missing or lost, nor its frame lost");
    // the subscriber
    if (!csessions.contains(sid)) {
      fail(sid + ": the subscriber heard nothing of it");
    } else {
      const auto& c = csessions[sid];
      Set heard;
      long long nheard = 0;
      if (!parseRanges(c["ranges"].get<std::string>(), n, heard, nheard))
        fail(sid + ": the subscriber heard seqs never published");
      long long heard_lost = 0, heard_not_recv = 0, silent = 0;
      for (std::int64_t i = 0; i < n; ++i) {
        const auto k = static_cast<std::size_t>(i);
        if (!heard[k]) continue;
        if (lost[k]) ++heard_lost;
        if (!rec[k]) ++heard_not_recv;
        if (!file[k] && !lost[k]) ++silent;
      }
      if (silent) fail(sid + ": " + std::to_string(silent) + " states the subscriber heard are neither in the file nor listed lost");
      const long long missed = c["missed"].get<long long>();
      if (nheard + missed != n)
        fail(sid + ": the subscriber's heard " + std::to_string(nheard) + " + missed " + std::to_string(missed) +
             " is not the " + std::to_string(n) + " published");
      t_heard += nheard;
      t_heard_lost += heard_lost;
      t_heard_not_recv += heard_not_recv;
      t_counter_missed += missed;
    }
    t_rec += nrec;
    t_rep += nrep;
    t_lost += nlost;
    t_file += file_states[sid];
    if (nlost) ++sessions_lossy;
  }
  // a ledger of a session never published
  for (const auto& [name, kv] : meta)
    if (name.rfind("ledger/", 0) == 0 && name != "ledger/events" && !sent.count(name.substr(7)))
      fail(name + ": a ledger of a session the flood never published");

  std::printf("sessions %zu: published %lld states; ledger: received %lld, repaired %lld, lost %lld (listed, in %d "
              "sessions); sum %lld; in the file %lld\n",
              sent.size(), t_sent, t_rec, t_rep, t_lost, sessions_lossy, t_rec + t_rep + t_lost, t_file);
  std::printf("subscriber: heard %lld, missed %lld (its own gaps, nothing repaired); of those it heard, the recorder "
              "had %lld only by repair or not at all, and lists %lld lost\n",
              t_heard, t_counter_missed, t_heard_not_recv, t_heard_lost);
  if (t_rec + t_rep + t_lost != t_sent) fail("the ledgers' received + repaired + lost is not what was published");
  if (t_rec == 0) fail("the recorder received nothing live: the check proves nothing");
  // repair where the ring answers, none where it does not
  const long long missed_live = t_rep + t_lost;
  std::printf("repair: ring %s; %lld re-requests answered with %lld states (%lld distinct seqs); the recorder missed "
              "%lld live: %lld repaired, %lld lost\n",
              ring ? "on" : "off", answers_requests, answers_resent, t_resent, missed_live, t_rep, t_lost);
  if (missed_live == 0)
    fail("the recorder missed nothing live (it is stalled while the flood goes on): repair was not exercised");
  if (ring) {
    if (answers_resent == 0) fail("the ring resent nothing, though the recorder missed " + std::to_string(missed_live));
    if (t_rep == 0) fail("the ring answers, yet none of the " + std::to_string(missed_live) + " seqs missed live was repaired");
  } else {
    if (answers_resent != 0 || t_resent != 0) fail("the flood ran without its ring, yet resent " + std::to_string(answers_resent));
    if (t_rep != 0) fail("no ring answers, yet " + std::to_string(t_rep) + " seqs are listed repaired");
  }
  if (failures.empty()) std::printf("accounting: every state published is in the file or listed lost; none silent\n");
  return failures.empty() ? 0 : 1;
}
