// `groundsim replay --resimulate FILE.mcap [--session ID] [--assets DIR]`
// (docs/logging.md, Re-simulation): re-simulates a recorded session from
// the scenario attached to the file and its applied-command log
// (/<session>/applied), and compares every recorded state, car state and
// contact state with the re-simulated one.
// - The re-simulated frame goes through the server's own conversion
//   (net::toMessage) and the recorder's own JSON writer with the precision
//   the recording was made with, so equal text is equal values: a file
//   recorded --exact is compared to the bit (the shortest text that reads
//   back as the same double; -0 and 0 differ). Otherwise (each quantity's
//   decimals, the default, or N digits) the comparison is at that
//   precision, and the report says so.
// - With --raw recordings, the raw LCM bytes of each state are compared too
//   (bit for bit, whatever the JSON's precision).
// - Not re-simulated but taken from the recording: mode, status, reason,
//   epoch and the live error estimate.
// - The first difference is reported: seq, time, tick, the field, the
//   recorded and the re-simulated value. Exit 0 identical, 5 a difference,
//   1 the file cannot be re-simulated (no scenario, no applied log, a
//   recording that began after the session did, ...).
#include <charconv>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lcm/convert.hpp"
#include "net/common.hpp"
#include "protocol/channels.hpp"
#include "protocol/text.hpp"
#include "protocol/message_json.hpp"
#include "recording/mcap_reader.hpp"
#include "stepping/resimulate.hpp"

