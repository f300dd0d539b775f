"""Stability: zero-order lobes and the time-domain boundary against `toolpoint lobes` (the same
doubles), the published 1-DOF floor, shapes; and the GIL released during a long computation."""
import threading
import time

import numpy as np
import pytest

import toolpoint as tp
from conftest import EXAMPLE, read_csv, run_cli, run_cli_json

# Insperger & Stépán's 1-DOF benchmark (docs/reference.md §7).
BENCH = tp.Mode(0.03993, 0.011, 922.0)


def test_zero_order_lobes_are_the_cli_ones(tmp_path, model, example):
    f = example.frequency_hz
    H = tp.milling_frfs(model, f)
    assert np.array_equal(H, model.tool_point(f)[:, 0, 0])
    cut = tp.CuttingConditions(4, 6e8, 0.3, immersion=0.5, milling="down")
    r = tp.zero_order_lobes(f, H, cut, speeds=(2000.0, 20000.0, 2000))
    run_cli("lobes", "--assembly", EXAMPLE, "--teeth", 4, "--kt", 6e8, "--kr", 0.3, "--immersion", 0.5, "--milling", "down",
            "--rpm", "2000:20000", "--output", tmp_path / "lobes.csv", "--envelope", tmp_path / "env.csv")
    lobes = read_csv(tmp_path / "lobes.csv")  # lobe, speed rpm, depth mm, chatter Hz, root
    p = r.points
    assert np.array_equal(lobes[:, 0], p["lobe"]) and np.array_equal(lobes[:, 1], p["speed_rpm"])
    assert np.array_equal(lobes[:, 2], p["depth_m"] * 1e3) and np.array_equal(lobes[:, 3], p["chatter_hz"])
    env = read_csv(tmp_path / "env.csv")
    finite = np.isfinite(r.envelope["depth_m"])
    assert np.array_equal(env[:, 1], r.envelope["depth_m"][finite] * 1e3)
    study = tp.run_lobes_study(cut, (2000.0, 20000.0, 0), frequency_hz=f, xx=H)
    cli = run_cli_json("lobes", "--assembly", EXAMPLE, "--teeth", 4, "--kt", 6e8, "--kr", 0.3, "--immersion", 0.5, "--milling",
                       "down", "--rpm", "2000:20000")
    d = study.to_dict()
    for key in ("pockets", "zero_order", "cutting", "speeds", "method"):
        assert d[key] == cli[key], key
    assert d["zero_order"] == study.zero_order.to_dict() and cli["zero_order"]["floor_depth_m"] == r.floor_depth_m
    assert study.zero_order.floor_depth_m == r.floor_depth_m


def test_the_published_one_dof_slot_floor():
    # docs/reference.md §7: 0.298054 mm (six digits). A 0.045 Hz grid resolves the resonance (ζf = 10 Hz).
    f = np.linspace(300.0, 3000.0, 60001)
    G = tp.modal_frf([BENCH], f)
    slot = tp.CuttingConditions(2, 6e8, 2e8 / 6e8, immersion=1.0, milling="down")
    r = tp.zero_order_lobes(f, G, slot, speeds=(5000.0, 25000.0, 100), rigid_y=True)
    assert abs(r.floor_depth_m * 1e3 - 0.298054) < 1e-6


