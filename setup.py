"""Builds the intermix Python package with CMake for `pip install --no-build-isolation .`.

The version is CMake's (project(intermix VERSION ...) in CMakeLists.txt). The extension module
comes from an existing build when INTERMIX_BUILD_DIR names one (its python/intermix folder,
brought up to date with `cmake --build DIR --target intermix_python`), else from a build of its
own in build-pip/cmake (Release, no tests; minutes on two cores). setuptools' own folders go to
build-pip/ too, never into build/, the CMake build folder.
"""

import os
import re
import shutil
import subprocess
import sys

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))
WORK = os.path.join(HERE, "build-pip")
PACKAGE_FILES = ("__init__.py", "__init__.pyi", "py.typed", "_images.py", "_figures.py",
                 "_movies.py")


def cmake_version():
    with open(os.path.join(HERE, "CMakeLists.txt")) as f:
        match = re.search(r"project\(intermix VERSION ([0-9.]+)", f.read())
    if not match:
        sys.exit("setup.py: no project(intermix VERSION ...) line in CMakeLists.txt")
    return match.group(1)


def built_package():
    """The folder holding the built package (python/intermix under a CMake build folder)."""
    build = os.environ.get("INTERMIX_BUILD_DIR")
    if build:
        build = os.path.abspath(build)
        if not os.path.isfile(os.path.join(build, "CMakeCache.txt")):
            sys.exit(f"setup.py: INTERMIX_BUILD_DIR={build} is not a CMake build folder")
    else:
        build = os.path.join(WORK, "cmake")
        subprocess.run(["cmake", "-S", HERE, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                        "-DIMX_BUILD_TESTS=OFF", f"-DPython_EXECUTABLE={sys.executable}"],
                       check=True)
    jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
    subprocess.run(["cmake", "--build", build, "--target", "intermix_python", "-j", jobs],
                   check=True)
    return os.path.join(build, "python", "intermix")


class BuildWithCMake(build_py):
    def run(self):
        source = built_package()
        target = os.path.join(self.build_lib, "intermix")
        os.makedirs(target, exist_ok=True)
        modules = [f for f in os.listdir(source) if f.startswith("_intermix") and f.endswith(".so")]
        if len(modules) != 1:
            sys.exit(f"setup.py: expected one _intermix*.so in {source}, found {modules}")
        for name in PACKAGE_FILES + tuple(modules):
            shutil.copy2(os.path.join(source, name), os.path.join(target, name))
        # Scene.show's page
        shutil.copytree(os.path.join(source, "web"), os.path.join(target, "web"), dirs_exist_ok=True)


class BinaryDistribution(Distribution):
    def has_ext_modules(self):  # a platform wheel: the package holds a compiled module
        return True


os.makedirs(WORK, exist_ok=True)
setup(
    version=cmake_version(),
    packages=["intermix"],
    package_dir={"intermix": "python/intermix"},
    cmdclass={"build_py": BuildWithCMake},
    distclass=BinaryDistribution,
    options={"build": {"build_base": os.path.relpath(WORK, HERE)},
             "egg_info": {"egg_base": os.path.relpath(WORK, HERE)}},
    zip_safe=False,
)
