// experiments::BatchEnv over LCM: the environments run in a vectorised
// session of groundsim-server (docs/protocol.md, "Vectorised sessions").
// One step is one vec_request_t and one reply, split by the server into
// parts of one datagram each and put back together here; a part that does
// not come is an error naming it, never a silently short result. Every wait
// also watches the server's heartbeat. The same seed and actions give
// bit-identical observations to makeVecEnv in process.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include <groundsim/reply_t.hpp>
#include <groundsim/vec_reply_t.hpp>
#include <groundsim/vec_request_t.hpp>

#include "experiments/batch_env.hpp"
#include "protocol/assets_client.hpp"
#include "protocol/server_watch.hpp"
#include "protocol/vec_parts.hpp"

namespace groundsim::experiments {

// The transport failed: no server, no reply, parts missing. (A refusal
// naming a field is an ExperimentError, as in process.)
class RemoteError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct RemoteVecOptions {
  std::string lcm_url;           // "": LCM_DEFAULT_URL or LCM's default (ttl=0)
  double create_timeout_s = 60;  // building N environments takes a while
  double timeout_s = 30;         // any other request, until its first part
  double part_gap_s = 1.0;       // after a part, the next one must come within this
  // Where the files the scenario names (heightfields, friction maps) are
  // read, as makeVecEnvFromFile reads them (the scenario file's folder);
  // they are sent with the create (docs/protocol.md, Assets). "": none are
  // sent (the server may still have them under its --terrain-dir).
  std::string files_dir;
  bool send_files = false;  // files_dir is set (it may be "" for the working directory)
};

class RemoteVecEnv final : public BatchEnv {
 public:
  // Creates the vectorised session. Throws ExperimentError (e.g. num_envs
  // above the server's --max-envs, an invalid scenario as field
  // "scenario_json") or RemoteError.
  RemoteVecEnv(const std::string& scenario_text, int num_envs, RemoteVecOptions options = {});
  ~RemoteVecEnv() override;
  RemoteVecEnv(const RemoteVecEnv&) = delete;
  RemoteVecEnv& operator=(const RemoteVecEnv&) = delete;

  const Layout& layout() const override { return layout_; }
  void reset(std::optional<std::uint64_t> seed, float* obs) override;
  void resetEnv(int env, std::optional<std::uint64_t> seed, float* obs_row) override;
  void step(const float* actions, float* obs, double* rewards, std::uint8_t* terminated,
            std::uint8_t* truncated) override;
  EnvInfo info(int env) const override;
  std::string snapshot(int env) const override;
  void restore(int env, const std::string& snapshot, float* obs_row) override;
  void setRandomization(int env, const std::string& randomize_json) override;
  void drawn(double* out) const override;
  void render(int env, int width, int height, std::uint8_t* rgb) const override;
  // Stops the session (request_t OP_STOP); later calls throw. Idempotent.
  void close() override;

  const std::string& sessionId() const { return session_id_; }
  const std::string& serverId() const { return server_id_; }  // the owner (a fleet's: its heartbeat is watched)
  const std::string& url() const { return url_; }

 private:
  // A refusal throws, except one for missing assets when *missing_assets
  // is given: it is set and the reply returned.
  groundsim::vec_reply_t call(groundsim::vec_request_t req, double timeout_s, const char* what,
                              bool* missing_assets = nullptr) const;
  groundsim::vec_reply_t create(const std::string& scenario_text, int num_envs);
  void onVecReply(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  void onReply(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  void onAssetWant(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  void onEvent(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  void takeEnvs(const groundsim::vec_reply_t& r, float* obs, double* rewards, std::uint8_t* terminated,
                std::uint8_t* truncated);
  void checkEnv(int env) const;
  void checkOpen(const char* what) const;
  void drain() const;

  RemoteVecOptions options_;
  std::string url_;
  mutable lcm::LCM lcm_;
  mutable net::ServerWatch watch_;  // after lcm_
  std::string client_id_;
  mutable std::int64_t next_id_ = 1;
  mutable net::VecAssembler assembler_{0};
  mutable std::string part_error_;   // an inconsistent part of the reply waited for
  mutable net::AssetWants wants_;
  mutable std::string asset_error_;  // a file part the server refused (event on GROUNDSIM_ASSET)
  mutable std::optional<groundsim::reply_t> stop_reply_;
  mutable std::int64_t stop_waiting_ = -1;
  std::string session_id_, token_;
  std::string server_id_;  // the session's owner, from the create reply ("" from an older server)
  Layout layout_;
  std::vector<EnvInfo> infos_;
  bool closed_ = false;
};

}  // namespace groundsim::experiments
