"""Assemblies, the forward model, beams, the prediction, overhang and tap-test studies: against the
CLI (the same code, so the same doubles), against independent algebra, and shapes/dtypes."""
import numpy as np
import pytest

import toolpoint as tp
from conftest import EXAMPLE, read_block_csv, run_cli, run_cli_json


def test_prediction_is_the_cli_prediction_to_the_bit(tmp_path, prediction):
    # The same library call behind both: identical doubles (the CSV keeps shortest round-trip digits).
    run_cli("predict", EXAMPLE, "--output", tmp_path / "sht11.csv")
    f, blocks = read_block_csv(tmp_path / "sht11.csv")
    assert np.array_equal(f, prediction.frequency_hz)
    assert np.array_equal(blocks, prediction.frf)
    j = run_cli_json("predict", EXAMPLE)
    assert [m["frequency_hz"] for m in j["modes"]] == [m.frequency_hz for m in prediction.modes]
    assert prediction.to_dict()["modes"] == j["modes"]


def test_holder_tip_prediction_is_the_cli_one(tmp_path, example):
    p = tp.run_prediction_study(example, receptance="SH11")
    run_cli("predict", EXAMPLE, "--at", "holder", "--output", tmp_path / "sh11.csv")
    f, blocks = read_block_csv(tmp_path / "sh11.csv")
    assert p.receptance == "SH11"
    assert np.array_equal(blocks, p.frf)


def test_arrays_have_the_documented_shapes_and_dtypes(model, prediction):
    f = np.array([100.0, 916.0, 2500.0])
    assert prediction.frequency_hz.dtype == np.float64 and prediction.frequency_hz.shape == (4991,)
    assert prediction.frf.dtype == np.complex128 and prediction.frf.shape == (4991, 2, 2)
    for method in (model.tool_point, model.holder_tip, model.spindle_nose):
        assert method(f).shape == (3, 2, 2) and method(f).dtype == np.complex128
    for method in (model.tool, model.holder, model.holder_tool):
        assert method(f).shape == (3, 4, 4) and method(f).dtype == np.complex128
    # Lists and integer arrays are accepted as frequencies.
    assert np.array_equal(model.tool_point([100, 916, 2500]), model.tool_point(f))


def couple(A, B11, K):
    """Seed Eq. 1/5 in numpy: G11 = A11 − A12 (A22 + K⁻¹ + B11)⁻¹ A21, per frequency."""
    A11, A12, A21, A22 = A[:, :2, :2], A[:, :2, 2:], A[:, 2:, :2], A[:, 2:, 2:]
    return A11 - A12 @ np.linalg.inv(A22 + np.linalg.inv(K) + B11) @ A21


def test_tool_point_is_the_coupling_of_its_components(model, example):
    # An independent route through the (n, 4, 4) two-ports: Eq. 1 then Eq. 5 in numpy, against
    # the library's SIMD sweep. The README states the sweep's agreement with per-frequency algebra:
    # 5e-11 above 300 Hz; numpy's LAPACK inverse rounds differently again, so 1e-8 of each entry's peak.
    f = np.linspace(300.0, 5000.0, 471)
    sh11 = couple(model.holder(f), model.spindle_nose(f), example.spindle_holder.stiffness(f))
    sht11 = couple(model.tool(f), sh11, example.holder_tool.stiffness(f))
    sweep = model.tool_point(f)
    scale = np.abs(sweep).max(axis=0)
    assert np.all(np.abs(sht11 - sweep) <= 1e-8 * scale)
    assert np.all(np.abs(sh11 - model.holder_tip(f)) <= 1e-8 * np.abs(sh11).max(axis=0))


