// The owners/ values of the fleet's etcd keys (fleet_node.cpp,
// fleet_placement.cpp): which server owns a session, at which epoch, and
// for a session made by a create, which create.
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

namespace groundsim::net::fleet_owners {

// An owners/ value: the server and epoch, and for a session made by a
// create (epoch 1) that create's placement ("<client>/<request>").
inline std::string ownerValue(const std::string& server, std::int64_t epoch, const std::string& placement = "") {
  nlohmann::json j{{"server", server}, {"epoch", epoch}};
  if (!placement.empty()) j["create"] = placement;
  return j.dump();
}

struct Owner {
  std::string server, placement;
  std::int64_t epoch = 0;  // 0: none given
};

inline Owner ownerOf(const std::string& value) {
  const nlohmann::json j = nlohmann::json::parse(value, nullptr, false);
  if (!j.is_object()) return {};
  const auto text = [&](const char* field) {
    const auto it = j.find(field);
    return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
  };
  const auto e = j.find("epoch");
  return Owner{text("server"), text("create"), e != j.end() && e->is_number_integer() ? e->get<std::int64_t>() : 0};
}

}  // namespace groundsim::net::fleet_owners
