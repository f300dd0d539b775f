"""Python.pip_install: `pip install .` as docs/python.md says, into a new virtual environment, then
`import toolpoint` from outside the source tree and one computation checked against a closed form.

    check_pip_install.py SOURCE_DIR CMAKE_BUILD_DIR

The venv takes Debian's numpy (--system-site-packages); the build uses Debian's setuptools, wheel
and pybind11 (--no-build-isolation) and no index (--no-index: offline). By default the CMake build
folder of the tests is reused (setup.py builds only its target toolpoint_python there), so the test
takes seconds; TOOLPOINT_PIP_TEST_FRESH=1 lets setup.py configure and build a folder of its own,
CMAKE_BUILD_DIR/pip-fresh (the whole library once, minutes; then incremental), as a user's
`pip install .` does.
"""
import os
import subprocess
import sys
import tempfile
from pathlib import Path

source, build = Path(sys.argv[1]).resolve(), Path(sys.argv[2]).resolve()
env = dict(os.environ)
env.pop("PYTHONPATH", None)  # the installed package, not the build tree's
env["TOOLPOINT_CMAKE_BUILD_DIR"] = str(build / "pip-fresh" if os.environ.get("TOOLPOINT_PIP_TEST_FRESH") else build)

# What the installed package is checked for, run by the venv's interpreter in an empty folder.
CHECK = r'''
import importlib.resources, sys
import numpy as np
import toolpoint as tp
assert "site-packages" in tp.__file__ and sys.prefix in tp.__file__, tp.__file__
files = {p.name for p in importlib.resources.files("toolpoint").iterdir()}
assert {"py.typed", "__init__.pyi"} <= files, f"not shipped: {files}"
# Savitzky-Golay of order 2 reproduces a quadratic exactly (its least-squares fit is the data):
x = np.linspace(0.0, 1.0, 21)
y = 3.0 * x**2 - 2.0 * x + 0.5
s = tp.savgol_filter(y, 7, 2)
assert np.max(np.abs(s - y)) < 1e-12, np.max(np.abs(s - y))   # rounding only
print("installed", tp.__version__, "at", tp.__file__)
'''

with tempfile.TemporaryDirectory(prefix="toolpoint-pip-") as tmp:
    venv = Path(tmp) / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True)
    python = str(venv / "bin" / "python")
    subprocess.run([python, "-m", "pip", "install", "--no-build-isolation", "--no-index", "--no-cache-dir",
                    "--disable-pip-version-check", "-q", str(source)], check=True, env=env)
    work = Path(tmp) / "elsewhere"
    work.mkdir()
    subprocess.run([python, "-c", CHECK], check=True, cwd=work, env=env)
