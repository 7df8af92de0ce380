# The Python module (python/, docs/python.md): pybind11 and NumPy from Debian,
# for Debian's own interpreter. The `python3` first on PATH may be another one
# (pyenv) without NumPy, so the interpreter is /usr/bin/python3 unless
# Python3_EXECUTABLE says otherwise. LAYERLAB_WITH_PYTHON: ON (fail when
# missing), OFF, or AUTO (built when pybind11, the headers and NumPy are found).
# Leaves the module out (returning from this file) for `reason`, listed at
# the end of the configuration, or stops it with "LAYERLAB_WITH_PYTHON=ON
# <error>" when the module was asked for.
macro(layerlab_leave_python_out reason error)
  if(LAYERLAB_WITH_PYTHON STREQUAL "ON")
    message(FATAL_ERROR "LAYERLAB_WITH_PYTHON=ON ${error}")
  endif()
  list(APPEND LAYERLAB_LEFT_OUT "Python module (${reason})")
  return()
endmacro()

if(LAYERLAB_WITH_PYTHON STREQUAL "OFF")
  list(APPEND LAYERLAB_LEFT_OUT "Python module (LAYERLAB_WITH_PYTHON=OFF)")
  return()
endif()
if(LAYERLAB_FUZZ OR LAYERLAB_SANITIZE)
  # A sanitized module would need the sanitizer runtime preloaded into python3.
  layerlab_leave_python_out("not in sanitizer builds" "cannot be combined with LAYERLAB_FUZZ or LAYERLAB_SANITIZE")
endif()
if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "The interpreter the Python module is built for")
endif()
find_package(Python3 COMPONENTS Interpreter Development.Module)
set(layerlab_python_missing "")
if(NOT Python3_FOUND)
  set(layerlab_python_missing "Python 3 headers (python3-dev)")
else()
  set(PYBIND11_FINDPYTHON ON)
  find_package(pybind11 2.6 CONFIG QUIET)
  execute_process(COMMAND ${Python3_EXECUTABLE} -c "import numpy" RESULT_VARIABLE numpy_missing OUTPUT_QUIET
                  ERROR_QUIET)
  if(NOT pybind11_FOUND)
    set(layerlab_python_missing "pybind11 (pybind11-dev)")
  elseif(numpy_missing)
    set(layerlab_python_missing "NumPy for ${Python3_EXECUTABLE} (python3-numpy)")
  endif()
endif()
if(layerlab_python_missing)
  layerlab_leave_python_out("no ${layerlab_python_missing}" "but ${layerlab_python_missing} was not found")
endif()
add_subdirectory(python)