def test_an_assembly_built_from_python_objects_is_the_file_one(example, prediction):
    # Rebuild the example field by field through the constructors: the same FRF to the bit.
    def material(m):
        return tp.Material(m.name, youngs_modulus=m.youngs_modulus, poisson=m.poisson, shear_modulus=m.shear_modulus,
                           density=m.density, loss_factor=m.loss_factor)

    def segment(s):
        return tp.Segment(s.length, [tp.Annulus(l.outer_diameter, l.inner_diameter, material(l.material), l.shear_coefficient)
                                     for l in s.layers], name=s.name, shear_model=s.shear_model)

    t = example.tool
    a = tp.Assembly(
        example.name,
        tp.Spindle([segment(s) for s in example.spindle.segments],
                   [tp.Bearing(b.position, b.stiffness, b.damping, b.rotational_stiffness, b.rotational_damping, b.name)
                    for b in example.spindle.bearings]),
        [segment(s) for s in example.holder],
        tp.Tool(material(t.material), t.length, t.overhang, t.diameter, t.shank_diameter, t.flute_length, t.flute_diameter_ratio,
                t.shear_coefficient),
        spindle_holder=tp.JointParameters.from_array(example.spindle_holder.to_array()),
        holder_tool=tp.JointParameters(**example.holder_tool.to_dict()),
        grid=example.grid)
    assert np.array_equal(tp.run_prediction_study(a).frf, prediction.frf)
    # A rigid joint is None; a changed joint changes the FRF.
    a.holder_tool = None
    assert a.holder_tool is None
    assert not np.array_equal(tp.AssemblyModel(a).tool_point([2500.0]), prediction.frf[2490:2491])


def test_joint_parameters(example):
    p = tp.seed_table1_joint()
    assert p == example.holder_tool  # the example carries the seed's Table 1
    assert p["k_yf"] == p[0] == p.k_yf == 4.19e7
    assert tp.JointParameters.names() == ["k_yf", "c_yf", "k_ym", "c_ym", "k_tf", "c_tf", "k_tm", "c_tm"]
    K = p.stiffness([1000.0])
    assert K.shape == (1, 2, 2)
    assert K[0, 0, 0] == p.k_yf + 1j * 2 * np.pi * 1000.0 * p.c_yf  # Eq. 8
    assert tp.JointParameters(k_ym=2.0, c_ym=3.0).k_tf == 2.0  # reciprocity default
    with pytest.raises(KeyError):
        p["k_xx"]


def test_beam_against_the_cli_and_the_euler_bernoulli_limit(tmp_path):
    steel = tp.Material("steel", youngs_modulus=2e11, poisson=0.3, density=7800)
    s = tp.Segment.tube(0.1, 0.016, 0.0, steel)
    f = tp.free_free_frequencies(s, 5)
    j = run_cli_json("beam", "--length", 0.1, "--diameter", 0.016, "--modes", 5)
    assert list(f) == [m["frequency_hz"] for m in j["modes"]]
    # A slender beam tends to Euler–Bernoulli: β₁L = 4.7300407, f = (β₁L)²/(2πL²) sqrt(EI/ρA).
    slender = tp.Segment.tube(2.0, 0.016, 0.0, steel)
    eb = 4.730040745**2 / (2 * np.pi * 2.0**2) * np.sqrt(2e11 * (0.016**2 / 16) / 7800)
    assert abs(tp.free_free_frequencies(slender, 1)[0] / eb - 1) < 2e-4  # (d/L)² ≈ 6e-5, times a few
    # Exact against modal summation (independent methods), README tolerance for 300 modes: 1e-2 on H, P.
    freqs = np.array([200.0, 3000.0, 11000.0])
    exact = tp.exact_receptance(s, freqs)
    modal = tp.ModalBeam(s, modes=300).receptance(freqs)
    assert exact.shape == modal.shape == (3, 4, 4)
    assert np.all(np.abs(modal[:, 0, 0] - exact[:, 0, 0]) <= 1e-2 * np.abs(exact[:, 0, 0]))
    run_cli("beam", "--length", 0.1, "--diameter", 0.016, "--frequencies", "200:3000:400", "--output", tmp_path / "t11.csv")
    fc, t11 = read_block_csv(tmp_path / "t11.csv")
    assert np.array_equal(tp.exact_receptance(s, fc)[:, :2, :2], t11)
    run_cli("beam", "--length", 0.1, "--diameter", 0.016, "--frequencies", "200:3000:400", "--method", "modal", "--block", 12,
            "--output", tmp_path / "m12.csv")
    _, m12 = read_block_csv(tmp_path / "m12.csv")
    assert np.array_equal(tp.ModalBeam(s).receptance(fc)[:, :2, 2:], m12)  # T12: rows of end 1, columns of end 2


