# The Python package (python/, groundsim._core built with pybind11). Sets
# GROUNDSIM_BUILD_PYTHON, ON by default when pybind11 and a Python with
# development headers are found, and Python_EXECUTABLE: the interpreter the
# module is built for and the tests run with.
#
# Debian's /usr/bin/python3 is preferred to whatever python3 comes first in
# PATH: numpy, pytest and matplotlib are Debian packages (scripts/setup.sh),
# and an interpreter of its own (pyenv, a venv without system packages) has
# none of them. -DPython_EXECUTABLE=... chooses another one.
if(NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "the Python the groundsim module is built for")
endif()
find_package(Python 3 COMPONENTS Interpreter Development.Module QUIET)
if(Python_FOUND)
  find_package(pybind11 CONFIG QUIET)
endif()

# A module built with sanitizers cannot be loaded by a Python that is not
# (the sanitizer runtime must come first), nor one built for libFuzzer.
set(groundsim_python_default OFF)
if(pybind11_FOUND AND NOT GROUNDSIM_SANITIZE AND NOT GROUNDSIM_FUZZ)
  set(groundsim_python_default ON)
endif()
option(GROUNDSIM_BUILD_PYTHON "Build the Python package groundsim (pybind11) into build/python"
       ${groundsim_python_default})

if(GROUNDSIM_BUILD_PYTHON)
  if(NOT pybind11_FOUND)
    message(FATAL_ERROR "GROUNDSIM_BUILD_PYTHON needs pybind11 and Python's headers "
                        "(scripts/setup.sh installs pybind11-dev, python3-pybind11, python3-dev)")
  endif()
  # The layer libraries are linked into a shared module: position-independent
  # code everywhere. -fno-semantic-interposition keeps GCC inlining and
  # calling functions directly as it does for the (PIE) executables.
  set(CMAKE_POSITION_INDEPENDENT_CODE ON)
  add_compile_options($<$<CXX_COMPILER_ID:GNU>:-fno-semantic-interposition>)
  message(STATUS "groundsim Python package: ${Python_EXECUTABLE} (${Python_VERSION}), pybind11 ${pybind11_VERSION}")
endif()