def test_time_domain_boundary_is_the_cli_one():
    cut = tp.CuttingConditions(2, 6e8, 2e8 / 6e8, immersion=0.05, milling="down")
    study = tp.run_lobes_study(cut, (5000.0, 25000.0, 0), method="fd", x_modes=[BENCH], rigid_y=True, threads=2)
    cli = run_cli_json("lobes", "--method", "fd", "--mode-x", "0.03993,0.011,922", "--rigid-y", "--teeth", 2, "--kt", 6e8,
                       "--kn", 2e8, "--immersion", 0.05, "--milling", "down", "--rpm", "5000:25000", "--threads", 1)
    d = study.to_dict()
    for key in ("pockets", "boundary", "modes", "fits", "cutting"):
        assert d[key] == cli[key], key  # identical for any thread count (2 here, 1 in the CLI)
    assert d["boundary"] == study.boundary.to_dict()
    assert d["boundary"]["worst_relative_error"] == study.boundary.worst_relative_error()
    b = study.boundary.boundary
    assert b["depth_m"].shape == (200,) and b["kind"][0] in ("hopf", "flip", "fold", "none")
    assert np.all(b["depth_error_m"] <= 0.01 * b["depth_m"] + 1e-15)
    direct = tp.stability_boundary([BENCH], [], cut, (5000.0, 25000.0, 200), threads=1)
    assert np.array_equal(direct.boundary["depth_m"], b["depth_m"])
    # The boundary is where ρ crosses 1: just below stable, just above unstable (at the finer level's steps).
    i = 57
    fd = tp.FullDiscretization([BENCH], [], cut, steps=int(b["steps"][i]))
    n, a, e = b["speed_rpm"][i], b["depth_m"][i], b["depth_error_m"][i]
    assert fd.spectral_radius(n, a - 3 * e - 1e-4 * a) < 1 < fd.spectral_radius(n, a + 3 * e + 1e-4 * a)


def test_semi_discretization_is_the_cli_one_and_agrees_with_fd():
    """`lobes --method sd` (issue 27) from Python: the CLI's doubles, and the fd boundary within 1 %
    (both converged to a 0.2 % error target; measured under 0.05 %, tests/semi_discretization_test.cpp)."""
    cut = tp.CuttingConditions(4, 6e8, 2e8 / 6e8, immersion=0.5, milling="down")
    study = tp.run_lobes_study(cut, (5000.0, 8000.0, 7), method="sd", x_modes=[BENCH], rigid_y=True, threads=1)
    cli = run_cli_json("lobes", "--method", "sd", "--mode-x", "0.03993,0.011,922", "--rigid-y", "--teeth", 4, "--kt", 6e8,
                       "--kn", 2e8, "--immersion", 0.5, "--milling", "down", "--rpm", "5000:8000", "--speeds", 7)
    assert study.method == "sd" and study.boundary.scheme == "sd"
    assert study.to_dict()["boundary"] == cli["boundary"]
    sd = tp.stability_boundary([BENCH], [], cut, (5000.0, 8000.0, 7), tolerance=0.002, degree=1, scheme="sd")
    fd = tp.stability_boundary([BENCH], [], cut, (5000.0, 8000.0, 7), tolerance=0.002)
    assert sd.scheme == "sd" and fd.scheme == "fd"
    assert np.allclose(sd.boundary["depth_m"], fd.boundary["depth_m"], rtol=0.01)
    with pytest.raises(tp.InvalidArgument, match="degree"):
        tp.stability_boundary([BENCH], [], cut, (5000.0, 8000.0, 7), degree=2, scheme="sd")


def test_modal_fit_is_the_cli_one(tmp_path, prediction):
    tp.write_frf_file(str(tmp_path / "h.csv"), prediction.frequency_hz, prediction.frf[:, 0, 0])
    cli = run_cli_json("modes", tmp_path / "h.csv")
    r = tp.fit_modes(prediction.frequency_hz, prediction.frf[:, 0, 0])
    assert [(m.frequency_hz, m.damping_ratio, m.mass_kg) for m in r.modes] == [
        (m["mode"]["frequency_hz"], m["mode"]["damping_ratio"], m["mode"]["mass_kg"]) for m in cli["modes"]]
    assert r.lower_residual == cli["lower_residual"]
    assert r.to_dict() == {k: v for k, v in cli.items() if k not in ("units", "file")}  # what the CLI adds


