"""The Python examples run, and give what the CLI gives: demo.py prints `toolpoint demo`'s report
line for line; tap_test_to_lobes.py gives the tutorial's (docs/tutorial.md) CLI results to the bit."""
import importlib.util
import subprocess
import sys

import numpy as np

from conftest import EXAMPLE, SOURCE_DIR, read_block_csv, run_cli, run_cli_json

EXAMPLES = SOURCE_DIR / "examples" / "python"


def load(name):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_demo_py_prints_the_cli_demo_report(tmp_path):
    # Linearised intervals (--bootstrap 0) keep it quick (the bootstrap is compared in the tutorial's
    # test); the numbers are the CLI's at the same setting.
    py = subprocess.run([sys.executable, str(EXAMPLES / "demo.py"), "--bootstrap", "0", "--figures", str(tmp_path / "fig")],
                        capture_output=True, text=True)
    assert py.returncode == 0, py.stderr
    cli = run_cli("demo", "--no-plots", "--bootstrap", 0, "--output", tmp_path / "cli")
    # The report, up to what each wrote (the CLI its data files, demo.py its figures, if any).
    expected = cli.split("\nwrote ")[0].rstrip("\n").splitlines()
    assert py.stdout.split("\nwrote ")[0].rstrip("\n").splitlines() == expected
    assert any(line.startswith("k_yf ") for line in expected)  # the table is there
    # Without matplotlib the figures are skipped with a note (with it, they are drawn and listed).
    try:
        import matplotlib  # noqa: F401
        figure = tmp_path / "fig" / "tool_point_frf.png"
        assert figure.exists()
        assert f"wrote {figure} (figure)" in py.stdout.splitlines()
    except ImportError:
        assert "matplotlib is not installed" in py.stderr
        assert "\nwrote " not in py.stdout


def test_tap_test_to_lobes_follows_the_cli_tutorial(tmp_path):
    r = load("tap_test_to_lobes").main(["--bootstrap", "20", "--threads", "1", "--figures", str(tmp_path / "fig")])
    # The tutorial's commands (docs/tutorial.md), binary UFF so the doubles pass through files unchanged.
    run_cli("taptest", EXAMPLE, "--at", "holder", "--spacing", 0.02, "--sigma", 0.005, "--binary", "--output", "tap_holder.uff", cwd=tmp_path)
    run_cli("taptest", EXAMPLE, "--at", "tool", "--spacing", 0.015, "--sigma", 0.005, "--seed", 11, "--binary", "--output", "tap_tool.uff",
            cwd=tmp_path)
    from toolpoint import run_tap_test_study, load_assembly
    a = load_assembly(str(EXAMPLE)).assembly
    k_h = run_tap_test_study(a, spacing_m=0.02, side="holder").shear_stiffness_n
    k_t = run_tap_test_study(a, spacing_m=0.015).shear_stiffness_n
    run_cli("rotational", "--uff", "tap_holder.uff", "--spacing", 0.02, "--order", 2, "--shear-stiffness", repr(k_h),
            "--model", EXAMPLE, "--at", "holder", "--output", "sh11.csv", cwd=tmp_path)
    run_cli("rotational", "--uff", "tap_tool.uff", "--spacing", 0.015, "--order", 2, "--shear-stiffness", repr(k_t),
            "--model", EXAMPLE, "--at", "tool", "--output", "sht11.csv", cwd=tmp_path)
    assert np.array_equal(read_block_csv(tmp_path / "sh11.csv")[1], r["sh11"])
    assert np.array_equal(read_block_csv(tmp_path / "sht11.csv")[1], r["sht11"])
    ident = run_cli_json("identify", "--assembly", EXAMPLE, "--sh", "sh11.csv", "--sht", "sht11.csv", "--bootstrap", 20,
                         "--joint-output", "kht.toml", cwd=tmp_path)
    ours = r["identification"].to_dict()
    assert ours["parameters"] == ident["parameters"] and ours["verdict"] == ident["verdict"]
    assert ident["verdict"]["verdict"] == "pass"
    run_cli("filter", "sh11.csv", "sh11_f.csv", "--window", 41, "--order", 2, cwd=tmp_path)
    assert np.array_equal(read_block_csv(tmp_path / "sh11_f.csv")[1], r["sh11_f"])
    run_cli("couple", "--sh", "sh11_f.csv", "--assembly", EXAMPLE, "--joint", "holder-tool=kht.toml", "--overhang", "0.040:0.060:0.004",
            "--output", "overhangs", cwd=tmp_path)
    _, sht48 = read_block_csv(tmp_path / "overhangs" / "sht11_overhang_48.0mm.csv")
    assert np.array_equal(r["study"].overhangs[2].sht11, sht48)
    lobes = run_cli_json("lobes", "--frf", "overhangs/sht11_overhang_48.0mm.csv", "--teeth", 4, "--kt", 6e8, "--kr", 0.3, "--immersion", 0.5,
                         "--milling", "down", "--rpm", "2000:20000", cwd=tmp_path)
    assert r["lobes"].to_dict()["pockets"] == lobes["pockets"]


def test_the_docs_example_runs(tmp_path, monkeypatch):
    # docs/python.md's example, as written (run in a scratch folder: it writes sht11.uff).
    text = (SOURCE_DIR / "docs" / "python.md").read_text()
    code = text.split("```python\n", 1)[1].split("```", 1)[0]
    monkeypatch.chdir(tmp_path)
    (tmp_path / "examples").symlink_to(SOURCE_DIR / "examples")
    scope = {}
    exec(compile(code, "docs/python.md", "exec"), scope)
    assert [round(m.frequency_hz, 1) for m in scope["p"].modes] == [916.1, 1599.8, 2584.6, 3629.0, 4554.2]
    assert (tmp_path / "sht11.uff").exists() and len(code.strip().splitlines()) <= 12