namespace groundsim::cli {
namespace {

constexpr int kExitDiffers = 5;

struct ReplayOptions {
  std::string file, session, assets_dir;
  bool resimulate = false;
};

std::string exactText(double x) {
  char b[32];
  const auto r = std::to_chars(b, b + sizeof b, x);
  return std::string(b, r.ptr);
}

std::string leafText(const nlohmann::json& j) {
  if (j.is_number_float()) return exactText(j.get<double>());
  return j.dump();
}

bool sameLeaf(const nlohmann::json& a, const nlohmann::json& b) {
  if (a.is_number() && b.is_number()) {
    const double x = a.get<double>(), y = b.get<double>();
    std::uint64_t u, v;
    std::memcpy(&u, &x, 8);
    std::memcpy(&v, &y, 8);
    return u == v;
  }
  return a == b;
}

// The first leaf (in the recorded message's field order) where the two
// differ: its path, e.g. "vehicles[0].position[2]".
std::optional<std::string> firstDifference(const nlohmann::json& rec, const nlohmann::json& sim, const std::string& path,
                                           std::string* rv, std::string* sv) {
  if (rec.is_object() && sim.is_object()) {
    for (auto it = rec.begin(); it != rec.end(); ++it) {
      const std::string p = path.empty() ? it.key() : path + "." + it.key();
      if (!sim.contains(it.key())) {
        *rv = leafText(it.value());
        *sv = "(absent)";
        return p;
      }
      if (auto d = firstDifference(it.value(), sim.at(it.key()), p, rv, sv)) return d;
    }
    for (auto it = sim.begin(); it != sim.end(); ++it)
      if (!rec.contains(it.key())) {
        *rv = "(absent)";
        *sv = leafText(it.value());
        return path.empty() ? it.key() : path + "." + it.key();
      }
    return std::nullopt;
  }
  if (rec.is_array() && sim.is_array()) {
    for (size_t i = 0; i < rec.size() && i < sim.size(); ++i)
      if (auto d = firstDifference(rec[i], sim[i], path + "[" + std::to_string(i) + "]", rv, sv)) return d;
    if (rec.size() != sim.size()) {
      *rv = std::to_string(rec.size()) + " elements";
      *sv = std::to_string(sim.size()) + " elements";
      return path + " (length)";
    }
    return std::nullopt;
  }
  if (sameLeaf(rec, sim)) return std::nullopt;
  *rv = leafText(rec);
  *sv = leafText(sim);
  return path;
}

stepping::Applied appliedFrom(const nlohmann::json& j) {
  stepping::Applied a;
  a.session_id = j.value("session_id", "");
  a.seq = j.at("seq").get<std::int64_t>();
  a.frame_seq = j.at("frame_seq").get<std::int64_t>();
  a.tick = j.at("tick").get<std::int64_t>();
  a.t = j.at("t").get<double>();
  a.kind = static_cast<stepping::AppliedKind>(j.at("kind").get<int>());
  a.vehicle = j.at("vehicle").get<int>();
  const auto& dt = j.at("drive_torque");
  const auto& bt = j.at("brake_torque");
  const auto& st = j.at("steer");
  for (size_t k = 0; k < dt.size() && k < bt.size() && k < st.size(); ++k)
    a.wheels.push_back(WheelControl{dt[k].get<double>(), bt[k].get<double>(), st[k].get<double>()});
  a.controls.throttle = j.at("throttle").get<double>();
  a.controls.brake = j.at("brake").get<double>();
  a.controls.steer = j.at("car_steer").get<double>();
  a.controls.handbrake = j.at("handbrake").get<bool>();
  a.controls.gear = j.at("gear").get<int>();
  const auto& wt = j.at("wheel_torque");
  for (size_t k = 0; k < 4 && k < wt.size(); ++k) a.controls.wheel_torque[k] = wt[k].get<double>();
  a.steps = j.value("steps", std::int64_t{0});
  a.reason = j.value("reason", "");
  return a;
}

// Metadata records by name (McapReader::metadata()).
using FileMetadata = std::map<std::string, std::map<std::string, std::string>>;

// The session a file holds, and the channel of each of its kinds.
struct RecordedSession {
  std::string id;
  std::map<std::string, std::uint16_t> kinds;  // "state", "car_state", "contact", "applied" -> channel
  int raw_state = -1;                           // the raw LCM channel of its states (--raw), or -1
  int channel(const char* kind) const {
    const auto it = kinds.find(kind);
    return it == kinds.end() ? -1 : it->second;
  }
};

// --session, or the one session whose states the file holds
RecordedSession findSession(const recording::McapReader& r, const ReplayOptions& o) {
  std::map<std::string, std::map<std::string, std::uint16_t>> topics;  // session -> kind -> channel
  for (const auto& [ch, c] : r.channels()) {
    if (c.topic.empty() || c.topic[0] != '/') continue;
    const auto slash = c.topic.find('/', 1);
    if (slash == std::string::npos) continue;
    topics[c.topic.substr(1, slash - 1)][c.topic.substr(slash + 1)] = ch;
  }
  std::map<std::string, std::uint16_t> raw_state;  // session -> raw channel of its states
  for (const auto& [ch, c] : r.channels())
    if (c.message_encoding == "lcm" && c.topic.rfind(std::string("lcm/") + net::kStatePrefix, 0) == 0)
      raw_state[c.topic.substr(4 + std::strlen(net::kStatePrefix))] = ch;
  std::vector<std::string> sessions;
  for (const auto& [sid, kinds] : topics)
    if (kinds.count("state")) sessions.push_back(sid);
  RecordedSession out;
  out.id = o.session;
  if (out.id.empty()) {
    if (sessions.size() != 1) {
      std::string list;
      for (const auto& sid : sessions) list += (list.empty() ? "" : ", ") + sid;
      fail(kExitRefused, net::quoted(o.file) + " holds " + std::to_string(sessions.size()) + " sessions (" + list +
                             "): name one with --session");
    }
    out.id = sessions.front();
  } else if (!topics.count(out.id) || !topics[out.id].count("state")) {
    fail(kExitRefused, net::quoted(o.file) + " holds no session " + net::quoted(out.id));
  }
  out.kinds = topics[out.id];
  if (!out.kinds.count("applied"))
    fail(kExitRefused, "session " + out.id + ": the file has no applied-command log (/" + out.id +
                           "/applied; recorded by a server or recorder from before it)");
  if (raw_state.count(out.id)) out.raw_state = raw_state[out.id];
  return out;
}

// the scenario and the files it names, attached to the file
std::string attachedScenario(recording::McapReader& r, const std::string& id, scenario::AssetBytes& assets) {
  std::string scenario;
  const std::string asset_prefix = "assets/" + id + "/";
  for (auto& [name, data] : r.attachments()) {
    if (name == "scenario/" + id + ".json") scenario = data;
    else if (name.rfind(asset_prefix, 0) == 0)
      assets[name.substr(asset_prefix.size())] = std::make_shared<const std::string>(std::move(data));
  }
  if (scenario.empty()) fail(kExitRefused, "session " + id + ": the file holds no scenario (scenario/" + id + ".json)");
  return scenario;
}

// The precision the states were written with (json_digits: files from
// before json_precision), set for the writer; a file that names none was
// written exactly. Whether the file named it.
bool usePrecisionOf(const FileMetadata& meta) {
  record::Precision precision = record::Precision::Exact;
  int digits = 17;
  bool known = false;
  if (auto it = meta.find("groundsim"); it != meta.end()) {
    auto d = it->second.find("json_precision");
    if (d == it->second.end()) d = it->second.find("json_digits");
    if (d != it->second.end()) {
      known = record::parsePrecision(d->second, &precision, &digits);
      if (!known)
        fail(kExitRefused, "the file's metadata groundsim/" + d->first + " is " + net::quoted(d->second) +
                               ": not a precision this program writes (fields-1, exact, digits-N)");
    }
  }
  record::setPrecision(precision, digits);
  return known;
}

// The session's messages, by seq.
struct Recorded {
  std::map<std::int64_t, std::string> states, cars, contacts, raws;
  std::map<std::int64_t, stepping::Applied> applied;
};

Recorded readSession(recording::McapReader& r, const RecordedSession& rs) {
  Recorded out;
  const int state_ch = rs.channel("state"), car_ch = rs.channel("car_state"), contact_ch = rs.channel("contact"),
            applied_ch = rs.channel("applied"), raw_ch = rs.raw_state;
  std::set<std::uint16_t> wanted;
  for (int c : {state_ch, car_ch, contact_ch, applied_ch, raw_ch})
    if (c >= 0) wanted.insert(static_cast<std::uint16_t>(c));
  std::string bad;
  r.readMessages(
      [&](const recording::McapMessage& m) {
        if (m.channel == raw_ch) {
          out.raws.emplace(m.sequence, m.data);  // seq mod 2^32: sessions of fewer states than that
          return;
        }
        nlohmann::json j = nlohmann::json::parse(m.data, nullptr, false);
        if (j.is_discarded() || !j.is_object() || !j.contains("seq")) {
          if (bad.empty()) bad = "a message on channel " + std::to_string(m.channel) + " is not the JSON expected";
          return;
        }
        const auto seq = j["seq"].get<std::int64_t>();
        if (m.channel == state_ch) out.states.emplace(seq, m.data);
        else if (m.channel == car_ch) out.cars.emplace(seq, m.data);
        else if (m.channel == contact_ch) out.contacts.emplace(seq, m.data);
        else if (m.channel == applied_ch) {
          try {
            out.applied.emplace(seq, appliedFrom(j));
          } catch (const std::exception& e) {
            if (bad.empty()) bad = "applied command " + std::to_string(seq) + ": " + e.what();
          }
        }
      },
      wanted);
  const std::string& id = rs.id;
  if (!bad.empty()) fail(kExitRefused, "session " + id + ": " + bad);
  if (out.states.empty()) fail(kExitRefused, "session " + id + ": no states recorded");
  if (out.states.begin()->first != 0)
    fail(kExitRefused, "session " + id + ": the recording begins at state seq " +
                           std::to_string(out.states.begin()->first) +
                           ", not 0: it began after the session did, and re-simulation needs the session from its "
                           "start (record --create, or start the recorder first)");
  return out;
}

// what the ledger says of the log: a gap is named before anything else
std::vector<std::string> gapsInTheLog(const Recorded& rec, const FileMetadata& meta,
                                      const std::string& id) {
  std::vector<std::string> warnings;
  std::int64_t expect = 0;
  for (const auto& [seq, a] : rec.applied) {
    if (seq != expect)
      warnings.push_back("applied commands " + std::to_string(expect) + ".." + std::to_string(seq - 1) +
                         " are missing from the file");
    expect = seq + 1;
  }
  if (auto it = meta.find("ledger/" + id); it != meta.end()) {
    for (const char* k : {"applied_lost", "applied_end_missing", "state_lost"})
      if (auto v = it->second.find(k); v != it->second.end() && !v->second.empty())
        warnings.push_back(std::string("the ledger's ") + k + ": " + net::printable(v->second, 200));
  }
  for (const auto& w : warnings) std::fprintf(stderr, "replay: %s: %s\n", id.c_str(), w.c_str());
  return warnings;
}

// Every recorded state, in seq order, against the re-simulation: the
// applied commands due before it replayed, stepped to its tick, its frame
// written as the server and the recorder would, then its raw bytes, car
// state and contact state. The first difference ends the comparison.
class Comparison {
 public:
  Comparison(const std::string& id, const Recorded& rec, stepping::Resimulator& sim, bool bitwise, bool raw)
      : id_(id), rec_(rec), sim_(sim), bitwise_(bitwise), raw_(raw), next_(rec.applied.begin()) {}

