# The Python module (python/, docs/python.md): pybind11 and NumPy from Debian,
# for Debian's own interpreter. The `python3` first on PATH may be another one
# (pyenv) without NumPy, so the interpreter is /usr/bin/python3 unless
# Python3_EXECUTABLE says otherwise. LAYERLAB_WITH_PYTHON: ON (fail when
# missing), OFF, or AUTO (built when pybind11, the headers and NumPy are found).
if(LAYERLAB_WITH_PYTHON STREQUAL "OFF")
  layerlab_leave_out(LAYERLAB_WITH_PYTHON "Python module" "LAYERLAB_WITH_PYTHON=OFF" "")
endif()
if(LAYERLAB_FUZZ OR LAYERLAB_SANITIZE)
  # A sanitized module would need the sanitizer runtime preloaded into python3.
  layerlab_leave_out(LAYERLAB_WITH_PYTHON "Python module" "not in sanitizer builds" "cannot be combined with LAYERLAB_FUZZ or LAYERLAB_SANITIZE")
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
  layerlab_leave_out(LAYERLAB_WITH_PYTHON "Python module" "no ${layerlab_python_missing}" "but ${layerlab_python_missing} was not found")
endif()
add_subdirectory(python)
