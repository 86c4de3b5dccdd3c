"""The extension module poreshell._poreshell, built by CMake (pyproject.toml has the rest).

`pip install .` configures a Release build of the library and the module in a temporary directory and
builds the module's target only (through ccache where there is one; PORESHELL_CMAKE_ARGS adds
arguments to that configure step). With PORESHELL_CMAKE_BUILD_DIR set to a configured build directory (the
tests' and CI's build/), it runs `cmake --build` there instead, which does nothing when the module is
built, so that making a wheel in CI compiles nothing a second time. Either way the module built is copied
into the wheel. Offline (no download of setuptools): pip install --no-build-isolation .
"""

import glob
import os
import re
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))


def version():
    with open(os.path.join(ROOT, "CMakeLists.txt"), encoding="utf-8") as f:
        return re.search(r"project\(poreshell VERSION ([0-9.]+)", f.read()).group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build_dir = os.environ.get("PORESHELL_CMAKE_BUILD_DIR")
        jobs = ["-j", str(self.parallel)] if self.parallel else []
        if build_dir:
            build_dir = os.path.abspath(build_dir)
            if not os.path.isfile(os.path.join(build_dir, "CMakeCache.txt")):
                sys.exit("PORESHELL_CMAKE_BUILD_DIR=%s is not a configured CMake build directory" % build_dir)
        else:
            build_dir = os.path.abspath(os.path.join(self.build_temp, "cmake"))
            generator = ["-G", "Ninja"] if shutil.which("ninja") else []
            # ccache where there is one: a reinstall then compiles nothing that did not change.
            launcher = ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache"] if shutil.which("ccache") else []
            extra = shlex.split(os.environ.get("PORESHELL_CMAKE_ARGS", ""))  # e.g. -DPORESHELL_WERROR=ON
            subprocess.run(
                ["cmake", "-S", ROOT, "-B", build_dir, *generator, *launcher, "-DCMAKE_BUILD_TYPE=Release",
                 "-DPORESHELL_BUILD_TESTS=OFF", "-DPORESHELL_PYTHON=ON", "-DPython_EXECUTABLE=" + sys.executable,
                 *extra],
                check=True,
            )
        subprocess.run(["cmake", "--build", build_dir, "--target", "_poreshell", *jobs], check=True)
        built = glob.glob(os.path.join(build_dir, "python", "poreshell", "_poreshell*.so"))
        if len(built) != 1:
            sys.exit("the CMake build in %s made no single poreshell/_poreshell*.so (the Python package is "
                     "not built with PORESHELL_SANITIZE or without pybind11: see its configure log)" % build_dir)
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        # The name CMake gave carries the interpreter's suffix, which must be the one setuptools expects.
        if os.path.basename(built[0]) != os.path.basename(target):
            sys.exit("the module %s was built for another Python than %s (%s): configure the build "
                     "with -DPython_EXECUTABLE=%s" % (built[0], sys.executable, os.path.basename(target),
                                                       sys.executable))
        shutil.copyfile(built[0], target)


# setuptools' own files: not in build/ (where the project's CMake build usually lives) nor python/ (the
# sources); inside the given CMake build directory when there is one, so that the tests leave the source
# tree as it was.
if os.environ.get("PORESHELL_CMAKE_BUILD_DIR"):
    BASE = os.path.join(os.path.abspath(os.environ["PORESHELL_CMAKE_BUILD_DIR"]), "setuptools")
else:
    BASE = os.path.join(ROOT, "build-python")
os.makedirs(BASE, exist_ok=True)
setup(
    version=version(),
    ext_modules=[Extension("poreshell._poreshell", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": BASE}, "egg_info": {"egg_base": BASE}},
)
