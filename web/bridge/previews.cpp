#include "bridge/previews.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <boost/asio/post.hpp>
#include <nlohmann/json.hpp>

#include "bridge/shipped_scenarios.hpp"

namespace groundsim::web {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

Previews::Previews(boost::asio::io_context& io, Worker& worker, const Browsers& browsers, std::string configs_dir)
    : io_(io), worker_(worker), browsers_(browsers), dir_(std::move(configs_dir)) {}

void Previews::ask(Peer* p, const std::string& config) {
  if (auto it = done_.find(config); it != done_.end()) return p->send(it->second);
  auto& waiting = waiting_[config];
  if (std::find(waiting.begin(), waiting.end(), p) == waiting.end()) waiting.push_back(p);
  if (waiting.size() > 1) return;  // queued or under way
  queue_.push_back(config);
  next();
}

void Previews::next() {
  if (busy_ || queue_.empty()) return;
  busy_ = true;
  const std::string id = queue_.front(), dir = dir_;
  queue_.pop_front();
  worker_.post([this, id, dir] {
    const auto t0 = Clock::now();
    json out;
    try {
      out = scenarioPreview(dir, id);
    } catch (const std::exception& e) {
      out = {{"error", e.what()}};
    }
    out["op"] = "preview";
    out["config"] = id;
    out["ms"] = std::round(std::chrono::duration<double, std::milli>(Clock::now() - t0).count() * 10.0) / 10.0;
    auto text = std::make_shared<const std::string>(out.dump());
    boost::asio::post(io_, [this, id, text] {
      done_[id] = text;
      auto waiting = std::move(waiting_[id]);
      waiting_.erase(id);
      for (Peer* q : waiting)
        if (browsers_.attached(q)) q->send(text);
      busy_ = false;
      next();
    });
  });
}

}  // namespace groundsim::web