  // 0 when every state matched, else kExitDiffers (the difference printed)
  int run() {
    for (const auto& [seq, text] : rec_.states)
      if (const std::optional<int> code = compareState(seq, text)) return *code;
    return 0;
  }

  std::int64_t states = 0, cars = 0, contacts = 0, raws = 0;

 private:
  std::optional<int> compareState(std::int64_t seq, const std::string& text) {
    const nlohmann::json rec = nlohmann::json::parse(text, nullptr, false);
    for (; next_ != rec_.applied.end() && next_->second.frame_seq <= seq; ++next_) {
      if (std::string why = sim_.apply(next_->second); !why.empty())
        return differ("state", seq, rec,
                      "applied command " + std::to_string(next_->first) + " (" +
                          stepping::appliedKindName(next_->second.kind) + " at tick " +
                          std::to_string(next_->second.tick) + ")",
                      "applied", "cannot be: " + why);
    }
    const std::int64_t tick = rec.value("tick", std::int64_t{-1});
    if (std::string why = sim_.stepTo(tick); !why.empty())
      return differ("state", seq, rec, "tick", std::to_string(tick), why);
    stepping::Frame f = frameAsRecorded(seq, rec);
    const groundsim::state_t m = net::toMessage(f);
    if (auto code = differsFrom("state", seq, record::toJson(m), text)) return code;
    ++states;
    if (auto code = compareRaw(seq, rec, m)) return code;
    // A car or contact state names its own publisher: an owner killed
    // between a state and its car state leaves the new owner's copy of the
    // car state (published again, equal but for the epoch) in the file.
    // Compared as the state's publisher's first; only a difference reads
    // the message's own epoch.
    if (auto it = rec_.cars.find(seq); it != rec_.cars.end()) {
      if (auto code = sameAs("car state", seq, f, [](const stepping::Frame& g) { return net::toCarMessage(g); },
                             it->second))
        return code;
      ++cars;
    }
    if (auto it = rec_.contacts.find(seq); it != rec_.contacts.end()) {
      if (auto code = sameAs("contact state", seq, f,
                             [](const stepping::Frame& g) { return net::toContactMessage(g); }, it->second))
        return code;
      ++contacts;
    }
    return std::nullopt;
  }

