// The handle's methods. Every buffer is the caller's numpy array, written in
// place: its dtype, shape, C order, alignment and (for outputs) writability
// are checked here, before the GIL is released, and a mismatch is an
// ExperimentError (a ValueError in Python) naming the argument and what was
// expected. Nothing is converted, so nothing is copied.
#include "batch_env_binding.hpp"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

namespace py = pybind11;
using groundsim::experiments::BatchEnv;
using groundsim::experiments::EnvInfo;
using groundsim::experiments::ExperimentError;
using groundsim::experiments::Layout;

namespace groundsim::python {

EnvHandle::EnvHandle(std::unique_ptr<BatchEnv> env) : env_(std::move(env)), layout_(env_->layout()) {}

EnvHandle::~EnvHandle() {
  // the environment's worker threads are joined without the GIL, so that a
  // worker never waits on Python while the interpreter waits on it
  py::gil_scoped_release release;
  std::lock_guard lock(mutex_);
  env_.reset();
}

BatchEnv& EnvHandle::env() {
  if (!env_) throw ExperimentError("env", "the environment is closed");
  return *env_;
}

void EnvHandle::close() {
  if (env_) env_->close();
  env_.reset();
}

namespace {

std::string shapeText(const std::vector<py::ssize_t>& shape) {
  std::ostringstream s;
  s << '(';
  for (std::size_t i = 0; i < shape.size(); ++i) s << (i ? ", " : "") << shape[i];
  s << (shape.size() == 1 ? ",)" : ")");
  return s.str();
}

template <class T>
const char* dtypeName() {
  if constexpr (std::is_same_v<T, float>) return "float32";
  else if constexpr (std::is_same_v<T, double>) return "float64";
  else if constexpr (std::is_same_v<T, bool>) return "bool";
  else if constexpr (std::is_same_v<T, std::uint8_t>) return "uint8";
  else return "int64";
}

// The data of `obj` if it is a C-contiguous, aligned numpy array of T with
// exactly `shape`; writable too when `output`.
template <class T>
T* buffer(const py::handle& obj, const char* name, const std::vector<py::ssize_t>& shape, bool output) {
  // the common case first, without building the message (a step checks nine arrays)
  if (py::isinstance<py::array_t<T>>(obj)) {
    auto arr = py::reinterpret_borrow<py::array>(obj);
    const bool fits = arr.ndim() == static_cast<py::ssize_t>(shape.size()) &&
                      std::equal(shape.begin(), shape.end(), arr.shape()) && (arr.flags() & py::array::c_style) &&
                      reinterpret_cast<std::uintptr_t>(arr.data()) % alignof(T) == 0 && (!output || arr.writeable());
    if (fits) return static_cast<T*>(const_cast<void*>(arr.data()));
  }
  const std::string expected = std::string("a C-contiguous") + (output ? " writable" : "") +
                               " numpy array of " + dtypeName<T>() + " with shape " + shapeText(shape);
  if (!py::isinstance<py::array>(obj))
    throw ExperimentError(name, "expected " + expected + ", got " + std::string(py::str(obj.get_type().attr("__name__"))));
  auto arr = py::reinterpret_borrow<py::array>(obj);
  std::vector<py::ssize_t> got(arr.shape(), arr.shape() + arr.ndim());
  if (!py::isinstance<py::array_t<T>>(arr))
    throw ExperimentError(name, "expected " + expected + ", got dtype " + std::string(py::str(arr.dtype())));
  if (got != shape) throw ExperimentError(name, "expected " + expected + ", got shape " + shapeText(got));
  if (!(arr.flags() & py::array::c_style))
    throw ExperimentError(name, "expected " + expected + ", got a non-contiguous array");
  if (reinterpret_cast<std::uintptr_t>(arr.data()) % alignof(T) != 0)
    throw ExperimentError(name, "expected " + expected + ", got an unaligned array");
  if (output && !arr.writeable()) throw ExperimentError(name, "expected " + expected + ", got a read-only array");
  return static_cast<T*>(const_cast<void*>(arr.data()));
}

// None, or an int in [0, 2^63) (numpy integers too).
std::optional<std::uint64_t> seedOf(const py::handle& seed) {
  if (seed.is_none()) return std::nullopt;
  py::object index = py::reinterpret_steal<py::object>(PyNumber_Index(seed.ptr()));
  if (!index) {
    PyErr_Clear();
    throw ExperimentError("seed", "must be an integer in [0, 2^63) or None, got " +
                                      std::string(py::str(seed.get_type().attr("__name__"))));
  }
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
  if (overflow != 0 || v < 0)
    throw ExperimentError("seed", "must be in [0, 2^63), got " + std::string(py::str(index)));
  return static_cast<std::uint64_t>(v);
}

int envIndex(const EnvHandle& h, int env) {
  if (env < 0 || env >= h.layout().num_envs)
    throw ExperimentError("env", "must be in [0, " + std::to_string(h.layout().num_envs) + "), got " +
                                     std::to_string(env));
  return env;
}

// one row per agent of each environment (Layout::rows)
std::vector<py::ssize_t> obsShape(const Layout& l) { return {l.rows(), l.obsSize()}; }

// Layout: what the buffers of a BatchEnv hold.
void bindLayout(py::module_& m) {
  py::class_<Layout>(m, "Layout", "What the buffers of a BatchEnv hold (experiments/batch_env.hpp)")
      .def_readonly("num_envs", &Layout::num_envs)
      .def_readonly("num_agents", &Layout::num_agents, "agents per environment: buffers have num_envs x num_agents rows")
      .def_readonly("agents", &Layout::agents, "the agents' vehicle names, the row order within an environment")
      .def_property_readonly("rows", &Layout::rows)
      .def_readonly("dt", &Layout::dt, "physics step, s")
      .def_readonly("control_period", &Layout::control_period, "physics steps per action")
      .def_readonly("time_limit", &Layout::time_limit, "episode length before truncation, s; 0 = none")
      .def_readonly("observation", &Layout::observation, "one name per observation component")
      .def_readonly("observation_low", &Layout::observation_low)
      .def_readonly("observation_high", &Layout::observation_high)
      .def_readonly("action", &Layout::action, "one name per action component")
      .def_readonly("action_low", &Layout::action_low)
      .def_readonly("action_high", &Layout::action_high)
      .def_readonly("wheel_counts", &Layout::wheel_counts, "wheels per vehicle, in document order")
      .def_readonly("scenario_hash", &Layout::scenario_hash)
      .def_readonly("drawn", &Layout::drawn, "what each reset draws: x, y, yaw (rad), speed, then parameter paths")
      .def_property_readonly("obs_size", &Layout::obsSize)
      .def_property_readonly("action_size", &Layout::actionSize)
      .def("__repr__", [](const Layout& l) {
        return "Layout(num_envs=" + std::to_string(l.num_envs) + ", obs_size=" + std::to_string(l.obsSize()) +
               ", action_size=" + std::to_string(l.actionSize()) + ", dt=" + std::to_string(l.dt) +
               ", control_period=" + std::to_string(l.control_period) + ")";
      });
}

// reset, reset_env, step, fill_infos: an episode's calls, each writing the caller's arrays
void bindEpisodes(py::class_<EnvHandle>& env) {
  env
      .def(
          "reset",
          [](EnvHandle& h, const py::handle& seed, const py::handle& obs) {
            const auto s = seedOf(seed);
            float* o = buffer<float>(obs, "obs", obsShape(h.layout()), true);
            py::gil_scoped_release release;
            std::lock_guard lock(h.mutex());
            h.env().reset(s, o);
          },
          py::arg("seed"), py::arg("obs"), "resets every env (env i seeded with seed + i); writes obs")
      .def(
          "reset_env",
          [](EnvHandle& h, int env, const py::handle& seed, const py::handle& obs) {
            const int i = envIndex(h, env);
            const auto s = seedOf(seed);
            float* o = buffer<float>(obs, "obs", obsShape(h.layout()), true);
            py::gil_scoped_release release;
            std::lock_guard lock(h.mutex());
            h.env().resetEnv(i, s, o + static_cast<std::ptrdiff_t>(i) * h.layout().num_agents * h.layout().obsSize());
          },
          py::arg("env"), py::arg("seed"), py::arg("obs"), "resets env with exactly seed; writes its row of obs")
      .def(
          "step",
          [](EnvHandle& h, const py::handle& actions, const py::handle& obs, const py::handle& rewards,
             const py::handle& terminations, const py::handle& truncations) {
            const Layout& l = h.layout();
            const py::ssize_t n = l.rows();
            const float* a = buffer<float>(actions, "actions", {n, l.actionSize()}, false);
            float* o = buffer<float>(obs, "obs", obsShape(l), true);
            double* r = buffer<double>(rewards, "rewards", {n}, true);
            // numpy's bool is one byte holding 0 or 1: the uint8 flags of the interface
            auto* term = reinterpret_cast<std::uint8_t*>(buffer<bool>(terminations, "terminations", {n}, true));
            auto* trunc = reinterpret_cast<std::uint8_t*>(buffer<bool>(truncations, "truncations", {n}, true));
            py::gil_scoped_release release;
            std::lock_guard lock(h.mutex());
            h.env().step(a, o, r, term, trunc);
          },
          py::arg("actions"), py::arg("obs"), py::arg("rewards"), py::arg("terminations"), py::arg("truncations"))
      .def(
          "fill_infos",
          [](EnvHandle& h, const py::handle& episode, const py::handle& episode_steps,
             const py::handle& episode_return, const py::handle& diverged, const py::handle& active) {
            const py::ssize_t n = h.layout().rows();
            auto* ep = buffer<std::int64_t>(episode, "episode", {n}, true);
            auto* steps = buffer<std::int64_t>(episode_steps, "episode_steps", {n}, true);
            auto* ret = buffer<double>(episode_return, "episode_return", {n}, true);
            auto* div = buffer<bool>(diverged, "diverged", {n}, true);
            auto* act = active.is_none() ? nullptr : buffer<bool>(active, "active", {n}, true);
            py::gil_scoped_release release;
            std::lock_guard lock(h.mutex());
            BatchEnv& env = h.env();
            for (py::ssize_t i = 0; i < n; ++i) {
              const EnvInfo info = env.info(static_cast<int>(i));
              ep[i] = info.episode;
              steps[i] = info.episode_steps;
              ret[i] = info.episode_return;
              div[i] = info.diverged;
              if (act) act[i] = info.active;
            }
          },
          py::arg("episode"), py::arg("episode_steps"), py::arg("episode_return"), py::arg("diverged"),
          py::arg("active") = py::none(), "writes every row's EnvInfo into the arrays (active: optional)");
}

// snapshot, restore, set_randomization, drawn: an environment's state and its draws
void bindSnapshots(py::class_<EnvHandle>& env) {
  env
      .def(
          "snapshot",
          [](EnvHandle& h, int env) {
            const int i = envIndex(h, env);
            std::string data;
            {
              py::gil_scoped_release release;
              std::lock_guard lock(h.mutex());
              data = h.env().snapshot(i);
            }
            return py::bytes(data);
          },
          py::arg("env"), "the full state of env, restorable bit for bit")
      .def(
          "restore",
          [](EnvHandle& h, int env, const py::bytes& snapshot, const py::handle& obs) {
            const int i = envIndex(h, env);
            std::string data = snapshot;  // bytes -> string before the GIL is released
            float* o = buffer<float>(obs, "obs", obsShape(h.layout()), true);
            py::gil_scoped_release release;
            std::lock_guard lock(h.mutex());
            h.env().restore(i, data, o + static_cast<std::ptrdiff_t>(i) * h.layout().num_agents * h.layout().obsSize());
          },
          py::arg("env"), py::arg("snapshot"), py::arg("obs"), "restores env; writes its row of obs")
      .def(
          "set_randomization",
          [](EnvHandle& h, int env, const std::string& randomize_json) {
            if (env != -1) envIndex(h, env);
            py::gil_scoped_release release;
            std::lock_guard lock(h.mutex());
            h.env().setRandomization(env, randomize_json);
          },
          py::arg("env"), py::arg("randomize_json"),
          "a curriculum: new ranges (the task's randomize object as JSON) for env, -1 for every env, "
          "from its next reset on")
      .def(
          "drawn",
          [](EnvHandle& h, const py::handle& out) {
            const Layout& l = h.layout();
            double* o = buffer<double>(out, "drawn", {l.num_envs, l.drawnSize()}, true);
            py::gil_scoped_release release;
            std::lock_guard lock(h.mutex());
            h.env().drawn(o);
          },
          py::arg("out"), "writes what each env's last reset drew, [num_envs x len(layout.drawn)]");
}

// render and close
void bindViews(py::class_<EnvHandle>& env) {
  env
      .def(
          "render",
          [](EnvHandle& h, int env, const py::handle& out) {
            const int i = envIndex(h, env);
            if (!py::isinstance<py::array>(out) || py::reinterpret_borrow<py::array>(out).ndim() != 3 ||
                py::reinterpret_borrow<py::array>(out).shape(2) != 3)
              throw ExperimentError("rgb", "expected a (height, width, 3) uint8 array");
            const py::array a = py::reinterpret_borrow<py::array>(out);
            const int height = static_cast<int>(a.shape(0)), width = static_cast<int>(a.shape(1));
            auto* rgb = buffer<std::uint8_t>(out, "rgb", {height, width, 3}, true);
            py::gil_scoped_release release;
            std::lock_guard lock(h.mutex());
            h.env().render(i, width, height, rgb);
          },
          py::arg("env"), py::arg("out"), "writes a frame of env (a (height, width, 3) uint8 array)")
      .def(
          "close",
          [](EnvHandle& h) {
            py::gil_scoped_release release;
            std::lock_guard lock(h.mutex());
            h.close();
          },
          "stops the environment's threads; later calls raise ExperimentError(field='env')");
}

}  // namespace

void bindBatchEnv(py::module_& m) {
  bindLayout(m);
  py::class_<EnvHandle> env(m, "BatchEnv",
                            "N environments stepped together; buffers are the caller's numpy arrays, written in place");
  env.def_property_readonly("layout", &EnvHandle::layout, py::return_value_policy::reference_internal)
      .def_property_readonly("closed", &EnvHandle::closed);
  bindEpisodes(env);
  bindSnapshots(env);
  bindViews(env);
}

}  // namespace groundsim::python
