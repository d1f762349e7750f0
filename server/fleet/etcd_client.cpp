#include "fleet/etcd_client.hpp"

#include <algorithm>
#include <sstream>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

#include "fleet/http.hpp"

namespace groundsim::fleet {

using nlohmann::json;

EtcdError::EtcdError(std::string endpoint, std::string reason, bool transport, int grpc_code)
    : std::runtime_error("etcd " + endpoint + ": " + reason),
      endpoint_(std::move(endpoint)),
      reason_(std::move(reason)),
      transport_(transport),
      grpc_code_(grpc_code) {}

namespace {

// gRPC status codes the gateway reports (google.golang.org/grpc/codes)
constexpr int kDeadlineExceeded = 4;
constexpr int kNotFound = 5;
constexpr int kUnavailable = 14;

std::int64_t i64(const json& j, const char* name) {
  auto it = j.find(name);
  if (it == j.end() || it->is_null()) return 0;
  if (it->is_string()) return std::stoll(it->get<std::string>());
  if (it->is_number()) return it->get<std::int64_t>();
  if (it->is_boolean()) return it->get<bool>() ? 1 : 0;
  throw std::invalid_argument(std::string("etcd answer: field ") + name + " is not a number");
}

std::string bytes(const json& j, const char* name) {
  auto it = j.find(name);
  if (it == j.end() || it->is_null()) return {};
  return EtcdClient::base64Decode(it->get<std::string>());
}

Kv parseKv(const json& j) {
  Kv kv;
  kv.key = bytes(j, "key");
  kv.value = bytes(j, "value");
  kv.create_revision = i64(j, "create_revision");
  kv.mod_revision = i64(j, "mod_revision");
  kv.version = i64(j, "version");
  kv.lease = i64(j, "lease");
  return kv;
}

std::vector<Kv> parseKvs(const json& j) {
  std::vector<Kv> out;
  auto it = j.find("kvs");
  if (it == j.end()) return out;
  for (const auto& kv : *it) out.push_back(parseKv(kv));
  return out;
}

std::int64_t headerRevision(const json& j) {
  auto it = j.find("header");
  return it == j.end() ? 0 : i64(*it, "revision");
}

json rangeBody(const std::string& key, bool prefix) {
  json body;
  if (prefix) {
    body["key"] = EtcdClient::base64Encode(key.empty() ? std::string(1, '\0') : key);
    body["range_end"] = EtcdClient::base64Encode(EtcdClient::prefixEnd(key));
  } else {
    body["key"] = EtcdClient::base64Encode(key);
  }
  return body;
}

json putBody(const std::string& key, const std::string& value, std::int64_t lease) {
  json body{{"key", EtcdClient::base64Encode(key)}, {"value", EtcdClient::base64Encode(value)}};
  if (lease != 0) body["lease"] = std::to_string(lease);
  return body;
}

json opJson(const Op& op) {
  switch (op.kind) {
    case Op::Kind::Put: return {{"request_put", putBody(op.key, op.value, op.lease)}};
    case Op::Kind::Get: return {{"request_range", rangeBody(op.key, false)}};
    case Op::Kind::GetPrefix: return {{"request_range", rangeBody(op.key, true)}};
    case Op::Kind::Delete: return {{"request_delete_range", rangeBody(op.key, false)}};
    case Op::Kind::DeletePrefix: return {{"request_delete_range", rangeBody(op.key, true)}};
  }
  return {};
}

json compareJson(const Compare& c) {
  static const char* targets[] = {"VERSION", "CREATE", "MOD", "VALUE", "LEASE"};
  static const char* results[] = {"EQUAL", "GREATER", "LESS", "NOT_EQUAL"};
  json j{{"key", EtcdClient::base64Encode(c.key)},
         {"target", targets[static_cast<int>(c.target)]},
         {"result", results[static_cast<int>(c.result)]}};
  switch (c.target) {
    case Compare::Target::Version: j["version"] = std::to_string(c.number); break;
    case Compare::Target::Create: j["create_revision"] = std::to_string(c.number); break;
    case Compare::Target::Mod: j["mod_revision"] = std::to_string(c.number); break;
    case Compare::Target::Lease: j["lease"] = std::to_string(c.number); break;
    case Compare::Target::Value: j["value"] = EtcdClient::base64Encode(c.value); break;
  }
  return j;
}

// The streaming endpoints (lease keepalive, watch) wrap each message as
// {"result": ...} or {"error": ...}; a unary answer is the message itself.
// A stream answer may hold several lines: the first message counts.
json firstMessage(const std::string& body) {
  std::istringstream lines(body);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    return json::parse(line);
  }
  return json::object();
}

struct Refusal {
  std::string reason;
  int code = -1;
  bool retry_elsewhere = false;  // the member cannot serve now: another may
};

// An error answer: {"error": "...", "message": "...", "code": n} (unary) or
// {"error": {"grpc_code": n, "http_code": n, "message": "..."}} (stream).
std::optional<Refusal> refusal(unsigned status, const json& j) {
  const json* err = nullptr;
  if (j.is_object()) {
    auto it = j.find("error");
    if (it != j.end() && !it->is_null()) err = &*it;
  }
  if (status == 200 && err == nullptr) return std::nullopt;
  Refusal r;
  if (err != nullptr && err->is_object()) {
    r.reason = err->value("message", std::string("error"));
    r.code = static_cast<int>(err->contains("grpc_code") ? i64(*err, "grpc_code") : i64(*err, "code"));
  } else if (err != nullptr && err->is_string()) {
    r.reason = j.value("message", err->get<std::string>());
    r.code = j.contains("code") ? static_cast<int>(i64(j, "code")) : -1;
  } else {
    r.reason = "HTTP " + std::to_string(status);
  }
  r.retry_elsewhere = r.code == kUnavailable || r.code == kDeadlineExceeded || (r.code < 0 && status >= 500);
  return r;
}

}  // namespace