def test_modal_fit_study_is_the_cli_one(tmp_path, prediction):
    """run_modal_fit_study gives what `toolpoint modes` prints (--json: the fit; text: the modes lobes
    accepts) and writes (the fitted receptance, shortest round-trip doubles: equal exactly)."""
    f, h = prediction.frequency_hz, prediction.frf[:, 0, 0]
    path = tmp_path / "h.csv"
    tp.write_frf_file(str(path), f, h)
    cli = run_cli_json("modes", path, "--band", "300:3000", "--output", tmp_path / "fit.csv")
    study = tp.run_modal_fit_study(f, h, options=tp.ModalFitOptions(band_hz=(300.0, 3000.0)), what=str(path))
    assert study.to_dict()["fit"] == {k: v for k, v in cli.items() if k not in ("units", "file", "output")}
    d = read_csv(tmp_path / "fit.csv")
    assert np.array_equal(study.frequency_hz, d[:, 0]) and np.array_equal(study.fitted, d[:, 1] + 1j * d[:, 2])
    text = run_cli("modes", path, "--band", "300:3000")
    line = next(x for x in text.splitlines() if x.startswith("for `toolpoint lobes --method fd`:"))
    assert line.split(":", 1)[1].split() == [
        w for m in study.model for w in ("--mode-x", f"{m.mass_kg:.6g},{m.damping_ratio:.6g},{m.frequency_hz:.6g}")]
    assert len(study.model) >= 1 and study.warnings == study.fit.warnings


def test_modal_fit_recovers_the_modes_it_is_given():
    f = np.linspace(500.0, 2000.0, 3001)
    modes = [tp.Mode(0.04, 0.011, 922.0), tp.Mode(0.08, 0.02, 1400.0)]
    r = tp.fit_modes(f, tp.modal_frf(modes, f), options=tp.ModalFitOptions(max_modes=2, residual_terms=False))
    for got, want in zip(r.modes, modes):  # exact data, exact model: to the solver's tolerance
        assert got.frequency_hz == pytest.approx(want.frequency_hz, rel=1e-6)
        assert got.damping_ratio == pytest.approx(want.damping_ratio, rel=1e-4)
        assert got.mass_kg == pytest.approx(want.mass_kg, rel=1e-4)


def test_the_gil_is_released_while_a_long_computation_runs():
    # A Python thread records timestamps while the period maps are computed on one thread. Were the
    # GIL held, it could not run at all during the call: no timestamp would fall inside it.
    cut = tp.CuttingConditions(2, 6e8, 2e8 / 6e8, immersion=0.05, milling="down")
    fd = tp.FullDiscretization([BENCH], [], cut, steps=40)
    speeds, depths = np.linspace(5000, 25000, 300), np.linspace(1e-4, 3e-3, 40)
    stamps, stop = [], threading.Event()

    def tick():
        while not stop.is_set():
            stamps.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=tick)
    t.start()
    time.sleep(0.01)
    start = time.perf_counter()
    rho = fd.spectral_radius_map(speeds, depths, threads=1)
    end = time.perf_counter()
    stop.set()
    t.join()
    inside = [s for s in stamps if start < s < end]
    assert rho.shape == (300, 40)
    assert end - start > 0.05, "the computation was too short to tell"
    assert len(inside) >= 10, f"{len(inside)} ticks in {end - start:.3f} s"
    middle = (start + end) / 2  # it kept running throughout: ticks in both halves of the call
    assert any(s < middle for s in inside) and any(s > middle for s in inside)


def test_bad_stability_input_raises():
    with pytest.raises(tp.InvalidArgument, match="milling"):
        tp.CuttingConditions(2, 6e8, 0.3, immersion=0.5, milling="climb")
    with pytest.raises(tp.InvalidArgument):
        tp.CuttingConditions(0, 6e8, 0.3, immersion=0.5)
    f = np.linspace(100.0, 200.0, 11)
    cut = tp.CuttingConditions(2, 6e8, 0.3, immersion=0.5)
    with pytest.raises(tp.InputError, match="xx"):
        tp.zero_order_lobes(f, np.ones(10, complex), cut, speeds=(1000.0, 2000.0, 10))
    with pytest.raises(tp.InvalidArgument, match="method"):
        tp.run_lobes_study(cut, (1000.0, 2000.0, 10), method="xd")