def test_beam_study_is_the_cli_one(tmp_path):
    """run_beam_study gives what `toolpoint beam` prints and writes: the same section and modes (JSON),
    the same receptance (the CSV holds shortest round-trip doubles, so equality is exact)."""
    hollow = dict(length=0.123, outer_diameter=0.016, inner_diameter=0.004)
    j = run_cli_json("beam", "--length", 0.123, "--diameter", 0.016, "--inner-diameter", 0.004, "--modes", 4,
                     "--shear-model", "cowper")
    r = tp.run_beam_study(**hollow, shear_model="cowper", modes=4)
    d = r.to_dict()
    assert d["section"] == j["section"] and d["modes"] == j["modes"]
    assert list(r.mode_frequency_hz) == [m["frequency_hz"] for m in j["modes"]]
    assert d["warnings"] == [] and r.receptance.shape == (0, 2, 2)
    run_cli("beam", "--length", 0.123, "--diameter", 0.016, "--inner-diameter", 0.004, "--frequencies", "100:20000:100",
            "--method", "modal", "--modal-terms", 50, "--static-residual", "--block", 21, "--output", tmp_path / "m21.csv")
    f, m21 = read_block_csv(tmp_path / "m21.csv")
    r = tp.run_beam_study(**hollow, modes=0, frequency_hz=f, method="modal", modal_terms=50, static_residual=True, block="21")
    assert r.method == "modal (50 modes + static residual)"
    assert np.array_equal(r.frequency_hz, f) and np.array_equal(r.receptance, m21)
    with pytest.raises(tp.InvalidArgument, match="BeamStudyOptions::modes"):
        tp.run_beam_study(**hollow, modes=-1)


def test_couple_and_overhang_study_are_the_cli_ones(tmp_path, example, model):
    f = example.frequency_hz
    sh11 = model.holder_tip(f)
    tp.write_frf_file(str(tmp_path / "sh11.csv"), f, sh11)
    run_cli("couple", "--sh", tmp_path / "sh11.csv", "--assembly", EXAMPLE, "--output", tmp_path / "one.csv")
    _, one = read_block_csv(tmp_path / "one.csv")
    assert np.array_equal(tp.couple_tool(example, f, sh11), one)
    # The CLI's sweep START:STOP:STEP is start + i·step rounded to a nanometre (0.044 + 0.005 is not the
    # double 0.049, the sweep's second overhang is).
    assert tp.overhang_sweep(0.044, 0.054, 0.005) == [0.044, 0.049, 0.054] != [0.044 + i * 0.005 for i in range(3)]
    study = tp.run_overhang_study(example, f, sh11, overhangs_m=tp.overhang_sweep(0.044, 0.054, 0.005), threads=2)
    j = run_cli_json("couple", "--sh", tmp_path / "sh11.csv", "--assembly", EXAMPLE, "--overhang", "0.044:0.054:0.005",
                     "--output", tmp_path / "sweep")
    assert study.to_dict()["tracked_modes_hz"] == j["tracked_modes_hz"]
    _, sweep49 = read_block_csv(tmp_path / "sweep" / "sht11_overhang_49.0mm.csv")
    assert np.array_equal(study.overhangs[1].sht11, sweep49)
    assert study.tracked_modes_hz.shape == (len(j["tracked_modes_hz"]), 3)
    # Coupling the model's own SH11 gives the model's SHT11 (Eq. 5 is exact): the sweep's rounding only.
    assert np.allclose(study.overhangs[1].sht11[:, 0, 0], model.tool_point(f)[:, 0, 0], rtol=1e-8, atol=0)


