// `groundsim log SESSION... --csv FILE`: records published states with the
// columns of `groundsim run`'s CSV and accounts for every message. LCM drops
// silently when a subscription's queue (30 by default) or the socket buffer
// overflows, so this logger asks for an 8 MiB socket buffer and a deep queue,
// and counts gaps in each session's seq to prove nothing was lost.
#include <chrono>
#include <cstdio>
#include <map>

#include "channels.hpp"
#include "codec.hpp"
#include "convert.hpp"
#include "net_commands.hpp"
#include "telemetry_csv.hpp"

namespace groundsim::cli {
namespace {

struct Stream {
  long long received = 0;
  long long first_seq = -1, last_seq = -1;
  long long gaps = 0, lost = 0, duplicates = 0;
  bool ended = false;
};

}  // namespace

void registerLogCommand(CLI::App& app) {
  struct Opts {
    NetOptions net;
    std::vector<std::string> sessions;
    std::string csv;
    double duration = 0.0;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("log", "record sessions' states to CSV (the columns of `groundsim run`)");
  cmd->add_option("SESSION", o->sessions, "session ids")->required();
  cmd->add_option("--csv", o->csv, "output file ('-' for stdout)")->required();
  cmd->add_option("--duration", o->duration,
                  "wall seconds to record (0: until every session ends, or SIGINT)")->capture_default_str();
  addNetOptions(cmd, o->net, false);
  cmd->callback([o] {
    guarded([&] {
      installStopSignals();
      FILE* out = o->csv == "-" ? stdout : std::fopen(o->csv.c_str(), "w");
      if (!out) fail(kExitRefused, "cannot write " + o->csv);
      std::setvbuf(out, nullptr, _IOFBF, 1 << 20);
      std::fprintf(out, "%s\n", csvHeader().c_str());

      NetClient client(o->net.url, /*deep_receive=*/true);
      std::map<std::string, Stream> streams;
      for (const auto& s : o->sessions) streams[s];
      const bool prefix = o->sessions.size() > 1;  // vehicle column "SESSION/vehicle" when mixing sessions
      long long rows = 0;

      auto handler = [&](const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
        groundsim::state_t m;
        const auto d = net::decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), m, "groundsim.state_t");
        if (!d.ok()) {
          std::fprintf(stderr, "log: %s: %s\n", channel.c_str(), d.reason.c_str());
          return;
        }
        auto it = streams.find(m.session_id);
        if (it == streams.end()) return;
        Stream& st = it->second;
        if (st.last_seq >= 0 && m.seq <= st.last_seq) {
          ++st.duplicates;  // a reset does not restart seq: this is a repeat
          return;
        }
        if (st.last_seq >= 0 && m.seq > st.last_seq + 1) {
          ++st.gaps;
          st.lost += m.seq - st.last_seq - 1;
          std::fprintf(stderr, "log: %s: gap, seq %lld -> %lld (%lld lost)\n", m.session_id.c_str(), st.last_seq,
                       static_cast<long long>(m.seq), static_cast<long long>(m.seq - st.last_seq - 1));
        }
        if (st.first_seq < 0) st.first_seq = m.seq;
        st.last_seq = m.seq;
        ++st.received;
        st.ended = isFinal(m.status);
        for (int v = 0; v < m.nvehicles; ++v) {
          const std::string name = prefix ? m.session_id + "/" + m.vehicles[v].name : m.vehicles[v].name;
          std::fprintf(out, "%s\n", csvRow(net::toSample(m, v), name).c_str());
          ++rows;
        }
      };
      for (const auto& s : o->sessions)
        client.lcm()
            .subscribeFunction(
                net::stateChannel(s),
                +[](const lcm::ReceiveBuffer* rbuf, const std::string& ch, decltype(handler)* h) { (*h)(rbuf, ch); },
                &handler)
            ->setQueueCapacity(net::kDeepQueue);

      const auto start = std::chrono::steady_clock::now();
      auto allEnded = [&] {
        for (const auto& [id, st] : streams)
          if (!st.ended) return false;
        return true;
      };
      while (!stopRequested() && !allEnded()) {
        if (o->duration > 0 && std::chrono::steady_clock::now() - start > std::chrono::duration<double>(o->duration))
          break;
        client.lcm().handleTimeout(100);
      }
      // drain what already arrived
      while (client.lcm().handleTimeout(0) > 0) {
      }
      if (out != stdout) std::fclose(out);
      else std::fflush(out);

      long long lost = 0;
      for (const auto& [id, st] : streams) {
        std::fprintf(stderr, "log %s: %lld states received (seq %lld..%lld), %lld lost in %lld gaps%s\n", id.c_str(),
                     st.received, st.first_seq, st.last_seq, st.lost, st.gaps, st.ended ? ", session ended" : "");
        lost += st.lost;
      }
      std::fprintf(stderr, "log: %lld rows written to %s\n", rows, o->csv.c_str());
      if (lost > 0) fail(kExitLoss, std::to_string(lost) + " state messages lost");
    });
  });
}

}  // namespace groundsim::cli