def test_variable_pitch_and_process_damping_are_the_cli_ones():
    """Variable pitch, runout and process damping (issue 27) reach the time-domain boundary from Python as
    from `toolpoint lobes --pitch/--runout/--process-damping` (degrees, mm in the CLI; SI here)."""
    deg = np.pi / 180.0
    cut = tp.CuttingConditions(4, 6e8, 1.0 / 3.0, immersion=0.5, milling="down",
                               pitch_rad=[70 * deg, 110 * deg, 70 * deg, 110 * deg], runout_m=[1e-5, 0.0, -1e-5, 0.0],
                               feed_per_tooth_m=5e-5, diameter_m=0.02, process_damping_n_per_m=1e5)
    assert len(cut.pitch_rad) == 4 and cut.process_damping_n_per_m == 1e5
    study = tp.run_lobes_study(cut, (4000.0, 8000.0, 8), method="fd", x_modes=[BENCH], rigid_y=True, threads=1)
    cli = run_cli_json("lobes", "--method", "fd", "--mode-x", "0.03993,0.011,922", "--rigid-y", "--teeth", 4, "--kt", 6e8,
                       "--kr", 1.0 / 3.0, "--immersion", 0.5, "--milling", "down", "--rpm", "4000:8000", "--speeds", 8,
                       "--pitch", "70,110,70,110", "--runout", "0.01,0,-0.01,0", "--feed", 0.05, "--diameter", 20,
                       "--process-damping", 1e5, "--threads", 1)
    assert study.to_dict()["boundary"] == cli["boundary"]
    with pytest.raises(tp.InvalidArgument, match="pitch_rad"):
        tp.CuttingConditions(4, 6e8, 0.3, immersion=0.5, pitch_rad=[1.0, 1.0, 1.0, 1.0])
    with pytest.raises(tp.InvalidArgument, match="process_damping_n_per_m"):
        tp.CuttingConditions(4, 6e8, 0.3, immersion=0.5, diameter_m=0.02, process_damping_n_per_m=2e11)


def test_helix_is_the_cli_one():
    """A variable helix (issue 27) reaches the time-domain boundary from Python as from `toolpoint lobes --helix`
    (degrees in the CLI, radians here), and the simulation takes the same cutting conditions' helix."""
    deg = np.pi / 180.0
    cut = tp.CuttingConditions(4, 1.5e8, 1.0 / 3.0, immersion=0.05, milling="down",
                               helix_rad=[30 * deg, 40 * deg, 30 * deg, 40 * deg], diameter_m=0.02)
    assert len(cut.helix_rad) == 4 and cut.helix_slices == 0
    study = tp.run_lobes_study(cut, (6000.0, 7000.0, 3), method="fd", x_modes=[BENCH], rigid_y=True, threads=1)
    cli = run_cli_json("lobes", "--method", "fd", "--mode-x", "0.03993,0.011,922", "--rigid-y", "--teeth", 4, "--kt", 1.5e8,
                       "--kr", 1.0 / 3.0, "--immersion", 0.05, "--milling", "down", "--rpm", "6000:7000", "--speeds", 3,
                       "--helix", "30,40,30,40", "--diameter", 20, "--threads", 1)
    assert study.to_dict()["boundary"] == cli["boundary"]
    with pytest.warns(Warning):  # few revolutions analysed
        sim = tp.simulate_milling(cut, 6000.0, 1e-3, 1e-4, 0.02, x_modes=[BENCH], rigid_y=True, revolutions=4, record=False)
    d = sim.to_dict()
    assert d["cutter"]["tooth_helix_rad"] == list(cut.helix_rad) and d["simulation"]["slices"] > 1
    with pytest.raises(tp.InvalidArgument, match="helix_rad"):
        tp.CuttingConditions(4, 6e8, 0.3, immersion=0.5, diameter_m=0.02, helix_rad=[-0.1])
    with pytest.raises(tp.InvalidArgument, match="2 angles for 4 teeth"):
        tp.CuttingConditions(4, 6e8, 0.3, immersion=0.5, diameter_m=0.02, helix_rad=[0.5, 0.6])
