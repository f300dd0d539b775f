"""Joint identification: the closed form against the joint put into the model, the study against
`toolpoint identify --json` (the same doubles), joint files, the band carried forward."""
import numpy as np
import pytest

import toolpoint as tp
from conftest import EXAMPLE, read_csv, run_cli, run_cli_json


@pytest.fixture(scope="module")
def measured(tmp_path_factory, example, model):
    """SH11 and SHT11 of the example with the seed's 5 % noise (seeds 1 and 2), as arrays and CSV files."""
    d = tmp_path_factory.mktemp("measured")
    f = example.frequency_hz
    sh = tp.add_measurement_noise(f, model.holder_tip(f), sigma=0.05, seed=1)
    sht = tp.add_measurement_noise(f, model.tool_point(f), sigma=0.05, seed=2)
    tp.write_frf_file(str(d / "sh11.csv"), f, sh)
    tp.write_frf_file(str(d / "sht11.csv"), f, sht)
    return f, sh, sht, d


def test_closed_form_returns_the_joint_put_in(example, model):
    # Noise-free model data: Eq. 6 gives back Table 1 at every frequency (README: within 1e-8 over the band).
    f = np.linspace(500.0, 5000.0, 91)
    s = tp.identify_series(f, model.tool(f), model.holder_tip(f), model.tool_point(f))
    ref = example.holder_tool.to_array()
    assert s.parameters.shape == (91, 8) and s.K.shape == (91, 2, 2) and s.noise_gain.shape == (91, 8)
    assert np.all(np.abs(s.parameters / ref - 1) < 1e-6)
    r = tp.band_readout(s, 2500.0, 2650.0)
    assert np.all(np.abs(r.median / ref - 1) < 1e-6) and r.medians() == tp.JointParameters.from_array(r.median)
    e = tp.effect_analysis(example, "holder_tool", example.frequency_hz)
    assert e.frequency_hz[e.dominant] == pytest.approx(2584.6, abs=0.1)  # the tool mode (README)


def test_identification_study_is_the_cli_one(measured, example):
    f, sh, sht, d = measured
    sh_path, sht_path = str(d / "sh11.csv"), str(d / "sht11.csv")
    for method in ("seed", "fit"):
        cli = run_cli_json("identify", "--assembly", EXAMPLE, "--sh", sh_path, "--sht", sht_path, "--method", method,
                           "--bootstrap", 20, "--threads", 2, "--accept")
        data = tp.IdentificationData(f, sht, B11=sh, g_name=sht_path, b_name=sh_path)
        ours = tp.run_identification_study(example, [data], method=method, bootstrap_samples=20, threads=1)
        j = ours.to_dict()
        for key in ("parameters", "verdict", "mode", "seed", "forward_checks", "g_noise", "b_noise", "warnings"):
            assert j[key] == cli[key], (method, key)
        if method == "fit":
            assert j["fit"] == cli["fit"]
            assert ours.fit.lower.shape == (8,) and ours.fit.covariance.shape == (8, 8)
            # The band fit holds Table 1 (the joint put in) within its intervals for the stiffnesses.
            ref = example.holder_tool.to_array()
            for k in (0, 2, 6):
                assert ours.fit.lower[k] <= ref[k] <= ours.fit.upper[k]
            assert ours.identified == ours.fit.parameters
        assert ours.verdict in ("pass", "doubtful", "fail")


def test_case_study_is_the_cli_demo(tmp_path, example):
    # to_dict is demo --json's JSON, less what the CLI adds about its run (options echoed, files).
    cli = run_cli_json("demo", "--assembly", EXAMPLE, "--no-plots", "--bootstrap", 0, "--output", tmp_path / "demo")
    cs = tp.run_case_study(example, uncertainty="linearised", threads=1)
    run = {"case_study", "assembly", "units", "frequency_range_hz", "points", "noise", "filter", "files", "figures"}
    assert cs.to_dict() == {k: v for k, v in cli.items() if k not in run}
    assert cs.to_dict()["fitted"] == cs.fitted.to_dict() and cs.to_dict()["seed"]["method"] == "seed"