def test_tap_test_is_the_cli_one(tmp_path, example):
    t = tp.run_tap_test_study(example, spacing_m=0.015, sigma=0.005, seed=11)
    run_cli("taptest", EXAMPLE, "--at", "tool", "--spacing", 0.015, "--sigma", 0.005, "--seed", 11, "--binary",
            "--output", tmp_path / "tap.uff")
    u = tp.read_uff(str(tmp_path / "tap.uff"))
    assert len(u.functions) == len(t.frfs) == 9
    for d in u.functions:  # binary 58b holds the doubles exactly; node i+1 is point i
        assert np.array_equal(d.y, t.frf(d.response_node - 1, d.reference_node - 1))
    assert t.distance_m.tolist() == [0.0, 0.015, 0.03]
    assert t.frfs[0].values.dtype == np.complex128
    assert t.to_dict()["shear_stiffness_n"] == t.shear_stiffness_n > 0


def test_progress_is_reported(example):
    seen = []
    tp.run_prediction_study(example, progress=seen.append)
    assert seen and seen[-1] == pytest.approx(1.0) and all(0 < x <= 1 for x in seen)


def test_progress_from_worker_threads_and_concurrent_calls(example, prediction):
    # The overhang study reports progress from its worker threads (the callback takes the GIL).
    f = example.frequency_hz[::10]
    sh11 = tp.AssemblyModel(example).holder_tip(f)
    seen = []
    one = tp.run_overhang_study(example, f, sh11, overhangs_m=[0.045, 0.05, 0.055, 0.06], threads=2, progress=seen.append)
    assert len(seen) >= 4 and max(seen) == pytest.approx(1.0)
    # Python threads may call the library at once (the GIL is released): the same results as alone.
    from concurrent.futures import ThreadPoolExecutor
    with ThreadPoolExecutor(2) as pool:
        runs = list(pool.map(lambda _: tp.run_prediction_study(example).frf, range(3)))
    assert all(np.array_equal(r, prediction.frf) for r in runs)
    again = tp.run_overhang_study(example, f, sh11, overhangs_m=[0.045, 0.05, 0.055, 0.06], threads=1)
    assert all(np.array_equal(a.sht11, b.sht11) for a, b in zip(one.overhangs, again.overhangs))


def test_spinning_beam_is_the_cli_one_and_its_blocks_are_gyroscopic():
    """beam --speed's whirl frequencies are run_beam_study's (the same doubles); spinning_receptance's
    x–y blocks are skew (H_yx = −H_xy, the gyroscopic coupling) and vanish at standstill, where x–x
    is exact_receptance (docs/reference.md §10)."""
    j = run_cli_json("beam", "--length", "0.15", "--diameter", "0.04", "--modes", "3", "--speed", "30000")
    r = tp.run_beam_study(length=0.15, outer_diameter=0.04, modes=3, speed_rpm=30000.0, campbell_rpm=[0.0, 30000.0])
    assert r.whirl["forward_hz"] == j["whirl"]["forward_hz"]
    assert r.whirl["backward_hz"] == j["whirl"]["backward_hz"]
    assert all(f > b for f, b in zip(r.whirl["forward_hz"], r.whirl["backward_hz"]))
    assert len(r.campbell) == 2 and r.campbell[1]["forward_hz"] == r.whirl["forward_hz"]
    seg = r.segment
    f = np.array([500.0, 3000.0])
    b = tp.spinning_receptance(seg, f, 30000.0)
    assert b.shape == (2, 8, 8) and b.dtype == np.complex128
    assert np.abs(b[:, 0, 2]).min() > 0.0
    assert np.allclose(b[:, 2, 0], -b[:, 0, 2], rtol=1e-12, atol=0.0)
    still = tp.spinning_receptance(seg, f, 0.0)
    assert np.all(still[:, 0, 2] == 0.0)
    t = tp.exact_receptance(seg, f)
    assert np.array_equal(still[:, 0:2, 0:2], t[:, 0:2, 0:2])
    w = tp.whirl_frequencies(seg, 30000.0, 3)
    assert w["forward_hz"] == r.whirl["forward_hz"]


