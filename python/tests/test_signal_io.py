"""Signal processing and files: against the CLI (the same doubles), closed forms, pyuff's reading of
real UFF files, round trips, and errors that name what is wrong."""
import json

import numpy as np
import pytest

import toolpoint as tp
from conftest import EXAMPLE, SOURCE_DIR, read_block_csv, read_csv, run_cli


def test_savgol_coefficients_closed_form():
    # Savitzky & Golay (1964): window 5, quadratic: (−3, 12, 17, 12, −3)/35 (docs/reference.md §6's oracle).
    c = tp.savgol_coefficients(5, 2)
    assert np.allclose(c, np.array([-3, 12, 17, 12, -3]) / 35, rtol=0, atol=1e-15)


def test_savgol_filter_reproduces_polynomials_and_the_cli(tmp_path, example, prediction):
    x = np.linspace(0, 1, 50)
    cubic = 1 - 2 * x + 3 * x**3
    assert np.allclose(tp.savgol_filter(cubic, 11, 3), cubic, rtol=0, atol=1e-13)  # exact for degree ≤ order
    f, blocks = prediction.frequency_hz, prediction.frf
    noisy = tp.add_measurement_noise(f, blocks, sigma=0.05, seed=3)
    tp.write_frf_file(str(tmp_path / "noisy.csv"), f, noisy)
    run_cli("filter", tmp_path / "noisy.csv", tmp_path / "filtered.csv", "--window", 41, "--order", 2)
    _, cli = read_block_csv(tmp_path / "filtered.csv")
    ours = tp.savgol_filter(noisy, 41, 2, frequency_hz=f)
    assert ours.shape == (4991, 2, 2) and ours.dtype == np.complex128
    assert np.array_equal(ours, cli)
    assert np.array_equal(tp.savgol_filter(noisy, 41, 2), cli)  # the grid only checks evenness
    h = tp.savgol_filter(noisy[:, 0, 0], 41, 2)
    assert np.array_equal(h, cli[:, 0, 0])


def test_filter_study_is_the_cli_one(tmp_path, prediction):
    """run_filter_study gives what `toolpoint filter` writes (the same doubles) and prints (its peak
    table, as printed: 6 significant digits, changes in % to 2 decimals)."""
    f, blocks = prediction.frequency_hz, prediction.frf
    noisy = tp.add_measurement_noise(f, blocks, sigma=0.05, seed=3)
    tp.write_frf_file(str(tmp_path / "noisy.csv"), f, noisy)
    out = run_cli("filter", tmp_path / "noisy.csv", tmp_path / "filtered.csv", "--window", 41, "--order", 2)
    _, cli = read_block_csv(tmp_path / "filtered.csv")
    r = tp.run_filter_study(f, noisy, 41, 2, what=str(tmp_path / "noisy.csv"))
    assert isinstance(r, tp.BlockFilterStudy) and np.array_equal(r.filtered, cli)
    assert r.noise_gain == pytest.approx(np.sum(tp.savgol_coefficients(41, 2) ** 2), rel=1e-15)
    rows = [line.split() for line in out.splitlines()[2:] if line.startswith("  ") and not line.startswith("  (")]
    peaks = r.to_dict()["peaks"]["peaks"]
    assert len(rows) == len(peaks) > 0
    for row, p in zip(rows, peaks):
        assert row[0] == p["entry"] and row[1] == f"{p['raw_frequency_hz']:.6g}"
        assert row[5] == f"{100 * p['height_change']:+.2f}"
    # A window of 41 flattens the sharp peaks by more than 2 %: said in the result's warnings.
    assert r.to_dict()["peaks"]["warnings"] and all(w in r.warnings for w in r.to_dict()["peaks"]["warnings"])
    single = tp.run_filter_study(f, noisy[:, 0, 0], 5, 2)
    assert isinstance(single, tp.FilterStudy) and single.filtered.shape == (len(f),)


