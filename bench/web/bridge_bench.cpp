// What the bridge adds per frame: a state datagram from the server decoded
// (with its checks), re-encoded as the page's JSON and handed to every
// watching browser's outbox; and per controls message: parsed, validated,
// mapped to a drive_t and encoded for LCM. Goal: well under 1 ms.
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bridge/browser_message.hpp"
#include "bridge/controls.hpp"
#include "bridge/state_json.hpp"
#include "protocol/codec.hpp"

namespace {

std::vector<char> encodedState(int nvehicles) {
  groundsim::state_t s{};
  s.session_id = "ABCDEF12";
  s.t = 12.345678;
  s.status = 1;
  s.nvehicles = nvehicles;
  s.vehicles.resize(nvehicles);
  for (int k = 0; k < nvehicles; ++k) {
    auto& v = s.vehicles[k];
    v.name = "car-" + std::to_string(k);
    for (int i = 0; i < 3; ++i) v.position[i] = 1.234567 * (i + k), v.velocity[i] = 0.5 * i;
    v.orientation[0] = 0.9998;
    v.orientation[3] = 0.0199;
    v.speed = 3.21;
    v.wheel_count = 4;
    for (int i = 0; i < 4; ++i) v.wheel_spin[i] = 3.2, v.normal_force[i] = 3.43, v.in_contact[i] = true;
  }
  std::vector<char> buf(s.getEncodedSize());
  s.encode(buf.data(), 0, static_cast<int>(buf.size()));
  return buf;
}

// One state frame through the bridge: decode, JSON, fan out to `watchers`.
void BM_StateFrame(benchmark::State& st) {
  const int nveh = static_cast<int>(st.range(0)), watchers = static_cast<int>(st.range(1));
  const std::vector<char> wire = encodedState(nveh);
  std::vector<std::shared_ptr<const std::string>> outbox(watchers);
  std::size_t bytes = 0;
  for (auto _ : st) {
    groundsim::state_t s;
    auto d = groundsim::net::decodeMessage(wire.data(), static_cast<int>(wire.size()), s, "groundsim.state_t");
    if (!d.ok()) st.SkipWithError("decode");
    auto json = std::make_shared<const std::string>(groundsim::web::stateJson(s, 1.0));
    for (auto& slot : outbox) slot = json;  // the newest frame replaces the stale one
    bytes = json->size();
    benchmark::DoNotOptimize(outbox.data());
  }
  st.counters["json_bytes"] = static_cast<double>(bytes);
}
BENCHMARK(BM_StateFrame)->Args({1, 1})->Args({4, 3})->Args({32, 8})->Unit(benchmark::kMicrosecond);

// One controls message from a browser to the LCM datagram.
void BM_ControlsMessage(benchmark::State& st) {
  const std::string text = R"({"op":"controls","throttle":0.7,"brake":0,"steer":-0.25,"handbrake":false,"gear":1,"seq":1234})";
  std::vector<char> buf(1024);
  for (auto _ : st) {
    auto m = groundsim::web::parseBrowserMessage(text);
    auto d = groundsim::web::toDrive(std::get<groundsim::web::ControlsMsg>(*m.message).controls, 0, 4);
    d.session_id = "ABCDEF12";
    d.token = "0123456789abcdef0123456789abcdef";
    d.client_id = "web-1-1";
    benchmark::DoNotOptimize(d.encode(buf.data(), 0, static_cast<int>(buf.size())));
  }
}
BENCHMARK(BM_ControlsMessage)->Unit(benchmark::kMicrosecond);

}  // namespace
