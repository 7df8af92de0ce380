#!/usr/bin/env bash
# Installs layerlab's dependencies (Debian 12 packages) and builds it in ./build.
# Usage: scripts/setup.sh [extra cmake -D options]
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(cmake ninja-build g++ pkg-config
          libembree-dev libeigen3-dev nlohmann-json3-dev libopenexr-dev libceres-dev
          libcli11-dev libtbb-dev libgtest-dev libgmock-dev libbenchmark-dev libpng-dev
          chromium fonts-liberation)  # headless Chromium for the report's end-to-end test

# Calibration from photographs, layerlab detect (docs/calibration.md)
packages+=(libopencv-calib3d-dev libopencv-imgproc-dev libopencv-imgcodecs-dev)
packages+=(clang-14 libclang-rt-14-dev libomp-14-dev)  # the sanitizer and fuzz build in .ci/run (docs/robustness.md)
packages+=(clang-format-14)  # the layout check in .ci/run (scripts/check_format.sh)
packages+=(zsh groff-base)  # cli.completion checks the zsh completion parses and the man page renders (docs/cli.md)
# The Python module and its tests, for Debian's /usr/bin/python3 (docs/python.md)
packages+=(pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib)
packages+=(python3-skimage)  # the perceptual metrics' reference in python/tests/test_metrics.py (docs/metrics.md)
packages+=(python3-torch)  # layerlab.torch, the forward model's autograd Functions (docs/python.md)
# pip install . into a virtual environment, offline, with Debian's build backend (python.pip_install)
packages+=(python3-venv python3-pip python3-setuptools python3-wheel python3-build)
packages+=(python3-mypy)  # python.stubs type-checks a use of the API against the shipped stubs
packages+=(libopenmpi-dev openmpi-bin)  # layerlab sweep --mpi and its tests (docs/sweeps.md)
packages+=(libnlopt-dev)  # layerlab optimize (docs/optimize.md)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  echo "setup: installing ${missing[*]}"
  $sudo apt-get update
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends "${missing[@]}"
fi

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "$@"
cmake --build build -j2