def test_resample_frf_is_the_cli_one(tmp_path, prediction):
    """run_resample_study gives what `toolpoint resample` writes: interpolated onto a grid cropped to a band,
    or cropped, the coherence carried (CSV: shortest round-trip doubles, so equality is exact)."""
    f, h = prediction.frequency_hz[::10], prediction.frf[::10, 0, 0]
    coh = np.linspace(0.5, 1.0, len(f))
    rows = "".join(f"{x!r},{v.real!r},{v.imag!r},{c!r}\n" for x, v, c in zip(f, h, coh))
    (tmp_path / "h.csv").write_text("frequency_hz,re,im,coherence\n" + rows)
    data = tp.read_frf_file(str(tmp_path / "h.csv"))
    run_cli("resample", tmp_path / "h.csv", tmp_path / "g.csv", "--grid", "1:5000:4", "--band", "300:4000",
            "--method", "cubic")
    r = tp.run_resample_study(data, band_hz=(300.0, 4000.0), target_hz=np.arange(1.0, 5000.0, 4.0), method="cubic",
                              target_name="--grid 1:5000:4", what=str(tmp_path / "h.csv"))
    d = read_csv(tmp_path / "g.csv")
    assert np.array_equal(r.file.frequency_hz, d[:, 0]) and np.array_equal(r.file.values, d[:, 1] + 1j * d[:, 2])
    assert np.array_equal(r.coherence, d[:, 3])
    assert f"h.csv {r.description}" in (tmp_path / "g.csv").read_text() and r.warnings == []
    assert r.description == "cubic interpolation of real and imaginary parts onto --grid 1:5000:4, within 300–4000 Hz"
    run_cli("resample", tmp_path / "h.csv", tmp_path / "c.csv", "--band", "300:4000")
    r = tp.run_resample_study(data, band_hz=(300.0, 4000.0))
    d = read_csv(tmp_path / "c.csv")
    assert np.array_equal(r.file.values, d[:, 1] + 1j * d[:, 2]) and np.array_equal(r.coherence, d[:, 3])
    assert r.description == "cropped to 300–4000 Hz"
    with pytest.raises(tp.InputError, match="FrfResampleOptions::band_hz"):
        tp.run_resample_study(data, band_hz=(1.0, 2.0), target_hz=[5000.0, 6000.0])


def test_noise_is_the_cli_noise(tmp_path, prediction):
    f, h = prediction.frequency_hz, prediction.frf[:, 0, 0]
    tp.write_frf_file(str(tmp_path / "h.csv"), f, h)
    run_cli("noise", tmp_path / "h.csv", tmp_path / "hn.csv", "--sigma", 0.05, "--seed", 7)
    d = read_csv(tmp_path / "hn.csv")
    noisy = tp.add_measurement_noise(f, h, sigma=0.05, seed=7)
    assert np.array_equal(noisy, d[:, 1] + 1j * d[:, 2])
    # The factors are 1 + σz with z from standard_normals: real, mean 1, σ 5 %.
    z = tp.standard_normals(len(f), 7)
    assert np.array_equal(noisy, h * (1 + 0.05 * z))
    assert abs(np.mean(z)) < 4 / np.sqrt(len(z)) and abs(np.std(z) - 1) < 0.05


def test_rotational_frfs_are_the_cli_ones(tmp_path, example):
    run_cli("taptest", EXAMPLE, "--at", "tool", "--spacing", 0.015, "--binary", "--output", tmp_path / "tap.uff")
    t = tp.run_tap_test_study(example, spacing_m=0.015)
    run_cli("rotational", "--uff", tmp_path / "tap.uff", "--spacing", 0.015, "--order", 2, "--shear-stiffness",
            repr(t.shear_stiffness_n), "--output", tmp_path / "sht11.csv")
    _, cli = read_block_csv(tmp_path / "sht11.csv")
    H = {(r.response, r.hammer): r.values for r in t.frfs}
    r = tp.rotational_frfs(example.frequency_hz, H, tp.RotationalOptions(spacing=0.015, order=2, shear_stiffness=t.shear_stiffness_n))
    assert np.array_equal(r.block, cli)
    assert r.p_from_cross_terms
    assert np.array_equal(r.block[:, 0, 0], t.frf(0, 0))  # H is the tip's H00 itself