def test_prediction_at_speed_has_the_skew_cross_receptance():
    """run_prediction_study(speed_rpm=): the two-plane block's cross
    terms are skew (isotropic bearings: H_yx = −H_xy) and its x–x block is the FRF."""
    a = tp.load_assembly(str(EXAMPLE)).assembly
    a.grid = (200.0, 3000.0, 20.0)
    p = tp.run_prediction_study(a, speed_rpm=20000.0)
    assert p.two_plane.shape == (p.frf.shape[0], 4, 4)
    assert np.array_equal(p.two_plane[:, 0:2, 0:2], p.frf)
    assert np.allclose(p.two_plane[:, 2, 0], -p.two_plane[:, 0, 2], rtol=1e-12, atol=0.0)
    assert np.abs(p.two_plane[:, 0, 2]).max() > 0.0
    still = tp.run_prediction_study(a)
    assert still.two_plane.shape[0] == 0


def test_lobes_at_speed_follow_the_bearing_table():
    """run_lobes_study with an assembly whose bearings carry speed tables: the lobes use the x–y FRF
    at each speed (speed_model 'spinning', automatically), say so, and state the interpolation error;
    'standstill' keeps the single-plane FRF; a speed beyond the table is refused naming it."""
    a = tp.load_assembly(str(EXAMPLE)).assembly
    a.grid = (200.0, 3000.0, 10.0)
    sp = a.spindle
    bearings = sp.bearings
    for b in bearings:
        b.speed_table = [(0.0, b.stiffness, b.damping), (30000.0, 0.7 * b.stiffness, b.damping)]
    sp.bearings = bearings
    a.spindle = sp
    cut = tp.CuttingConditions(4, 6e8, 0.3, immersion=0.5, milling="down")
    r = tp.run_lobes_study(cut, (5000.0, 30000.0, 50), assembly=a, speed_nodes=5)
    assert r.speed_model == "spinning"
    assert len(r.frf_speeds_rpm) == 9
    assert 0.0 <= r.envelope_interpolation_error < 1.0
    assert any("at each spindle speed" in w for w in r.warnings)
    d = r.to_dict()
    assert d["speed_model"] == "spinning" and len(d["frf_speeds_rpm"]) == 9
    still = tp.run_lobes_study(cut, (5000.0, 30000.0, 50), assembly=a, speed_model="standstill")
    assert still.speed_model == "standstill" and len(still.frf_speeds_rpm) == 0
    assert not np.allclose(still.envelope["depth_m"], r.envelope["depth_m"])
    with pytest.raises(tp.InvalidArgument, match="speed_table"):
        tp.run_lobes_study(cut, (5000.0, 35000.0, 50), assembly=a)


def test_time_domain_lobes_at_speed():
    """run_lobes_study(method='fd') with the spindle spinning: a modal model with x–y pole-residue terms
    fitted at each speed, its residuals stated (result and to_dict), and the boundary within 3 % of the
    zero-order lobes of the same FRFs in a 4-tooth slot (tests/lobes_at_speed_test.cpp: 1.5 % seen)."""
    a = tp.load_assembly(str(EXAMPLE)).assembly
    a.grid = (200.0, 5000.0, 4.0)
    cut = tp.CuttingConditions(4, 6e8, 0.3, immersion=1.0, milling="down")
    speeds = (40000.0, 44000.0, 3)
    fd = tp.run_lobes_study(cut, speeds, method="fd", assembly=a, speed_model="spinning", speed_nodes=3)
    zoa = tp.run_lobes_study(cut, speeds, assembly=a, speed_model="spinning", speed_nodes=3)
    assert fd.speed_model == "spinning" and fd.method == "fd"
    assert 0.0 < fd.block_fit_residual < 0.03 and 0.0 < fd.fit_residual < 0.1
    d = fd.to_dict()
    assert d["block_fit_residual"] == pytest.approx(fd.block_fit_residual)
    assert np.allclose(fd.envelope["depth_m"], zoa.envelope["depth_m"], rtol=0.03, atol=0.0)
