// groundsim._core: the factories of BatchEnvs and the handle class
// (batch_env_binding.cpp). The package's Python side (groundsim/) wraps a
// handle in Gymnasium's vector API.
#include <algorithm>
#include <memory>
#include <optional>
#include <string>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "batch_env_binding.hpp"
#include "client/experiments/remote_vec_env.hpp"
#include "client/experiments/sharded_vec_env.hpp"
#include "experiments/vec_env.hpp"
#include "gate_env.hpp"
#include "scenario/file_access.hpp"

namespace py = pybind11;
using namespace groundsim;

namespace {

experiments::VecEnvOptions options(int num_threads) {
  experiments::VecEnvOptions o;
  o.num_threads = num_threads;
  return o;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "groundsim's C++ experiments API (use groundsim.make_vec)";
  python::registerErrorTranslators();
  python::bindBatchEnv(m);

  // Scenario text (a document with a task). Files it names are read
  // relative to files_dir, none without it.
  m.def(
      "make_vec_env",
      [](const std::string& text, int num_envs, int num_threads, std::optional<std::string> files_dir) {
        auto o = options(num_threads);
        if (files_dir) o.files = scenario::FileAccess::local(*files_dir);
        std::unique_ptr<experiments::BatchEnv> env;
        {
          py::gil_scoped_release release;  // building can read and parse heightfields
          env = experiments::makeVecEnv(text, num_envs, o);
        }
        return std::make_unique<python::EnvHandle>(std::move(env));
      },
      py::arg("text"), py::arg("num_envs"), py::arg("num_threads") = 0, py::arg("files_dir") = py::none());

  // A scenario file; the files it names are read next to it.
  m.def(
      "make_vec_env_from_file",
      [](const std::string& path, int num_envs, int num_threads) {
        std::unique_ptr<experiments::BatchEnv> env;
        {
          py::gil_scoped_release release;
          env = experiments::makeVecEnvFromFile(path, num_envs, options(num_threads));
        }
        return std::make_unique<python::EnvHandle>(std::move(env));
      },
      py::arg("path"), py::arg("num_envs"), py::arg("num_threads") = 0);

  // A vectorised session of groundsim-server over LCM (RemoteVecEnv); the
  // files the scenario names are read relative to files_dir and sent with
  // the create (none without it; the server may have them under its
  // --terrain-dir).
  m.def(
      "make_remote_vec_env",
      [](const std::string& text, int num_envs, const std::string& lcm_url, double timeout,
         std::optional<std::string> files_dir, int shards) {
        experiments::RemoteVecOptions o;
        o.lcm_url = lcm_url;
        if (files_dir) {
          o.files_dir = *files_dir;
          o.send_files = true;
        }
        o.timeout_s = timeout;
        o.create_timeout_s = std::max(timeout, o.create_timeout_s);
        std::unique_ptr<experiments::BatchEnv> env;
        {
          py::gil_scoped_release release;  // waits on the network
          if (shards > 1) env = std::make_unique<experiments::ShardedVecEnv>(text, num_envs, shards, o);
          else env = std::make_unique<experiments::RemoteVecEnv>(text, num_envs, o);
        }
        return std::make_unique<python::EnvHandle>(std::move(env));
      },
      py::arg("text"), py::arg("num_envs"), py::arg("lcm_url") = "", py::arg("timeout") = 30.0,
      py::arg("files_dir") = py::none(), py::arg("shards") = 1);

  // For tests of the binding (tests/python/test_gil.py): an env whose step
  // waits until the returned gate is opened from another thread.
  py::class_<python::Gate, std::shared_ptr<python::Gate>>(m, "_Gate").def("open", &python::Gate::open).def("waiting", &python::Gate::waiting);
  m.def("_make_gate_env", [](int num_envs) {
    auto gate = std::make_shared<python::Gate>();
    auto handle = std::make_unique<python::EnvHandle>(python::makeGateEnv(num_envs, gate));
    return py::make_tuple(std::move(handle), gate);
  });
}