def test_frf_files_round_trip(tmp_path, prediction):
    f, blocks = prediction.frequency_hz, prediction.frf
    h = blocks[:, 0, 0]
    tp.write_frf_file(str(tmp_path / "b.csv"), f, blocks, comments=["a comment"])
    back = tp.read_frf_file(str(tmp_path / "b.csv"))
    assert back.is_block and np.array_equal(back.values, blocks) and np.array_equal(back.frequency_hz, f)
    for name, fmt in (("h.csv", "auto"), ("h.uff", "uffb"), ("h.frf", "auto")):
        lost = tp.write_frf_file(str(tmp_path / name), f, h, format=fmt,
                                 dof={"response_node": 1, "response_direction": 2, "reference_node": 1, "reference_direction": 2})
        r = tp.read_frf_file(str(tmp_path / name))
        assert r.values.shape == (4991,) and r.values.dtype == np.complex128
        assert np.array_equal(r.values, h) and not lost, name  # CSV, 58b and .frf keep every digit
    md = tp.read_frf_file(str(tmp_path / "h.uff")).metadata
    assert md["format"] == "uff" and md["dof"]["response_direction"] == 2 and md["ordinate"] == "receptance"
    # ASCII UFF: E20.12 fields, 13 significant digits.
    tp.write_frf_file(str(tmp_path / "a.uff"), f, h)
    assert np.allclose(tp.read_frf_file(str(tmp_path / "a.uff")).values, h, rtol=1e-12, atol=0)


def test_uff_datasets_as_pyuff_reads_them():
    # The real files and pyuff's reading of them (tests/data/uff/pyuff_expected.json).
    uff_dir = SOURCE_DIR / "tests" / "data" / "uff"
    expected = json.loads((uff_dir / "pyuff_expected.json").read_text())
    for name in ("Sample_UFF58b_bin.uff", "binary8byte.uff"):
        u = tp.read_uff(str(uff_dir / name))
        for e in expected[name]["datasets58"]:
            d = u.functions[e["index"]]
            assert d.function_type == e["func_type"] and len(d.y) == e["num_pts"] and d.id[0] == e["id1"]
            assert (d.response_node, d.response_direction) == (e["rsp_node"], e["rsp_dir"])
            assert d.x[0] == e["x_first"] and d.x[-1] == pytest.approx(e["x_last"], rel=1e-12)
            assert d.y[0].real == pytest.approx(e["data_first"], rel=1e-7) and d.y[-1].real == pytest.approx(e["data_last"], rel=1e-7)
            assert d.y.real.sum() == pytest.approx(e["sum"], rel=1e-9)
            assert d.metadata["function_type_name"]


def test_uff_write_read(tmp_path):
    f = np.linspace(10.0, 100.0, 10)
    d = tp.UffDataset58(f, (1 + 2j) * f)
    d.id = ["tap", "NONE", "NONE", "NONE", "NONE"]
    d.response_node, d.reference_node = 3, 1
    for binary in (False, True):
        tp.write_uff(str(tmp_path / "x.uff"), [d, d], binary=binary)
        u = tp.read_uff(str(tmp_path / "x.uff"))
        assert len(u.functions) == 2 and u.functions[1].response_node == 3 and u.functions[0].id[0] == "tap"
        assert np.allclose(u.functions[0].y, d.y, rtol=1e-12, atol=0)


def test_bad_files_raise_with_file_line_and_hint(tmp_path):
    with pytest.raises(tp.IoError):
        tp.read_frf_file(str(tmp_path / "missing.csv"))
    (tmp_path / "bad.csv").write_text("frequency_hz,re,im\n10,1,2\n20,x,3\n")
    with pytest.raises(tp.InputError) as e:
        tp.read_frf_file(str(tmp_path / "bad.csv"))
    assert "bad.csv:3" in str(e.value) and isinstance(e.value.hint, str)
    with pytest.raises(tp.InvalidArgument) as e:  # also a ValueError
        tp.savgol_filter(np.ones(10), 4, 2)
    assert isinstance(e.value, ValueError) and "window" in str(e.value)
    with pytest.raises(tp.InputError) as e:
        tp.savgol_filter(np.array([1.0, np.nan, 1, 1, 1, 1, 1]), 5, 2)
    with pytest.raises(tp.InvalidArgument):
        tp.read_frf_file(str(tmp_path / "bad.csv"), format="xlsx")


def test_uneven_grid_gives_a_python_warning():
    f = np.array([1.0, 2, 3, 4, 5, 7, 8])
    with pytest.warns(tp.Warning, match="even"):
        tp.savgol_filter(np.ones(7, complex), 5, 2, frequency_hz=f)


