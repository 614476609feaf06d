"""Builds the extension isocorr._isocorr with the repository's CMake project.

The engine is C++ (the folder above this one); CMake builds the module with pybind11.
ISOCORR_CMAKE_BUILD_DIR names an existing build folder configured with
-DISOCORR_BUILD_PYTHON=ON (the tests reuse the one scripts/build.sh made); otherwise a
fresh one is configured without the service and the tests. ISOCORR_CMAKE_ARGS adds
configure options, e.g. -DISOCORR_ARCH=auto for this machine's widest instruction set.
"""

import os
import pathlib
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

REPOSITORY = pathlib.Path(__file__).resolve().parent.parent


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        target = pathlib.Path(self.get_ext_fullpath(ext.name)).resolve()
        build = os.environ.get("ISOCORR_CMAKE_BUILD_DIR")
        if build:
            build = pathlib.Path(build).resolve()
        else:
            build = pathlib.Path(self.build_temp).resolve() / "cmake"
            subprocess.check_call(
                ["cmake", "-S", str(REPOSITORY), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                 "-DISOCORR_BUILD_SERVICE=OFF", "-DISOCORR_BUILD_TESTS=OFF", "-DISOCORR_BUILD_PYTHON=ON",
                 f"-DPython_EXECUTABLE={sys.executable}"]
                + shlex.split(os.environ.get("ISOCORR_CMAKE_ARGS", "")))
        subprocess.check_call(
            ["cmake", "--build", str(build), "--target", "_isocorr", "--parallel", str(os.cpu_count() or 1)])
        built = next((build / "python").glob("_isocorr*.so"))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


setup(ext_modules=[CMakeExtension("isocorr._isocorr")], cmdclass={"build_ext": CMakeBuild})
