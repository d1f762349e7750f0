// C++ errors -> the Python exception classes of groundsim/_errors.py, which
// carry what a program needs besides the message: the field of an
// ExperimentError, the JSON-pointer issues of a ScenarioError.
#include <exception>

#include <pybind11/pybind11.h>

#include "batch_env_binding.hpp"
#include "client/experiments/remote_vec_env.hpp"
#include "experiments/batch_env.hpp"
#include "scenario/scenario.hpp"

namespace py = pybind11;

namespace groundsim::python {

namespace {

// Raises an instance of groundsim._errors.<name> built from args. Runs with
// the GIL held (translators are called after the call's GIL release ended).
void raise(const char* name, const py::tuple& args) {
  py::object cls = py::module_::import("groundsim._errors").attr(name);
  py::object exc = cls(*args);
  PyErr_SetObject(cls.ptr(), exc.ptr());
}

}  // namespace

void registerErrorTranslators() {
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const experiments::ExperimentError& e) {
      raise("ExperimentError", py::make_tuple(e.field(), e.what()));
    } catch (const scenario::ScenarioError& e) {
      py::list issues;
      for (const auto& issue : e.issues()) issues.append(py::make_tuple(issue.path, issue.message));
      raise("ScenarioError", py::make_tuple(e.what(), issues, e.omitted()));
    } catch (const experiments::RemoteError& e) {
      raise("RemoteError", py::make_tuple(e.what()));
    }
  });
}

}  // namespace groundsim::python
