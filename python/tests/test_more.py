"""The remaining bindings: peaks and mode tracking, noise models, sampling and quantiles, stability
with the joint uncertain, best speeds — against numpy, closed forms and the studies that use them."""
import numpy as np
import pytest

import toolpoint as tp
from conftest import EXAMPLE, run_cli_json


def test_find_peaks_and_track_modes(example, prediction):
    f, H = prediction.frequency_hz, prediction.frf[:, 0, 0]
    peaks = tp.find_peaks(f, H)
    # The grid peaks (parabola in log|H|) lie within a grid step of the model-refined modes.
    assert len(peaks) == len(prediction.modes)
    for p, m in zip(peaks, prediction.modes):
        assert abs(p.frequency_hz - m.frequency_hz) < 1.0 and p.index == m.index
    study = tp.run_overhang_study(example, f, tp.AssemblyModel(example).holder_tip(f), overhangs_m=[0.045, 0.049, 0.053])
    family = [r.modes for r in study.overhangs]
    assert np.array_equal(tp.track_modes(family, study.reference), study.tracked_modes_hz, equal_nan=True)


def test_noise_models(prediction):
    f, blocks = prediction.frequency_hz, prediction.frf
    stated = tp.stated_block_noise(f, blocks, magnitude_sigma=0.05)
    assert stated.relative.shape == (len(f), 8, 8) and stated.magnitude_sigma.tolist() == [0.05] * 4
    noisy = tp.draw_block_noise(f, blocks, stated, seed=4)
    rel = (noisy / blocks - 1).reshape(len(f), 4)
    # Radial only (the seed's multiplicative noise): real relative errors of σ 5 %, within 3 % of it.
    assert np.max(np.abs(rel.imag)) < 1e-12 and abs(np.std(rel.real) / 0.05 - 1) < 0.03
    est = tp.estimate_block_noise(f, noisy)
    # Estimated from the data: within 10 % of the 5 % put in, radial; the phase noise small.
    assert np.all(np.abs(est.magnitude_sigma / 0.05 - 1) < 0.1)
    assert est.to_dict()["source"].startswith("estimated")


def test_sampling_and_quantiles():
    v = np.random.default_rng(1).normal(size=101)
    for p in (0.05, 0.5, 0.95):  # type 7 is numpy's default
        assert tp.quantile(v.tolist(), p) == pytest.approx(np.quantile(v, p), rel=1e-14)
    mean = tp.seed_table1_joint()
    assert all(s == mean for s in tp.sample_joints(mean, np.zeros((8, 8)), 5, seed=1))
    cov = np.diag((0.01 * np.abs(mean.to_array())) ** 2)
    draws = np.array([s.to_array() for s in tp.sample_joints(mean, cov, 400, seed=2)])
    assert np.all(np.abs(draws.mean(axis=0) / mean.to_array() - 1) < 0.01 * 4 / np.sqrt(400) * 1.5)


def test_stability_uncertainty_without_uncertainty_is_the_nominal_lobes(example):
    jf = tp.JointFile("holder_tool", example.holder_tool, tp.JointUncertainty())  # zero covariance
    f = np.arange(500.0, 5000.0, 1.0)
    cut = tp.CuttingConditions(4, 6e8, 0.3, immersion=0.5, milling="down")
    depths = np.linspace(0.0, 5e-3, 11)
    s = tp.stability_uncertainty(example, jf, f, cut, (2000.0, 20000.0, 200), depths, samples=10, threads=1)
    H = tp.AssemblyModel(example).tool_point(f)[:, 0, 0]
    nominal = tp.run_lobes_study(cut, (2000.0, 20000.0, 200), frequency_hz=f, xx=H).envelope["depth_m"]
    assert np.array_equal(s.nominal_depth_m, nominal)
    assert all(np.array_equal(q, nominal) for q in s.depth_m)  # every sample is the nominal joint
    assert np.array_equal(s.probability, (nominal[:, None] > depths[None, :]).astype(float))


def test_stability_uncertainty_is_the_cli_one(tmp_path, example):
    f = example.frequency_hz
    sh = tp.add_measurement_noise(f, tp.AssemblyModel(example).holder_tip(f), sigma=0.02, seed=1)
    sht = tp.add_measurement_noise(f, tp.AssemblyModel(example).tool_point(f), sigma=0.02, seed=2)
    jf = tp.run_identification_study(example, [tp.IdentificationData(f, sht, B11=sh)], uncertainty="linearised").joint_file()
    tp.write_joint_file(str(tmp_path / "kht.toml"), jf)
    jf = tp.load_joint_file(str(tmp_path / "kht.toml"))
    cli = run_cli_json("lobes", "--assembly", EXAMPLE, "--joint", f"holder-tool={tmp_path / 'kht.toml'}", "--samples", 20, "--teeth", 4,
                       "--kt", 6e8, "--kr", 0.3, "--immersion", 0.5, "--milling", "down", "--rpm", "2000:20000", "--speeds", 300)
    a = example.with_joint(jf)
    cut = tp.CuttingConditions(4, 6e8, 0.3, immersion=0.5, milling="down")
    nominal = tp.run_lobes_study(cut, (2000.0, 20000.0, 300), frequency_hz=f, xx=tp.milling_frfs(tp.AssemblyModel(a), f))
    top = max(d for d in nominal.envelope["depth_m"] if np.isfinite(d))
    depths = [1.5 * top * j / 200 for j in range(201)]  # the CLI's grid (cmd_lobes.cpp)
    s = tp.stability_uncertainty(a, jf, f, cut, (2000.0, 20000.0, 300), depths, samples=20)
    assert s.to_dict() == cli["uncertainty"]
    assert cli["uncertain_joint"] == str(tmp_path / "kht.toml")
    # The study with the joint uncertain is the same numbers (and the CLI is it).
    study = tp.run_lobes_study(cut, (2000.0, 20000.0, 300), frequency_hz=f, xx=tp.milling_frfs(tp.AssemblyModel(a), f),
                               assembly=a, joint=jf, samples=20)
    assert study.uncertainty.to_dict() == cli["uncertainty"]
    assert s.probability.shape == (300, 201) and s.depth_m.shape == (3, 300)


def test_best_speeds_of_an_envelope(example, model):
    f = example.frequency_hz
    cut = tp.CuttingConditions(4, 6e8, 0.3, immersion=0.5, milling="down")
    study = tp.run_lobes_study(cut, (2000.0, 20000.0, 0), frequency_hz=f, xx=model.tool_point(f)[:, 0, 0])
    again = tp.stability_pockets(study.envelope, 5, 0.02)
    for key in ("speed_rpm", "depth_m", "lobe"):
        assert np.array_equal(again[key], study.pockets[key])


def test_results_have_a_short_repr(example):
    # Every result type with to_dict() gets a one-line summary built from it (its scalars first).
    p = tp.run_prediction_study(example)
    r = repr(p)
    assert r.startswith(type(p).__name__ + "(") and len(r) < 600 and "\n" not in r
    study = tp.run_precision_study(example, tool_spacing_m=0.015, holder_spacing_m=0.02, sigma=0.005)
    r = repr(study)
    assert r.startswith("PrecisionStudy(") and "route='Eq. (6)'" in r and "confidence=0.95" in r
    typed = [getattr(tp, n) for n in dir(tp) if isinstance(getattr(tp, n), type) and hasattr(getattr(tp, n), "to_dict")]
    assert typed and all("__repr__" in t.__dict__ for t in typed)
