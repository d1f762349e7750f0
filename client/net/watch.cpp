// `groundsim watch SESSION`: live state on the terminal. On a terminal one
// line is redrawn (at most 10 times a second); otherwise every state is
// printed on its own line, so the output can be piped or tested. Ends at
// the session's final state, or when the server's heartbeat says the
// session ended (its final state lost) or is not there; exits with
// kExitNoServer when the heartbeat stops.
#include <chrono>
#include <optional>
#include <algorithm>
#include <cstdio>

#include <unistd.h>

#include "protocol/channels.hpp"
#include "protocol/codec.hpp"
#include "protocol/names.hpp"
#include "protocol/text.hpp"
#include "common.hpp"

namespace groundsim::cli {

void registerWatchCommand(CLI::App& app) {
  struct Opts {
    NetOptions net;
    std::string session;
    long long count = 0;
    double duration = 0.0;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("watch", "show a session's state as it is published");
  cmd->add_option("SESSION", o->session, "session id")->required();
  cmd->add_option("--count", o->count, "stop after this many states (0: no limit)")->capture_default_str();
  cmd->add_option("--duration", o->duration, "stop after this many wall seconds (0: no limit)")->capture_default_str();
  addNetOptions(cmd, o->net, false);
  cmd->callback([o] {
    guarded([&] {
      installStopSignals();
      NetClient client(o->net.url, /*deep_receive=*/true);
      const bool tty = ::isatty(STDOUT_FILENO);
      long long received = 0, lost = 0;
      long long last_seq = -1;
      bool ended = false;
      auto last_draw = std::chrono::steady_clock::time_point{};
      groundsim::state_t latest;
      auto handler = [&](const lcm::ReceiveBuffer* rbuf, const std::string&) {
        groundsim::state_t m;
        if (!net::decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), m, "groundsim.state_t").ok()) return;
        if (last_seq >= 0 && m.seq > last_seq + 1) lost += m.seq - last_seq - 1;
        last_seq = std::max<long long>(last_seq, m.seq);
        ++received;
        ended = ended || net::isFinal(m.status);
        const auto now = std::chrono::steady_clock::now();
        if (!tty) {
          std::printf("%s\n", stateLine(m).c_str());
          std::fflush(stdout);
        } else if (ended || now - last_draw > std::chrono::milliseconds(100)) {
          std::printf("\r\033[K%s", stateLine(m).c_str());
          std::fflush(stdout);
          last_draw = now;
        }
      };
      auto* sub = client.lcm().subscribeFunction(
          net::stateChannel(o->session),
          +[](const lcm::ReceiveBuffer* rbuf, const std::string& ch, decltype(handler)* h) { (*h)(rbuf, ch); },
          &handler);
      sub->setQueueCapacity(net::kDeepQueue);
      std::fprintf(stderr, "watch %s: subscribed on %s\n", net::printable(o->session).c_str(), client.url().c_str());
      const auto start = std::chrono::steady_clock::now();
      const long long rounds_at_start = client.server().rounds();
      std::optional<std::chrono::steady_clock::time_point> final_listed;
      std::optional<long long> missing_since;
      std::string note, server_lost;
      bool unknown = false;
      while (!stopRequested() && !ended && (o->count <= 0 || received < o->count)) {
        const auto now = std::chrono::steady_clock::now();
        if (o->duration > 0 && now - start > std::chrono::duration<double>(o->duration)) break;
        try {
          client.pump(100);
        } catch (const NetError& e) {
          server_lost = e.what();
          break;
        }
        const auto info = client.server().session(o->session);
        // listed by no server for two rounds of every server's heartbeat (a
        // fleet moves a session in a few seconds): gone
        const long long rounds = client.server().rounds();
        if (info) missing_since.reset();
        else if (!missing_since) missing_since = rounds;
        if (!info && rounds >= std::max(rounds_at_start, *missing_since) + 2) {
          ended = true;
          unknown = received == 0;
          note = received == 0 ? "not on the server" : "no longer on the server";
        } else if (info && net::isFinal(info->status)) {
          if (!final_listed) final_listed = now;
          if (now - *final_listed > std::chrono::duration<double>(1.5 * net::kHeartbeatPeriod)) {
            ended = true;
            note = std::string(net::statusName(info->status)) + " (from the server's heartbeat)";
            if (info->seq > last_seq) lost += info->seq - last_seq;
          }
        }
      }
      if (tty) std::printf("\n");
      std::fprintf(stderr, "watch %s: %lld states received, %lld lost%s%s\n", net::printable(o->session).c_str(),
                   received, lost, note.empty() ? "" : "; session ", note.c_str());
      if (!server_lost.empty()) fail(kExitNoServer, server_lost);
      if (unknown) fail(kExitRefused, "session " + net::quoted(o->session) + " is not on the server");
    });
  });
}

}  // namespace groundsim::cli
