"""`pip install .` for the toolpoint Python package: the extension is built by the project's own
CMake build (target toolpoint_python, python/CMakeLists.txt), never from a second list of sources.

The CMake build folder is build/pip/cmake (kept, so a second install rebuilds only what changed;
ccache is used when installed). TOOLPOINT_CMAKE_BUILD_DIR names another: one that is already
configured keeps its settings and only its target toolpoint_python is built (the test
Python.pip_install reuses the test build so), a new one is configured for the Python module alone.
CMAKE_BUILD_PARALLEL_LEVEL sets the jobs (default: every core). The package's pure-Python files,
stubs (.pyi) and py.typed come from python/toolpoint, the compiled module from the CMake build;
setuptools' own scratch goes beside the CMake folder, never into the source tree.
"""
import os
import re
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent
CMAKE_DIR = Path(os.environ.get("TOOLPOINT_CMAKE_BUILD_DIR") or ROOT / "build" / "pip" / "cmake").resolve()
SCRATCH = CMAKE_DIR / "pip-setuptools"


def cmake_version():
    """The one version: project(toolpoint VERSION x.y.z) in CMakeLists.txt."""
    m = re.search(r"project\(toolpoint\s+VERSION\s+([0-9.]+)", (ROOT / "CMakeLists.txt").read_text())
    if not m:
        raise RuntimeError("CMakeLists.txt: no project(toolpoint VERSION x.y.z)")
    return m.group(1)


class CMakeBuild(build_ext):
    """Configures the project for the Python module alone (no CLI, tests or benchmarks) for this
    interpreter, builds toolpoint_python and copies the module where setuptools packs it."""

    def build_extension(self, ext):
        cmake = shutil.which("cmake")
        if cmake is None:
            raise RuntimeError("toolpoint: cmake not found; fix: apt-get install cmake (bash scripts/run.sh build installs it)")
        build_dir = CMAKE_DIR
        configure = [
            cmake, "-S", str(ROOT), "-B", str(build_dir),
            "-DCMAKE_BUILD_TYPE=Release",
            "-DTOOLPOINT_BUILD_PYTHON=ON", "-DTOOLPOINT_BUILD_CLI=OFF", "-DTOOLPOINT_BUILD_TESTS=OFF",
            "-DTOOLPOINT_BUILD_BENCH=OFF", "-DTOOLPOINT_INSTALL=OFF",
            # This interpreter (a venv's python is its base interpreter with the venv's site-packages).
            f"-DTOOLPOINT_PYTHON={sys.executable}",
        ]
        if shutil.which("ccache"):
            configure.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        if not (build_dir / "CMakeCache.txt").exists():
            subprocess.run(configure, check=True)
        subprocess.run([cmake, "--build", str(build_dir), "--target", "toolpoint_python", "-j", jobs], check=True)
        # The module for this interpreter's ABI (a reused folder may have been built for another).
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        built = build_dir / "python" / "toolpoint" / f"_toolpoint{suffix}"
        if not built.exists():
            raise RuntimeError(f"toolpoint: {built} was not built (a CMake folder configured for another Python?); "
                               "fix: give TOOLPOINT_CMAKE_BUILD_DIR a new folder")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


SCRATCH.mkdir(parents=True, exist_ok=True)  # egg_base must exist
setup(
    version=cmake_version(),
    ext_modules=[Extension("toolpoint._toolpoint", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": str(SCRATCH)}, "egg_info": {"egg_base": str(SCRATCH)}},
)
