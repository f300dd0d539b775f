"""Shared fixtures: the built package (PYTHONPATH set by ctest), the CLI it is compared with
(TOOLPOINT_CLI), the source tree (TOOLPOINT_SOURCE_DIR), and readers for the CLI's files."""
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import toolpoint as tp

SOURCE_DIR = Path(os.environ.get("TOOLPOINT_SOURCE_DIR", Path(__file__).resolve().parents[2]))
EXAMPLE = SOURCE_DIR / "examples" / "bt40_shrinkfit_16mm.toml"


def cli_path():
    path = os.environ.get("TOOLPOINT_CLI")
    if not path:
        pytest.skip("TOOLPOINT_CLI is not set (run through ctest, which sets it)")
    return path


def run_cli(*args, cwd=None, expect=0):
    """Runs the toolpoint CLI; returns its stdout. Fails the test on an unexpected exit code."""
    r = subprocess.run([cli_path(), "--quiet", *map(str, args)], cwd=cwd, capture_output=True, text=True)
    assert r.returncode == expect, f"toolpoint {' '.join(map(str, args))} exited {r.returncode}:\n{r.stderr}"
    return r.stdout


def run_cli_json(*args, cwd=None):
    return json.loads(run_cli(*args, "--json", cwd=cwd))


def read_csv(path):
    """A toolpoint CSV as a float array (rows, columns); numbers are written in shortest round-trip
    form, so this gives back the very doubles the CLI computed."""
    lines = [line for line in Path(path).read_text().splitlines() if line and not line.startswith("#")]
    return np.array([[float(x) if x else np.nan for x in line.split(",")] for line in lines[1:]])


def read_block_csv(path):
    d = read_csv(path)
    f = d[:, 0]
    c = d[:, 1::2] + 1j * d[:, 2::2]
    return f, c.reshape(-1, 2, 2)


@pytest.fixture(scope="session")
def example():
    loaded = tp.load_assembly(str(EXAMPLE))
    return loaded.assembly


@pytest.fixture(scope="session")
def model(example):
    return tp.AssemblyModel(example)


@pytest.fixture(scope="session")
def prediction(example):
    return tp.run_prediction_study(example)


@pytest.fixture
def python():
    return sys.executable


def expect_table_attributes(name, defaults, command, bound=True):
    """The option table `name` (toolpoint._option_fields) holds exactly the fields of `defaults`
    ({field: default}, written out by the test from the headers) with those defaults; where the
    type is `bound` as a class, each attribute has that default and type, and its docstring the
    field's help and, for a field with a flag, `command` and the flag."""
    fields = tp._toolpoint._option_fields[name]
    assert [f["name"] for f in fields] == list(defaults)
    for f in fields:
        assert f["default"] == defaults[f["name"]], f["name"]
    if not bound:
        return
    o = getattr(tp, name)()
    for f in fields:
        value = getattr(o, f["name"])
        assert value == defaults[f["name"]], f["name"]
        assert type(value) is type(defaults[f["name"]]), f["name"]
        doc = getattr(getattr(tp, name), f["name"]).__doc__
        assert f["help"] in doc, f["name"]
        if command and f["flag"]:
            assert f"{command} {f['flag']}" in doc, f["name"]
