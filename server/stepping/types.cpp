#include "stepping/types.hpp"

namespace groundsim::stepping {

const char* modeName(Mode m) {
  switch (m) {
    case Mode::Realtime: return "realtime";
    case Mode::Fast: return "fast";
    case Mode::Lockstep: return "lockstep";
    case Mode::Vectorised: return "vectorised";
  }
  return "?";
}

const char* statusName(Status s) {
  switch (s) {
    case Status::Running: return "running";
    case Status::Paused: return "paused";
    case Status::Finished: return "finished";
    case Status::Diverged: return "diverged";
    case Status::Stopped: return "stopped";
  }
  return "?";
}

const char* vecOpName(VecOp op) {
  switch (op) {
    case VecOp::Create: return "create";
    case VecOp::Step: return "step";
    case VecOp::Reset: return "reset";
    case VecOp::ResetEnv: return "reset_env";
    case VecOp::Snapshot: return "snapshot";
    case VecOp::Restore: return "restore";
    case VecOp::Randomize: return "randomize";
    case VecOp::Drawn: return "drawn";
  }
  return "?";
}

std::optional<Mode> modeFromInt(int m) {
  if (m == static_cast<int>(Mode::Realtime)) return Mode::Realtime;
  if (m == static_cast<int>(Mode::Fast)) return Mode::Fast;
  if (m == static_cast<int>(Mode::Lockstep)) return Mode::Lockstep;
  return std::nullopt;
}

}  // namespace groundsim::stepping
