# MPI for `layerlab sweep --mpi` (docs/sweeps.md) and `mpirun -np N layerlab solve` (docs/mpi.md): OpenMPI from Debian
# (libopenmpi-dev, openmpi-bin). LAYERLAB_WITH_MPI: ON (fail when missing),
# OFF, or AUTO (built when found). Sets LAYERLAB_MPI_FOUND and, for the tests,
# LAYERLAB_MPIEXEC (mpirun). Without it `--mpi` refuses, naming the option.
set(LAYERLAB_MPI_FOUND OFF)
if(LAYERLAB_WITH_MPI STREQUAL "OFF")
  layerlab_leave_out(LAYERLAB_WITH_MPI MPI "LAYERLAB_WITH_MPI=OFF" "")
endif()
if(LAYERLAB_FUZZ OR LAYERLAB_SANITIZE)
  # OpenMPI's own allocations outlive MPI_Finalize: LeakSanitizer would fail every MPI run.
  layerlab_leave_out(LAYERLAB_WITH_MPI MPI "not in sanitizer builds" "cannot be combined with LAYERLAB_FUZZ or LAYERLAB_SANITIZE")
endif()
find_package(MPI COMPONENTS CXX)
if(MPI_CXX_FOUND AND MPIEXEC_EXECUTABLE)
  set(LAYERLAB_MPI_FOUND ON)
  set(LAYERLAB_MPIEXEC ${MPIEXEC_EXECUTABLE})
else()
  layerlab_leave_out(LAYERLAB_WITH_MPI MPI "libopenmpi-dev, openmpi-bin not found"
                     "but MPI was not found (apt-get install libopenmpi-dev openmpi-bin)")
endif()