EtcdClient::EtcdClient(std::vector<std::string> endpoints) : EtcdClient(std::move(endpoints), Options{}) {}

EtcdClient::EtcdClient(std::vector<std::string> endpoints, Options options)
    : endpoints_(std::move(endpoints)), options_(options) {
  if (endpoints_.empty()) throw std::invalid_argument("etcd: no endpoint");
  for (const auto& e : endpoints_) parseUrl(e);  // throws on a bad one, naming it
  if (options_.attempt_timeout.count() <= 0) throw std::invalid_argument("etcd: attempt_timeout must be positive");
}

std::vector<std::string> EtcdClient::parseEndpoints(const std::string& comma_separated) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(comma_separated);
  while (std::getline(in, item, ',')) {
    auto b = item.find_first_not_of(" \t");
    auto e = item.find_last_not_of(" \t");
    if (b == std::string::npos) continue;
    out.push_back(item.substr(b, e - b + 1));
  }
  return out;
}

json EtcdClient::call(const std::string& path, const json& body) {
  const std::string text = body.dump();
  const std::size_t n = endpoints_.size();
  const std::size_t first = preferred_.load() % n;
  std::string failures;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = (first + k) % n;
    const std::string& endpoint = endpoints_[i];
    HttpAnswer answer;
    try {
      answer = httpPost(parseUrl(endpoint), path, text, options_.attempt_timeout);
    } catch (const HttpFailure& f) {
      if (!failures.empty()) failures += "; ";
      failures += endpoint + ": " + f.what();
      continue;
    }
    json j;
    try {
      j = firstMessage(answer.body);
    } catch (const std::exception& e) {
      if (answer.status != 200) {
        if (!failures.empty()) failures += "; ";
        failures += endpoint + ": HTTP " + std::to_string(answer.status);
        if (answer.status >= 500) continue;
        throw EtcdError(endpoint, path + ": HTTP " + std::to_string(answer.status), false);
      }
      throw EtcdError(endpoint, path + ": answer is not JSON: " + e.what(), false);
    }
    if (auto r = refusal(answer.status, j)) {
      if (r->retry_elsewhere) {
        if (!failures.empty()) failures += "; ";
        failures += endpoint + ": " + r->reason;
        continue;
      }
      preferred_.store(i);  // it answered: it is up
      throw EtcdError(endpoint, path + ": " + r->reason, false, r->code);
    }
    preferred_.store(i);
    if (j.is_object() && j.contains("result") && j.size() == 1) return j["result"];
    return j;
  }
  throw EtcdError(n == 1 ? endpoints_[0] : "(" + std::to_string(n) + " endpoints)",
                  path + ": no endpoint answered: " + failures, true);
}