def test_finite_difference_correction_restores_the_model_block():
    # On exact model data the correction is exact by construction: FD(H) − (FD(H) − exact) = exact,
    # the tap test and the correction taking the same station receptances (rounding of one subtraction).
    # H is not differenced: the tap test's H00 (station receptances) against the model's tip block
    # (another evaluation path) agree to rounding, 1e-9 of the peak (README: the model's paths agree to 5e-11
    # above 300 Hz, 1e-8 below 100 Hz).
    a = tp.load_assembly(str(EXAMPLE)).assembly  # a fresh copy: the grid is changed below
    a.grid = (10.0, 5000.0, 20.0)
    t = tp.run_tap_test_study(a, spacing_m=0.015)
    H = {(r.response, r.hammer): r.values for r in t.frfs}
    measured = tp.rotational_frfs(t.frfs[0].frequency_hz, H, tp.RotationalOptions(spacing=0.015, shear_stiffness=t.shear_stiffness_n)).block
    e = tp.finite_difference_error(a, t.frfs[0].frequency_hz, list(H), tp.RotationalOptions(spacing=0.015, shear_stiffness=t.shear_stiffness_n))
    assert e.error.shape == e.exact.shape == measured.shape
    corrected = measured - e.error
    tolerance = np.array([[1e-9, 1e-12], [1e-12, 1e-12]]) * np.abs(e.exact).max(axis=0)  # per entry H, L, N, P
    assert np.all(np.abs(corrected - e.exact) <= tolerance)
    assert np.allclose(e.exact, tp.AssemblyModel(a).tool_point(t.frfs[0].frequency_hz), rtol=1e-8, atol=0)
    assert e.max_relative[2] > 1e-3  # the differences do err (N at 15 mm)


def test_rotational_study_is_the_cli_and_the_correction_called_directly(tmp_path):
    # A noise-free virtual tap test on the holder, as the CLI writes it, read back by node; the study with the model
    # that made the data is `toolpoint rotational --model` (the same doubles), is rotational_frfs minus
    # finite_difference_error called directly (one subtraction: bit for bit), and is the model's own SH11 by the
    # coupling path to 1e-7 of each entry's largest value (station and point coupling are different algebra;
    # differences 20 mm apart lose ~4 digits), where the uncorrected P is off by more than 1 %.
    run_cli("taptest", EXAMPLE, "--at", "holder", "--spacing", 0.02, "--frequencies", "200:3000:20", "--binary",
            "--output", tmp_path / "tap.uff")
    run_cli("rotational", "--uff", tmp_path / "tap.uff", "--spacing", 0.02, "--order", 2, "--model", EXAMPLE, "--at",
            "holder", "--output", tmp_path / "fixed.csv")
    _, cli = read_block_csv(tmp_path / "fixed.csv")
    a = tp.load_assembly(str(EXAMPLE)).assembly
    t = tp.tap_test_frfs(tp.read_uff(str(tmp_path / "tap.uff")))
    assert sorted(t.H) == [(i, j) for i in range(3) for j in range(3)] and t.dataset[(1, 0)] == 1
    s = tp.run_rotational_study(t.frequency_hz, t.H, tp.RotationalOptions(spacing=0.02), model=a, side="holder", model_name="A.toml")
    assert np.array_equal(s.block, cli)
    raw = tp.rotational_frfs(t.frequency_hz, t.H, tp.RotationalOptions(spacing=0.02))
    e = tp.finite_difference_error(a, t.frequency_hz, list(t.H), tp.RotationalOptions(spacing=0.02), side="holder")
    assert np.array_equal(s.differences.block, raw.block)
    assert np.array_equal(s.block, raw.block - e.error)
    exact = tp.AssemblyModel(a).holder_tip(t.frequency_hz)
    scale = np.abs(exact).max(axis=0)
    assert np.all(np.abs(s.block - exact).max(axis=0)[[0, 1, 1], [1, 0, 1]] < 1e-7 * scale[[0, 1, 1], [1, 0, 1]])
    assert np.abs(raw.block - exact).max(axis=0)[1, 1] > 0.01 * scale[1, 1]
    d = s.to_dict()
    assert d["correction"]["max_relative"] == list(e.max_relative) and d["order"] == 2 and d["spacing_m"] == 0.02
    assert "estimated on the model A.toml (points on the holder)" in s.correction_note
    # Without a model: the differences themselves, and the study says so.
    plain = tp.run_rotational_study(t.frequency_hz, t.H, tp.RotationalOptions(spacing=0.02))
    assert np.array_equal(plain.block, raw.block) and plain.correction is None
    assert plain.correction_note == "no finite-difference correction"
    with pytest.raises(tp.InputError, match="no dataset with response and reference node 101"):
        tp.tap_test_frfs(tp.read_uff(str(tmp_path / "tap.uff")), nodes=[101, 102, 103])
