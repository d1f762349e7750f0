// An obstacle of the scenario's `objects` as validated (objects_section.cpp).
#pragma once

#include <cstddef>
#include <string>

#include "physics/build/collision_build.hpp"

namespace groundsim::scenario {

inline constexpr std::size_t kMaxObjects = 1000;
inline constexpr double kMaxObjectSize = 1e4;  // m, any dimension

struct ObjectEntry {
  ObjectSpec spec;
  // true: x and y place it, and its lowest point rests on the ground below
  // (z is ignored); false: position is its centre
  bool on_ground = true;
  std::string path;               // JSON pointer of the object, for errors
};

}  // namespace groundsim::scenario