def test_joint_file_round_trip_and_band(tmp_path, measured, example, prediction):
    f, sh, sht, _ = measured
    id_ = tp.run_identification_study(example, [tp.IdentificationData(f, sht, B11=sh)], uncertainty="linearised")
    jf = id_.joint_file(["sh11.csv", "sht11.csv"])
    tp.write_joint_file(str(tmp_path / "kht.toml"), jf)
    back = tp.load_joint_file(str(tmp_path / "kht.toml"))
    assert back.interface == "holder_tool" and back.parameters == jf.parameters  # shortest round-trip numbers
    assert np.array_equal(back.uncertainty.covariance, jf.uncertainty.covariance)
    # The joint file's constants in the example reproduce a prediction with those constants.
    with_file = example.with_joint(back)
    assert with_file.holder_tool == back.parameters
    band = tp.tool_point_band(example.with_joint(back), back, f[::50], samples=20, threads=1)
    assert band.magnitude.shape == (3, len(f[::50])) and band.nominal.shape == (len(f[::50]),)
    assert np.all(band.magnitude[0] <= band.magnitude[2])
    assert np.array_equal(band.nominal, tp.AssemblyModel(with_file).tool_point(f[::50])[:, 0, 0])
    # The band against predict --samples (the same samples and quantiles: identical doubles).
    run_cli("predict", EXAMPLE, "--joint", f"holder-tool={tmp_path / 'kht.toml'}", "--samples", 20, "--band-output", tmp_path / "band.csv")
    full = tp.tool_point_band(with_file, back, f, samples=20, seed=1)
    cli = read_csv(tmp_path / "band.csv")  # frequency, |H| q5, q50, q95 [m/N], phase q5, q50, q95 [deg]
    assert np.array_equal(cli[:, 0], full.frequency_hz) and np.array_equal(cli[:, 1:4].T, full.magnitude)
    # The prediction study with the joint carries the same band (predict --samples is that one call).
    p = tp.run_prediction_study(with_file, joint=back, samples=20, seed=1)
    assert np.array_equal(p.band.magnitude, full.magnitude) and np.array_equal(p.band.phase_rad, full.phase_rad)
    assert tp.run_prediction_study(with_file).band is None


def test_bad_identification_input_raises():
    a = tp.load_assembly(str(EXAMPLE)).assembly
    f = np.linspace(10.0, 100.0, 10)
    with pytest.raises(tp.InputError, match=r"\(n, 2, 2\)"):
        tp.IdentificationData(f, np.zeros((10, 2)))
    with pytest.raises(tp.InvalidArgument, match="route"):
        tp.run_identification_study(a, [tp.IdentificationData(f, np.ones((10, 2, 2)))], route="tool_holder")
    with pytest.raises(tp.InputError):  # no SH11 for Eq. 6
        tp.run_identification_study(a, [tp.IdentificationData(f, np.ones((10, 2, 2)))])


def test_precision_study_is_the_cli_one(example):
    cli = run_cli_json("precision", EXAMPLE, "--tool-spacing", 0.015, "--holder-spacing", 0.02, "--sigma", 0.005,
                       "--averages", 5, "--calibration", "1%", "--target", "2%")
    ours = tp.run_precision_study(example, tool_spacing_m=0.015, holder_spacing_m=0.02, sigma=0.005, averages=5,
                                  calibration=0.01, target=0.02)
    j = ours.to_dict()
    assert j == {k: v for k, v in cli.items() if k != "joint"}
    assert ours.half_width.shape == (8,) and ours.route == "holder_tool"
    assert np.allclose(ours.relative, ours.half_width / np.abs(ours.values))
    with pytest.raises(tp.InvalidArgument, match="spacing"):
        tp.run_precision_study(example, holder_spacing_m=0.02)
