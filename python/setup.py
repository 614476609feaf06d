"""Builds the extension isocorr._isocorr with the repository's CMake project.

The engine is C++ (the folder above this one); CMake builds the module with pybind11.
ISOCORR_CMAKE_BUILD_DIR names an existing build folder configured with
-DISOCORR_BUILD_PYTHON=ON (the tests reuse the one scripts/build.sh made); otherwise a
fresh one is configured without the service and the tests. ISOCORR_CMAKE_ARGS adds
configure options, e.g. -DISOCORR_ARCH=auto for this machine's widest instruction set.
The remote client's gRPC stubs are generated from proto/ at the same time.
"""

import os
import pathlib
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext
from setuptools.command.build_py import build_py

REPOSITORY = pathlib.Path(__file__).resolve().parent.parent
# google/rpc/status.proto (Job.error) comes from Debian's golang-github-gogo-googleapis-dev.
GOOGLEAPIS_PROTOS = os.environ.get("ISOCORR_GOOGLEAPIS_PROTO_DIR", "/usr/share/gocode/src/github.com/gogo/googleapis")
GRPC_PYTHON_PLUGIN = os.environ.get("ISOCORR_GRPC_PYTHON_PLUGIN", "/usr/bin/grpc_python_plugin")


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


class BuildWithStubs(build_py):
    """The package plus the API's gRPC stubs for isocorr.Client, generated from proto/ with
    protoc and grpc_python_plugin (protobuf-compiler, protobuf-compiler-grpc): isocorr/v1
    (the service) and isocorr/_proto/google/rpc (google.rpc.Status)."""

    def run(self):
        super().run()
        package = pathlib.Path(self.build_lib)
        includes = [f"-I{REPOSITORY / 'proto'}", f"-I{GOOGLEAPIS_PROTOS}"]
        subprocess.check_call(["protoc", *includes, f"--python_out={package}", f"--grpc_out={package}",
                               f"--plugin=protoc-gen-grpc={GRPC_PYTHON_PLUGIN}", "isocorr/v1/isocorr.proto"])
        vendored = package / "isocorr" / "_proto"
        vendored.mkdir(parents=True, exist_ok=True)
        subprocess.check_call(["protoc", *includes, f"--python_out={vendored}", "google/rpc/status.proto"])


setup(ext_modules=[CMakeExtension("isocorr._isocorr")], cmdclass={"build_ext": CMakeBuild, "build_py": BuildWithStubs})
