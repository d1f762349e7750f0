// record_state_counter: an independent subscriber for the recorder's
// checks (issue 23: "recorded beside an independent subscriber"). Its own
// LCM socket (8 MiB receive buffer, a deep queue, as the recorder asks
// for), nothing of the recorder's code: it decodes every state_t on
// GROUNDSIM_STATE_*, keeps which seqs of each session it heard, and from
// the heartbeat (server_status_t) each session's newest seq, so its own
// gaps are counted too. It repairs nothing. Until SIGINT/SIGTERM, then
// writes JSON: per session heard, the ranges heard, duplicates, the newest
// seq known (heard or listed) and missed (seqs 0..newest not heard).
//
//   record_state_counter --out FILE [--url URL]
#include <atomic>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include <groundsim/server_status_t.hpp>
#include <groundsim/state_t.hpp>

#include "protocol/channels.hpp"

namespace {

std::atomic<bool> g_stop{false};

struct Seen {
  std::vector<bool> heard;
  long long count = 0, duplicates = 0;
  std::int64_t listed = -1;  // newest seq a heartbeat listed
};

struct Counter {
  std::map<std::string, Seen> sessions;
  long long undecodable = 0, states = 0;

  void onState(const lcm::ReceiveBuffer* b, const std::string&) {
    groundsim::state_t m;
    if (m.decode(b->data, 0, static_cast<int>(b->data_size)) < 0 || m.seq < 0 || m.seq > (1 << 30)) {
      ++undecodable;
      return;
    }
    ++states;
    Seen& s = sessions[m.session_id];
    const auto i = static_cast<std::size_t>(m.seq);
    if (s.heard.size() <= i) s.heard.resize(std::max(i + 1, 2 * s.heard.size()), false);
    if (s.heard[i]) {
      ++s.duplicates;
      return;
    }
    s.heard[i] = true;
    ++s.count;
  }
  void onStatus(const lcm::ReceiveBuffer* b, const std::string&) {
    groundsim::server_status_t m;
    if (m.decode(b->data, 0, static_cast<int>(b->data_size)) < 0) return;
    for (const auto& in : m.sessions) {
      Seen& s = sessions[in.session_id];
      s.listed = std::max(s.listed, in.seq);
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  std::string out, url;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--out") out = argv[i + 1];
    else if (a == "--url") url = argv[i + 1];
  }
  if (out.empty()) {
    std::fprintf(stderr, "usage: record_state_counter --out FILE [--url URL]\n");
    return 2;
  }
  std::signal(SIGINT, [](int) { g_stop = true; });
  std::signal(SIGTERM, [](int) { g_stop = true; });
  lcm::LCM lcm(groundsim::net::withReceiveBuffer(url));
  if (!lcm.good()) {
    std::fprintf(stderr, "record_state_counter: cannot open LCM\n");
    return 1;
  }
  Counter c;
  lcm.subscribe(std::string(groundsim::net::kStatePrefix) + ".*", &Counter::onState, &c)
      ->setQueueCapacity(groundsim::net::kDeepQueue);
  lcm.subscribe(groundsim::net::kStatusChannel, &Counter::onStatus, &c)->setQueueCapacity(groundsim::net::kDeepQueue);
  std::fprintf(stderr, "record_state_counter: listening\n");
  while (!g_stop) lcm.handleTimeout(100);
  // what is still queued was heard: drain it
  while (lcm.handleTimeout(50) > 0) {
  }

  std::ofstream f(out + ".tmp");
  f << "{\"states\": " << c.states << ", \"undecodable\": " << c.undecodable << ", \"sessions\": {";
  bool first = true;
  for (const auto& [id, s] : c.sessions) {
    std::int64_t newest = s.listed;
    for (std::int64_t i = static_cast<std::int64_t>(s.heard.size()) - 1; i > newest; --i)
      if (s.heard[static_cast<std::size_t>(i)]) {
        newest = i;
        break;
      }
    std::string ranges;
    for (std::int64_t i = 0; i < static_cast<std::int64_t>(s.heard.size()); ++i) {
      if (!s.heard[static_cast<std::size_t>(i)]) continue;
      std::int64_t j = i;
      while (j + 1 < static_cast<std::int64_t>(s.heard.size()) && s.heard[static_cast<std::size_t>(j + 1)]) ++j;
      if (!ranges.empty()) ranges += ',';
      ranges += std::to_string(i);
      if (j > i) {
        ranges += '-';
        ranges += std::to_string(j);
      }
      i = j;
    }
    f << (first ? "" : ", ") << '"' << id << "\": {\"heard\": " << s.count << ", \"duplicates\": " << s.duplicates
      << ", \"newest\": " << newest << ", \"missed\": " << (newest + 1 - s.count) << ", \"ranges\": \"" << ranges
      << "\"}";
    first = false;
  }
  f << "}}\n";
  f.close();
  std::rename((out + ".tmp").c_str(), out.c_str());
  std::fprintf(stderr, "record_state_counter: %lld states heard, %lld undecodable\n", c.states, c.undecodable);
  return 0;
}