  // the re-simulated frame with what is taken from the recording, not
  // re-simulated: mode, status, reason, who owned the session, and the live
  // estimate (stepped beside the session, not by it)
  stepping::Frame frameAsRecorded(std::int64_t seq, const nlohmann::json& rec) const {
    stepping::Frame f = sim_.frame();
    f.session_id = rec.value("session_id", id_);
    f.seq = seq;
    f.mode = static_cast<stepping::Mode>(rec.value("mode", 1));
    f.status = static_cast<stepping::Status>(rec.value("status", 1));
    f.reason = rec.value("status_reason", "");
    f.epoch = rec.value("epoch", std::int64_t{0});
    if (auto e = rec.find("error_estimate"); e != rec.end() && e->is_number()) f.error_estimate = e->get<double>();
    return f;
  }

  std::optional<int> compareRaw(std::int64_t seq, const nlohmann::json& rec, const groundsim::state_t& m) {
    if (!raw_) return std::nullopt;
    const auto it = rec_.raws.find(static_cast<std::uint32_t>(seq));
    if (it == rec_.raws.end()) return std::nullopt;
    std::string bytes(static_cast<size_t>(m.getEncodedSize()), '\0');
    m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    if (bytes != it->second) return differ("state (raw LCM bytes)", seq, rec, "bytes", "recorded", "differ");
    ++raws;
    return std::nullopt;
  }

  template <class Encode>
  std::optional<int> sameAs(const char* what, std::int64_t seq, stepping::Frame& f, Encode encode,
                            const std::string& recorded) {
    if (record::toJson(encode(f)) == recorded) return std::nullopt;
    const std::int64_t state_epoch = f.epoch;
    const nlohmann::json j = nlohmann::json::parse(recorded, nullptr, false);
    f.epoch = j.is_object() ? j.value("epoch", state_epoch) : state_epoch;
    std::optional<int> code = differsFrom(what, seq, record::toJson(encode(f)), recorded);
    f.epoch = state_epoch;
    return code;
  }

  // a message against its recorded text: the first differing field's exit,
  // or nothing when the two are the same
  std::optional<int> differsFrom(const char* what, std::int64_t seq, const std::string& mine,
                                 const std::string& recorded) const {
    if (mine == recorded) return std::nullopt;
    std::string rv, sv;
    const nlohmann::json rc = nlohmann::json::parse(recorded);
    const auto field = firstDifference(rc, nlohmann::json::parse(mine), "", &rv, &sv);
    return differ(what, seq, rc, field.value_or("(text)"), rv, sv);
  }

