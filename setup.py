"""The build of `pip install .` (pyproject.toml): the package's Python files from python/layerlab, and its
compiled part, _layerlab, built by the project's CMake (the module target alone) and copied in.

LAYERLAB_BUILD_DIR=DIR takes the module already built in the CMake build folder DIR (DIR/python/layerlab)
instead of configuring and building one: no compiler runs, and nothing is written outside DIR and the
target. Without it the CMake build folder is build/pip (about 15 minutes on two cores the first time).
setuptools' own intermediate files go to build/pip-setuptools (or DIR/pip-setuptools), never beside the
sources."""

import glob
import os
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE = os.path.dirname(os.path.abspath(__file__))
GIVEN_BUILD = os.environ.get("LAYERLAB_BUILD_DIR")
CMAKE_BUILD = os.path.abspath(GIVEN_BUILD) if GIVEN_BUILD else os.path.join(SOURCE, "build", "pip")
SETUPTOOLS_BUILD = os.path.join(CMAKE_BUILD if GIVEN_BUILD else os.path.join(SOURCE, "build"), "pip-setuptools")


def project_version():
    with open(os.path.join(SOURCE, "CMakeLists.txt"), encoding="utf-8") as f:
        return re.search(r"project\(layerlab VERSION ([0-9.]+)", f.read()).group(1)


class CMakeModule(build_ext):
    """Builds _layerlab with CMake (or takes it from LAYERLAB_BUILD_DIR) and copies it where the wheel wants it."""

    def build_extension(self, ext):
        if not GIVEN_BUILD:
            # Argument lists, no shell: the paths may hold any character.
            subprocess.run(["cmake", "-S", SOURCE, "-B", CMAKE_BUILD, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                            "-DLAYERLAB_WITH_PYTHON=ON", f"-DPython3_EXECUTABLE={sys.executable}",
                            "-DBUILD_TESTING=OFF", "-DLAYERLAB_WITH_BENCHMARKS=OFF"], check=True)
            subprocess.run(["cmake", "--build", CMAKE_BUILD, "--target", "_layerlab", "-j2"], check=True)
        # The module built for this interpreter (its extension suffix names the Python version and ABI).
        name = "_layerlab" + sysconfig.get_config_var("EXT_SUFFIX")
        built = glob.glob(os.path.join(CMAKE_BUILD, "python", "layerlab", name))
        if len(built) != 1:
            raise RuntimeError(f"layerlab: expected one {name} module in {CMAKE_BUILD}/python/layerlab, found "
                               f"{len(built)}" + (" (LAYERLAB_BUILD_DIR: build it first, with "
                                                  "LAYERLAB_WITH_PYTHON, for this Python)" if GIVEN_BUILD else ""))
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(built[0], target)


os.makedirs(SETUPTOOLS_BUILD, exist_ok=True)
setup(
    version=project_version(),
    packages=["layerlab"],
    package_dir={"layerlab": "python/layerlab"},
    package_data={"layerlab": ["*.pyi", "py.typed"]},
    ext_modules=[Extension("layerlab._layerlab", sources=[])],
    cmdclass={"build_ext": CMakeModule},
    options={"build": {"build_base": SETUPTOOLS_BUILD}, "egg_info": {"egg_base": SETUPTOOLS_BUILD}},
    zip_safe=False,
)
