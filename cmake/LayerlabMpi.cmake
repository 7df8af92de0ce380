# MPI for `layerlab sweep --mpi` (docs/sweeps.md): OpenMPI from Debian
# (libopenmpi-dev, openmpi-bin). LAYERLAB_WITH_MPI: ON (fail when missing),
# OFF, or AUTO (built when found). Sets LAYERLAB_MPI_FOUND and, for the tests,
# LAYERLAB_MPIEXEC (mpirun). Without it `--mpi` refuses, naming the option.
set(LAYERLAB_MPI_FOUND OFF)
if(LAYERLAB_WITH_MPI STREQUAL "OFF")
  list(APPEND LAYERLAB_LEFT_OUT "MPI (LAYERLAB_WITH_MPI=OFF)")
  return()
endif()
if(LAYERLAB_FUZZ OR LAYERLAB_SANITIZE)
  # OpenMPI's own allocations outlive MPI_Finalize: LeakSanitizer would fail every MPI run.
  if(LAYERLAB_WITH_MPI STREQUAL "ON")
    message(FATAL_ERROR "LAYERLAB_WITH_MPI=ON cannot be combined with LAYERLAB_FUZZ or LAYERLAB_SANITIZE")
  endif()
  list(APPEND LAYERLAB_LEFT_OUT "MPI (not in sanitizer builds)")
  return()
endif()
find_package(MPI COMPONENTS CXX)
if(MPI_CXX_FOUND AND MPIEXEC_EXECUTABLE)
  set(LAYERLAB_MPI_FOUND ON)
  set(LAYERLAB_MPIEXEC ${MPIEXEC_EXECUTABLE})
elseif(LAYERLAB_WITH_MPI STREQUAL "ON")
  message(FATAL_ERROR "LAYERLAB_WITH_MPI=ON but MPI was not found (apt-get install libopenmpi-dev openmpi-bin)")
else()
  list(APPEND LAYERLAB_LEFT_OUT "MPI (libopenmpi-dev, openmpi-bin not found)")
endif()