  int differ(const char* what, std::int64_t seq, const nlohmann::json& rec, const std::string& field,
             const std::string& rv, const std::string& sv) const {
    std::printf("differs: session %s, %s seq %lld (t %s s, tick %lld): %s recorded %s, re-simulated %s\n", id_.c_str(),
                what, static_cast<long long>(seq), leafText(rec.value("t", nlohmann::json(0.0))).c_str(),
                static_cast<long long>(sim_.tick()), field.c_str(), rv.c_str(), sv.c_str());
    if (!bitwise_) std::printf("compared at the recording's precision: %s\n", record::precisionName().c_str());
    std::printf("applied commands replayed before it: %lld of %zu\n",
                static_cast<long long>(std::distance(rec_.applied.begin(), next_)), rec_.applied.size());
    return kExitDiffers;
  }

  const std::string& id_;
  const Recorded& rec_;
  stepping::Resimulator& sim_;
  const bool bitwise_, raw_;
  std::map<std::int64_t, stepping::Applied>::const_iterator next_;
};

int resimulate(const ReplayOptions& o) {
  recording::McapReader r(o.file);
  const RecordedSession rs = findSession(r, o);
  const std::string& id = rs.id;
  auto assets = std::make_shared<scenario::AssetBytes>();
  const std::string scenario = attachedScenario(r, id, *assets);
  const auto meta = r.metadata();
  const bool precision_known = usePrecisionOf(meta);
  const bool bitwise = record::precision() == record::Precision::Exact;
  const Recorded recorded = readSession(r, rs);
  const std::vector<std::string> warnings = gapsInTheLog(recorded, meta, id);

  std::optional<stepping::Resimulator> sim;
  try {
    sim.emplace(scenario, scenario::FileAccess::fromAssets(assets, o.assets_dir));
  } catch (const std::exception& e) {
    fail(kExitRefused, "session " + id + ": the recorded scenario cannot be built: " + net::printable(e.what(), 600) +
                           (assets->empty() && o.assets_dir.empty() ? " (files it names: give --assets DIR)" : ""));
  }
  Comparison compare(id, recorded, *sim, bitwise, rs.raw_state >= 0);
  if (const int code = compare.run(); code != 0) return code;

  std::printf("identical: session %s, %lld states, %lld car states, %lld contact states re-simulated from its "
              "scenario and %zu applied commands (last state seq %lld, tick %lld)\n",
              id.c_str(), static_cast<long long>(compare.states), static_cast<long long>(compare.cars),
              static_cast<long long>(compare.contacts), recorded.applied.size(),
              static_cast<long long>(recorded.states.rbegin()->first), static_cast<long long>(sim->tick()));
  if (bitwise)
    std::printf("compared bit for bit: every double as the shortest text that reads back as the same double%s\n",
                precision_known ? "" : " (the file does not say its precision: taken as exact)");
  else
    std::printf("compared at the recording's precision only: %s (record with --exact for a bit-exact "
                "comparison)\n", record::precisionName().c_str());
  if (compare.raws > 0) std::printf("raw LCM bytes identical too: %lld states\n", static_cast<long long>(compare.raws));
  if (!warnings.empty()) {
    std::printf("but the file is incomplete (above): a difference may hide in what is missing\n");
    return kExitDiffers;
  }
  return 0;
}

}  // namespace

void registerReplayCommand(CLI::App& app) {
  auto o = std::make_shared<ReplayOptions>();
  auto* cmd = app.add_subcommand("replay", "re-simulate a recorded session and compare its states (docs/logging.md)");
  cmd->add_option("FILE", o->file, "an .mcap recording")->required();
  cmd->add_flag("--resimulate", o->resimulate, "re-simulate from the scenario and the applied-command log")->required();
  cmd->add_option("--session", o->session, "the session (needed when the file holds several)");
  cmd->add_option("--assets", o->assets_dir, "a folder holding files the scenario names that the file does not");
  cmd->callback([o] {
    int rc = 0;
    try {
      rc = resimulate(*o);
    } catch (const std::exception& e) {
      fail(kExitRefused, net::printable(e.what(), 600));
    }
    if (rc) throw CLI::RuntimeError(rc);
  });
}

}  // namespace groundsim::cli