LeaseGrant EtcdClient::leaseGrant(std::int64_t ttl_s) {
  json j = call("/v3/lease/grant", {{"TTL", std::to_string(ttl_s)}, {"ID", "0"}});
  if (auto it = j.find("error"); it != j.end() && it->is_string() && !it->get<std::string>().empty())
    throw EtcdError(endpoints_[preferred_.load() % endpoints_.size()], "lease grant: " + it->get<std::string>(), false);
  LeaseGrant g{i64(j, "ID"), i64(j, "TTL")};
  if (g.id == 0) throw EtcdError(endpoints_[preferred_.load() % endpoints_.size()], "lease grant: no ID in the answer", false);
  return g;
}

std::int64_t EtcdClient::leaseKeepAliveOnce(std::int64_t id) {
  json j = call("/v3/lease/keepalive", {{"ID", std::to_string(id)}});
  return std::max<std::int64_t>(0, i64(j, "TTL"));
}

void EtcdClient::leaseRevoke(std::int64_t id) {
  try {
    call("/v3/lease/revoke", {{"ID", std::to_string(id)}});
  } catch (const EtcdError& e) {
    if (e.grpcCode() != kNotFound) throw;
  }
}

LeaseInfo EtcdClient::leaseTimeToLive(std::int64_t id, bool with_keys) {
  json body{{"ID", std::to_string(id)}};
  if (with_keys) body["keys"] = true;
  json j = call("/v3/lease/timetolive", body);
  LeaseInfo info;
  info.id = id;
  info.ttl_s = j.contains("TTL") ? i64(j, "TTL") : 0;  // proto3: 0 is left out
  info.granted_ttl_s = i64(j, "grantedTTL");
  if (info.ttl_s < 0) info.ttl_s = -1;
  if (auto it = j.find("keys"); it != j.end())
    for (const auto& k : *it) info.keys.push_back(base64Decode(k.get<std::string>()));
  return info;
}

std::int64_t EtcdClient::put(const std::string& key, const std::string& value, std::int64_t lease) {
  return headerRevision(call("/v3/kv/put", putBody(key, value, lease)));
}

std::optional<Kv> EtcdClient::get(const std::string& key, bool serializable) {
  json body = rangeBody(key, false);
  if (serializable) body["serializable"] = true;
  auto kvs = parseKvs(call("/v3/kv/range", body));
  if (kvs.empty()) return std::nullopt;
  return kvs.front();
}

std::vector<Kv> EtcdClient::range(const std::string& prefix, bool serializable) {
  json body = rangeBody(prefix, true);
  if (serializable) body["serializable"] = true;
  return parseKvs(call("/v3/kv/range", body));
}

std::int64_t EtcdClient::del(const std::string& key) {
  return i64(call("/v3/kv/deleterange", rangeBody(key, false)), "deleted");
}

std::int64_t EtcdClient::delPrefix(const std::string& prefix) {
  return i64(call("/v3/kv/deleterange", rangeBody(prefix, true)), "deleted");
}

TxnResult EtcdClient::txn(const std::vector<Compare>& compare, const std::vector<Op>& success,
                          const std::vector<Op>& failure) {
  json body{{"compare", json::array()}, {"success", json::array()}, {"failure", json::array()}};
  for (const auto& c : compare) body["compare"].push_back(compareJson(c));
  for (const auto& op : success) body["success"].push_back(opJson(op));
  for (const auto& op : failure) body["failure"].push_back(opJson(op));
  json j = call("/v3/kv/txn", body);
  TxnResult r;
  r.succeeded = j.value("succeeded", false);
  r.revision = headerRevision(j);
  if (auto it = j.find("responses"); it != j.end()) {
    for (const auto& resp : *it) {
      if (auto rr = resp.find("response_range"); rr != resp.end()) r.reads.push_back(parseKvs(*rr));
    }
  }
  return r;
}

bool EtcdClient::createIfAbsent(const std::string& key, const std::string& value, std::int64_t lease) {
  auto r = txn({Compare::version(key, Compare::Result::Equal, 0)}, {Op::put(key, value, lease)}, {Op::get(key)});
  if (r.succeeded) return true;
  // A lost answer to our own create, retried on another endpoint, finds our
  // key: a lease is one holder's, so the same lease and value are ours.
  if (lease != 0 && !r.reads.empty() && !r.reads[0].empty()) {
    const Kv& kv = r.reads[0][0];
    return kv.lease == lease && kv.value == value && kv.version == 1;
  }
  return false;
}

std::string EtcdClient::createOrRead(const std::string& key, const std::string& value, std::int64_t lease) {
  // a lost answer to our own create, retried, reads what it wrote; a
  // transaction's compare and read see one revision, so the read is there
  // when the compare failed
  auto r = txn({Compare::version(key, Compare::Result::Equal, 0)}, {Op::put(key, value, lease)}, {Op::get(key)});
  if (r.succeeded) return value;
  if (r.reads.empty() || r.reads[0].empty()) throw EtcdError("", "txn on " + key + ": the compare failed but the key is absent", false);
  return r.reads[0][0].value;
}

bool EtcdClient::compareAndSwap(const std::string& key, std::int64_t expected_mod_revision, const std::string& value,
                                std::int64_t lease) {
  return txn({Compare::modRevision(key, Compare::Result::Equal, expected_mod_revision)}, {Op::put(key, value, lease)})
      .succeeded;
}

bool EtcdClient::deleteIf(const std::string& key, std::int64_t mod_revision) {
  return txn({Compare::modRevision(key, Compare::Result::Equal, mod_revision)}, {Op::del(key)}).succeeded;
}

std::int64_t EtcdClient::revision() {
  json body = rangeBody(std::string(1, '\0'), false);
  body["count_only"] = true;
  return headerRevision(call("/v3/kv/range", body));
}

std::string EtcdClient::base64Encode(const std::string& in) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8 | (unsigned char)in[i + 2];
    out += table[v >> 18 & 63];
    out += table[v >> 12 & 63];
    out += table[v >> 6 & 63];
    out += table[v & 63];
  }
  if (i + 1 == in.size()) {
    unsigned v = (unsigned char)in[i] << 16;
    out += table[v >> 18 & 63];
    out += table[v >> 12 & 63];
    out += "==";
  } else if (i + 2 == in.size()) {
    unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8;
    out += table[v >> 18 & 63];
    out += table[v >> 12 & 63];
    out += table[v >> 6 & 63];
    out += '=';
  }
  return out;
}

std::string EtcdClient::base64Decode(const std::string& text) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+' || c == '-') return 62;
    if (c == '/' || c == '_') return 63;
    return -1;
  };
  std::string out;
  unsigned acc = 0;
  int bits = 0;
  std::size_t pad = 0;
  for (char c : text) {
    if (c == '=') {
      ++pad;
      continue;
    }
    int v = value(c);
    if (v < 0 || pad > 0) throw std::invalid_argument("base64: bad character in " + text.substr(0, 40));
    acc = (acc << 6) | static_cast<unsigned>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((acc >> bits) & 0xff);
    }
  }
  if (pad > 2 || bits >= 6) throw std::invalid_argument("base64: bad length in " + text.substr(0, 40));
  return out;
}

std::string EtcdClient::prefixEnd(const std::string& prefix) {
  std::string end = prefix;
  while (!end.empty()) {
    unsigned char last = static_cast<unsigned char>(end.back());
    if (last < 0xff) {
      end.back() = static_cast<char>(last + 1);
      return end;
    }
    end.pop_back();
  }
  return std::string(1, '\0');  // etcd: range_end "\0" = every key from key on
}

}  // namespace groundsim::fleet
