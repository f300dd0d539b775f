"""Bound *Options types: keyword-only constructors whose defaults are the C++ ones (the header's
values, include/toolpoint/stability/modal_fit.hpp and peaks.hpp, written out here as the independent
reference), check() raising the library's InvalidArgument naming the field, a repr that rebuilds
the object, and the functions taking them (also as one options object beside their keyword form)."""
import numpy as np
import pytest

import toolpoint as tp
from conftest import EXAMPLE, read_csv, run_cli, run_cli_json


def test_defaults_are_the_headers():
    assert tp.ModalFitOptions() == tp.ModalFitOptions(
        max_modes=3, band_hz=None, min_prominence_db=3.0, residual_terms=True, max_evaluations=2000)
    assert tp.PeakOptions().min_prominence == 0.02


def test_keyword_only_and_known_fields_only():
    with pytest.raises(TypeError):
        tp.ModalFitOptions(2)  # positional: which field would it be?
    with pytest.raises(TypeError, match="max_mode.*its fields: max_modes"):
        tp.ModalFitOptions(max_mode=2)  # a misspelt field is not silently ignored


def test_check_names_the_field():
    o = tp.ModalFitOptions(max_modes=0)  # built as given; check() (and every function taking it) refuses
    with pytest.raises(tp.InvalidArgument, match=r"ModalFitOptions::max_modes 0 must lie in 1…20"):
        o.check()
    with pytest.raises(tp.InvalidArgument, match=r"ModalFitOptions::band_hz"):
        tp.fit_modes(np.linspace(10, 100, 50), np.ones(50, complex) * 1e-6, options=tp.ModalFitOptions(band_hz=(90.0, 20.0)))


def test_repr_reads_back():
    o = tp.ModalFitOptions(max_modes=2, band_hz=(300.0, 3000.0))
    assert repr(o) == ("ModalFitOptions(max_modes=2, band_hz=(300.0, 3000.0), min_prominence_db=3.0, "
                       "residual_terms=True, max_evaluations=2000)")
    assert eval(repr(o), {"ModalFitOptions": tp.ModalFitOptions}) == o


def test_functions_use_the_options():
    # Two well-separated modes: max_modes=1 keeps one of them (the fit sees at most that many).
    f = np.linspace(100.0, 3000.0, 600)
    h = tp.modal_frf([tp.Mode(0.05, 0.02, 800.0), tp.Mode(0.08, 0.03, 2000.0)], f)
    assert len(tp.fit_modes(f, h).modes) == 2
    assert len(tp.fit_modes(f, h, options=tp.ModalFitOptions(max_modes=1)).modes) == 1
    assert len(tp.find_peaks(f, h)) == 2
    assert len(tp.find_peaks(f, h, options=tp.PeakOptions(min_prominence=0.999))) == 0


def test_rotational_options_enumeration_and_default():
    o = tp.RotationalOptions(spacing=0.015)
    assert (o.order, o.symmetrise, o.p_method, o.shear_stiffness, o.assume_reciprocity) == (2, False, "auto", None, False)
    with pytest.raises(tp.InvalidArgument, match=r"RotationalOptions::p_method 'schmitz' is not one of"):
        tp.RotationalOptions(spacing=0.015, p_method="schmitz")
    with pytest.raises(tp.InvalidArgument, match=r"spacing"):
        tp.RotationalOptions().check()  # spacing has no default: 0 is refused


# ---- The studies' options (issue 26): PredictOptions, OverhangStudyOptions, TapTestOptions,
# UncertaintyOptions. Defaults against the headers (studies/predict.hpp, overhang.hpp, tap_test.hpp,
# uncertainty/uncertainty.hpp) written out here; each options form against the keyword form it sits
# beside, and the tap test's new fields (floor, averages, calibration) against the CLI's UFF file.

def test_study_defaults_are_the_headers():
    assert tp.UncertaintyOptions() == tp.UncertaintyOptions(samples=200, seed=1, levels=[0.05, 0.5, 0.95], threads=0)
    p = tp.PredictOptions()
    assert (p.receptance, p.peaks.min_prominence, p.uncertain_joint, p.speed_rpm, p.extrapolate_bearings) == (
        "SHT11", 0.02, None, 0.0, False)
    assert p.band == tp.UncertaintyOptions()
    o = tp.OverhangStudyOptions()
    # The overhang study's own peak default (10 %: a measured SH11's noise makes no modes), not PeakOptions'.
    assert (o.overhangs_m, o.peaks.min_prominence, o.tracking_tolerance, o.threads, o.sh11_name) == ([], 0.1, 0.15, 0, "SH11")
    assert tp.TapTestOptions() == tp.TapTestOptions(side="tool", spacing_m=0.0, points=3, hammer="roving", sigma=0.0, seed=1,
                                                    floor=0.0, averages=0, calibration=0.0)


def test_study_options_name_a_wrong_field_and_value():
    with pytest.raises(TypeError, match="spacing.*its fields: side, spacing_m"):
        tp.TapTestOptions(spacing=0.015)
    with pytest.raises(TypeError, match="min_prominence.*its fields: receptance, peaks"):
        tp.PredictOptions(min_prominence=0.1)  # a nested field is set through its struct: peaks=PeakOptions(...)
    with pytest.raises(tp.InvalidArgument, match=r"TapTestOptions::hammer 'hammer' is not one of 'roving', 'tip'"):
        tp.TapTestOptions(hammer="hammer")
    with pytest.raises(tp.InvalidArgument, match=r"PredictOptions::receptance 'SHT12' is not one of"):
        tp.PredictOptions(receptance="SHT12")
    with pytest.raises(tp.InvalidArgument, match=r"TapTestOptions::spacing_m"):
        tp.TapTestOptions().check()  # the spacing has no default
    with pytest.raises(tp.InvalidArgument, match=r"UncertaintyOptions::samples 5\b"):
        tp.UncertaintyOptions(samples=5).check()
    with pytest.raises(tp.InvalidArgument, match=r"TapTestOptions::points"):
        tp.run_tap_test_study(tp.load_assembly(str(EXAMPLE)).assembly, tp.TapTestOptions(spacing_m=0.015, points=4))


def test_study_options_repr_reads_back():
    names = {n: getattr(tp, n) for n in ("PredictOptions", "PeakOptions", "UncertaintyOptions", "OverhangStudyOptions",
                                          "TapTestOptions")}
    p = tp.PredictOptions(receptance="SH11", peaks=tp.PeakOptions(min_prominence=0.05),
                          band=tp.UncertaintyOptions(samples=50, levels=[0.1, 0.9]), speed_rpm=12000.0)
    assert repr(p) == ("PredictOptions(receptance='SH11', peaks=PeakOptions(min_prominence=0.05), uncertain_joint=None, "
                       "band=UncertaintyOptions(samples=50, seed=1, levels=[0.1, 0.9], threads=0), speed_rpm=12000.0, "
                       "extrapolate_bearings=False)")
    for o in (p, tp.OverhangStudyOptions(overhangs_m=[0.05, 0.06], threads=1, sh11_name="sh.csv"),
              tp.TapTestOptions(side="holder", spacing_m=0.02, hammer="tip", sigma=0.01, averages=4)):
        back = eval(repr(o), names)
        assert back == o and back is not o
    o = tp.OverhangStudyOptions()
    o.peaks.min_prominence = 0.3  # a nested struct is the options' own, not a copy
    assert o.peaks.min_prominence == 0.3 and tp.OverhangStudyOptions().peaks.min_prominence == 0.1


def test_study_options_forms_are_the_keyword_forms(example, prediction):
    # Identical doubles: both forms must fill the same C++ options.
    p = tp.run_prediction_study(example, tp.PredictOptions(receptance="SH11", peaks=tp.PeakOptions(min_prominence=0.05)))
    q = tp.run_prediction_study(example, receptance="SH11", min_prominence=0.05)
    assert p.receptance == "SH11" and np.array_equal(p.frf, q.frf) and p.to_dict() == q.to_dict()
    assert np.array_equal(tp.run_prediction_study(example, options=tp.PredictOptions()).frf, prediction.frf)
    t = tp.run_tap_test_study(example, tp.TapTestOptions(spacing_m=0.015, sigma=0.005, seed=11))
    k = tp.run_tap_test_study(example, spacing_m=0.015, sigma=0.005, seed=11)
    assert all(np.array_equal(a.values, b.values) for a, b in zip(t.frfs, k.frfs)) and len(t.frfs) == 9
    f = example.frequency_hz[::20]
    sh11 = tp.AssemblyModel(example).holder_tip(f)
    s = tp.run_overhang_study(example, f, sh11, tp.OverhangStudyOptions(overhangs_m=[0.05, 0.06], threads=1))
    r = tp.run_overhang_study(example, f, sh11, overhangs_m=[0.05, 0.06], threads=1)
    assert np.array_equal(s.overhangs[1].sht11, r.overhangs[1].sht11) and s.to_dict() == r.to_dict()
    jf = tp.JointFile("holder_tool", example.holder_tool, tp.JointUncertainty())  # zero covariance: every sample the nominal
    b = tp.tool_point_band(example, jf, f, tp.UncertaintyOptions(samples=10, levels=[0.5], threads=1))
    c = tp.tool_point_band(example, jf, f, samples=10, levels=[0.5], threads=1)
    assert np.array_equal(b.magnitude, c.magnitude) and b.samples == 10 and b.magnitude.shape == (1, len(f))


def test_tap_test_options_reach_what_the_keywords_do_not(tmp_path, example):
    # floor, averages and calibration exist only in TapTestOptions: the same test as the CLI's
    # (the same library call; binary 58b keeps the doubles exactly).
    o = tp.TapTestOptions(spacing_m=0.015, sigma=0.01, seed=5, floor=0.002, averages=4, calibration=0.02)
    t = tp.run_tap_test_study(example, o)
    run_cli("taptest", EXAMPLE, "--at", "tool", "--spacing", 0.015, "--sigma", 0.01, "--seed", 5, "--floor", 0.002,
            "--averages", 4, "--calibration", 0.02, "--binary", "--output", tmp_path / "tap.uff")
    frfs = [d for d in tp.read_uff(str(tmp_path / "tap.uff")).functions if d.function_type == 4]  # 6: their coherences
    assert len(frfs) == len(t.frfs) == 9
    for d in frfs:
        assert np.array_equal(d.y, t.frf(d.response_node - 1, d.reference_node - 1))
    plain = tp.run_tap_test_study(example, spacing_m=0.015, sigma=0.01, seed=5)
    assert not np.array_equal(plain.frfs[0].values, t.frfs[0].values)  # the extra noise is there


# ---- The rest of the options (issue 26): SavgolOptions, NoiseEstimateOptions, FrfReadOptions,
# FrfWriteOptions, ModalOptions, BeamStudyOptions, TapNoise, PrecisionOptions, JointFitOptions,
# ReadoutOptions, ForwardCheckOptions, VerdictOptions, NoiseSpec, IdentificationOptions,
# CaseStudyOptions. Defaults against the headers (measured/signal.hpp, noise.hpp, io/frf_file.hpp,
# model/beam.hpp, studies/beam.hpp, precision.hpp, identify/joint_fit.hpp, identify.hpp,
# forward_check.hpp, studies/identification.hpp, case_study.hpp) written out here; each options form
# against the keyword form beside it (the same C++ options, so identical doubles); the plausibility
# checks against the CLI's (the same plausibility.hpp range and field named).

OPTION_NAMES = ("SavgolOptions", "NoiseEstimateOptions", "FrfReadOptions", "FrfWriteOptions", "ModalOptions",
                "BeamStudyOptions", "Material", "TapNoise", "TapTestOptions", "PrecisionOptions", "JointFitOptions",
                "ReadoutOptions", "ForwardCheckOptions", "VerdictOptions", "NoiseSpec", "IdentificationOptions",
                "CaseStudyOptions")


def test_more_defaults_are_the_headers():
    assert tp.SavgolOptions() == tp.SavgolOptions(window=5, order=2)
    assert tp.NoiseEstimateOptions() == tp.NoiseEstimateOptions(local=tp.SavgolOptions(window=7, order=3), window=201,
                                                                floor=True)
    assert tp.FrfReadOptions() == tp.FrfReadOptions(format="auto", dataset=None, response_node=None, response_direction=None,
                                                    reference_node=None, reference_direction=None, ordinate=None,
                                                    units=None, value_format=None, columns=[])
    assert tp.FrfWriteOptions() == tp.FrfWriteOptions(
        format="auto", description="", comments=[], coherence=[],
        dof={"response_node": 0, "response_direction": 0, "reference_node": 0, "reference_direction": 0})
    b = tp.BeamStudyOptions()
    assert (b.length, b.outer_diameter, b.inner_diameter, b.shear_coefficient, b.shear_model, b.modes, b.frequency_hz,
            b.block, b.method, b.speed_rpm, b.campbell_rpm) == (0.0, 0.0, 0.0, None, "hutchinson", 5, [], "11", "exact",
                                                                0.0, [])
    assert b.material == tp.Material("beam", 2.0e11, 0.3, 0.0, 7800.0, 0.0)
    assert b.modal == tp.ModalOptions(modes=100, static_residual=False)
    assert tp.TapNoise() == tp.TapNoise(sigma=0.01, floor=0.0, averages=1, calibration=0.0, shared_calibration=False)
    p = tp.PrecisionOptions()
    assert (p.route, p.tool.side, p.holder.side, p.reciprocal, p.confidence, p.target) == (
        "holder_tool", "tool", "holder", True, 0.95, None)
    assert tp.JointFitOptions() == tp.JointFitOptions(
        reciprocal=True, filter=None, uncertainty="bootstrap", bootstrap_samples=200, seed=1, shared_calibration=False,
        check_linearisation=True, confidence=0.95, max_iterations=200, threads=0)
    assert tp.ReadoutOptions() == tp.ReadoutOptions(cond_warning=1e6, reciprocity_warning=0.1, gain_warning=20.0)
    assert tp.ForwardCheckOptions() == tp.ForwardCheckOptions(
        smoothing=None, min_prominence=0.1, replicates=200, false_alarm=0.01, frequency_tolerance=0.01,
        peak_tolerance=0.15, seed=1, shared_calibration=False, threads=0)
    assert tp.VerdictOptions() == tp.VerdictOptions(forward=tp.ForwardCheckOptions(), residual_doubt=1.5,
                                                    residual_fail=3.0)
    assert tp.NoiseSpec() == tp.NoiseSpec(source="estimated", estimate=tp.NoiseEstimateOptions(), magnitude_sigma=0.0,
                                          phase_sigma_rad=0.0, floor=0.0, calibration=0.0, calibration_shared=False,
                                          averages=0)
    i = tp.IdentificationOptions()
    assert (i.route, i.method, i.band_hz, i.at_hz, i.width, i.filter) == ("holder_tool", "fit", None, None, 0.02, None)
    assert (i.noise, i.fit, i.readout, i.verdict) == (tp.NoiseSpec(), tp.JointFitOptions(), tp.ReadoutOptions(),
                                                      tp.VerdictOptions())
    assert tp.CaseStudyOptions() == tp.CaseStudyOptions(noise_sigma=0.05, seed=1, filter=tp.SavgolOptions(window=81, order=2),
                                                        apply_filter=True, band_width=0.02, fit=True,
                                                        fit_options=tp.JointFitOptions())


def test_more_options_name_a_wrong_field_and_value():
    with pytest.raises(TypeError, match="windw.*its fields: window, order"):
        tp.SavgolOptions(windw=7)
    with pytest.raises(TypeError):
        tp.SavgolOptions(7, 3)  # keyword-only
    # A name that is not one of the enumeration's (or not a unit): the library's message, naming the field.
    for cls, kwargs, message in (
            (tp.IdentificationOptions, {"route": "tool_holder"}, "IdentificationOptions::route 'tool_holder' is not one of"),
            (tp.JointFitOptions, {"uncertainty": "jackknife"}, "JointFitOptions::uncertainty 'jackknife' is not one of"),
            (tp.NoiseSpec, {"source": "guessed"}, "NoiseSpec::source 'guessed'"),
            (tp.FrfReadOptions, {"units": "furlongs"}, "FrfReadOptions::units 'furlongs' is not a unit"),
            (tp.FrfReadOptions, {"value_format": "mag-phase"}, "FrfCsvOptions::format 'mag-phase' is not one of"),
            (tp.BeamStudyOptions, {"block": "13"}, "BeamStudyOptions::block '13' is not one of")):
        with pytest.raises(tp.InvalidArgument, match=message):
            cls(**kwargs)
    # check(): the library's own messages, naming the field.
    taps = dict(tool=tp.TapTestOptions(spacing_m=0.015), holder=tp.TapTestOptions(side="holder", spacing_m=0.02))
    for o, field in (
            (tp.SavgolOptions(window=4), "window"),
            (tp.NoiseEstimateOptions(window=11), "NoiseEstimateOptions::window"),
            (tp.ModalOptions(modes=0), "ModalOptions::modes 0\\b"),
            (tp.BeamStudyOptions(length=0.1, outer_diameter=0.01, modes=-1), "BeamStudyOptions::modes"),
            (tp.TapNoise(sigma=-0.1), "TapNoise::sigma"),
            (tp.PrecisionOptions(**taps, confidence=1.5), "PrecisionOptions::confidence"),
            (tp.JointFitOptions(bootstrap_samples=5), "JointFitOptions::bootstrap_samples"),
            (tp.ForwardCheckOptions(replicates=10), "ForwardCheckOptions::replicates"),
            (tp.IdentificationOptions(width=-1.0), "IdentificationOptions::width"),
            (tp.CaseStudyOptions(noise_sigma=-0.05), "CaseStudyOptions::noise_sigma"),
            (tp.FrfWriteOptions(comments=["two\nlines"]), r"FrfWriteOptions::comments\[0\]"),
            (tp.FrfWriteOptions(coherence=[0.5, 1.5]), r"FrfWriteOptions::coherence\[1\]")):
        with pytest.raises(tp.InvalidArgument, match=field):
            o.check()


def test_more_options_repr_reads_back():
    names = {n: getattr(tp, n) for n in OPTION_NAMES}
    assert repr(tp.SavgolOptions(window=41, order=3)) == "SavgolOptions(window=41, order=3)"
    for o in (tp.NoiseEstimateOptions(local=tp.SavgolOptions(window=9, order=3), window=101, floor=False),
              tp.FrfReadOptions(format="uff", dataset=2, response_node=1, units="mm/N", columns=["1", "2", "3"]),
              tp.FrfWriteOptions(format="csv", comments=["a"], coherence=[0.5, 0.9],
                                 dof={"response_node": 1, "response_direction": 3, "reference_node": 1,
                                      "reference_direction": 3}),
              tp.BeamStudyOptions(length=0.123, outer_diameter=0.016, shear_coefficient=0.85, frequency_hz=[100.0, 200.0],
                                  method="modal", modal=tp.ModalOptions(modes=50, static_residual=True)),
              tp.PrecisionOptions(route="spindle_holder_sh", holder=tp.TapTestOptions(side="holder", spacing_m=0.02),
                                  noise=tp.TapNoise(averages=5), target=0.02),
              tp.IdentificationOptions(method="seed", band_hz=(2500.0, 2650.0), filter=tp.SavgolOptions(window=41, order=2),
                                       noise=tp.NoiseSpec(source="stated", magnitude_sigma=0.05),
                                       fit=tp.JointFitOptions(uncertainty="linearised", threads=1),
                                       verdict=tp.VerdictOptions(forward=tp.ForwardCheckOptions(replicates=100))),
              tp.CaseStudyOptions(noise_sigma=0.02, fit=False, fit_options=tp.JointFitOptions(seed=3))):
        back = eval(repr(o), names)
        assert back == o and back is not o, repr(o)


def test_savgol_and_noise_options_forms_are_the_keyword_forms(prediction):
    f, blocks = prediction.frequency_hz, prediction.frf
    noisy = tp.add_measurement_noise(f, blocks, sigma=0.05, seed=3)
    o = tp.SavgolOptions(window=41, order=3)
    assert np.array_equal(tp.savgol_filter(noisy, o, frequency_hz=f), tp.savgol_filter(noisy, 41, 3, frequency_hz=f))
    assert np.array_equal(tp.savgol_coefficients(o), tp.savgol_coefficients(41, 3))
    with pytest.raises(tp.InvalidArgument, match="window"):
        tp.savgol_filter(noisy, tp.SavgolOptions(window=40, order=3))
    e = tp.estimate_block_noise(f, noisy, tp.NoiseEstimateOptions(local=tp.SavgolOptions(window=9, order=3), window=101,
                                                                  floor=False))
    k = tp.estimate_block_noise(f, noisy, local_window=9, local_order=3, window=101, floor=False)
    assert e.to_dict() == k.to_dict() and np.array_equal(e.relative, k.relative)


def test_frf_file_options_forms_are_the_keyword_forms(tmp_path, prediction):
    f, h = prediction.frequency_hz, prediction.frf[:, 0, 0]
    tp.write_frf_file(str(tmp_path / "k.uff"), f, h, format="uff", description="keyword",
                      dof={"response_node": 1, "response_direction": 3, "reference_node": 1, "reference_direction": 3})
    tp.write_frf_file(str(tmp_path / "o.uff"), f, h, tp.FrfWriteOptions(
        format="uff", description="keyword",
        dof={"response_node": 1, "response_direction": 3, "reference_node": 1, "reference_direction": 3}))
    assert (tmp_path / "k.uff").read_bytes() == (tmp_path / "o.uff").read_bytes()
    k = tp.read_frf_file(str(tmp_path / "k.uff"), response_node=1)
    o = tp.read_frf_file(str(tmp_path / "k.uff"), tp.FrfReadOptions(response_node=1))
    assert np.array_equal(k.values, o.values) and k.metadata == o.metadata
    # What only the options reach: a coherence column written, and the units of a file that does not
    # say them (the oracle: values in mm/N read as 1e-3 m/N).
    coherence = np.linspace(0.5, 1.0, len(f))
    tp.write_frf_file(str(tmp_path / "c.csv"), f, h, tp.FrfWriteOptions(coherence=list(coherence)))
    assert np.array_equal(read_csv(tmp_path / "c.csv")[:, 3], coherence)
    (tmp_path / "mm.csv").write_text("frequency,real,imag\n100,1.0,-2.0\n200,0.5,-1.0\n300,0.25,-0.5\n")
    mm = tp.read_frf_file(str(tmp_path / "mm.csv"), tp.FrfReadOptions(units="mm/N"))
    assert np.allclose(mm.values, 1e-3 * np.array([1 - 2j, 0.5 - 1j, 0.25 - 0.5j]), rtol=1e-15, atol=0)


def test_beam_options_form_and_the_clis_plausibility():
    o = tp.BeamStudyOptions(length=0.123, outer_diameter=0.016, inner_diameter=0.004, shear_model="cowper", modes=4,
                            frequency_hz=[100.0, 1000.0, 5000.0], method="modal",
                            modal=tp.ModalOptions(modes=50, static_residual=True), block="21")
    r = tp.run_beam_study(o)
    k = tp.run_beam_study(length=0.123, outer_diameter=0.016, inner_diameter=0.004, shear_model="cowper", modes=4,
                          frequency_hz=np.array([100.0, 1000.0, 5000.0]), method="modal", modal_terms=50,
                          static_residual=True, block="21")
    assert r.to_dict() == k.to_dict() and np.array_equal(r.receptance, k.receptance)
    # 123 (mm meant) against the usual 1e-4…2 m: beyond 2 × 10, refused as the CLI's --length 123.
    with pytest.raises(tp.InvalidArgument, match=r"BeamStudyOptions::length = 123 is so far outside"):
        tp.run_beam_study(tp.BeamStudyOptions(length=123.0, outer_diameter=0.016))
    with pytest.raises(tp.InvalidArgument, match=r"Material::youngs_modulus = 210000"):  # MPa given
        tp.run_beam_study(length=0.1, outer_diameter=0.016, material=tp.Material("steel", 2.1e5, 0.3, 0.0, 7800.0, 0.0))


def test_precision_options_form_and_the_clis_plausibility(example):
    o = tp.PrecisionOptions(tool=tp.TapTestOptions(spacing_m=0.015), holder=tp.TapTestOptions(side="holder", spacing_m=0.02),
                            noise=tp.TapNoise(sigma=0.005, averages=5, calibration=0.01), target=0.02)
    k = tp.run_precision_study(example, tool_spacing_m=0.015, holder_spacing_m=0.02, sigma=0.005, averages=5,
                               calibration=0.01, target=0.02)
    assert tp.run_precision_study(example, o).to_dict() == k.to_dict()
    # 15 (mm meant) against the usual 1e-3…0.1 m: refused as the CLI's --tool-spacing 15; σ = 5 (%
    # meant) against the usual 1e-4…0.2: refused as its --sigma 5.
    with pytest.raises(tp.InvalidArgument, match=r"PrecisionOptions::tool.spacing_m = 15 is so far outside"):
        tp.run_precision_study(example, tp.PrecisionOptions(tool=tp.TapTestOptions(spacing_m=15.0),
                                                            holder=tp.TapTestOptions(side="holder", spacing_m=0.02)))
    with pytest.raises(tp.InvalidArgument, match=r"TapNoise::sigma = 5 is so far outside"):
        tp.run_precision_study(example, tool_spacing_m=0.015, holder_spacing_m=0.02, sigma=5.0)


def test_tap_test_judges_what_the_cli_judges(example):
    # 15 (mm meant) against the usual 1e-3…0.1 m, as the CLI's --spacing 15; a floor of 2 (% meant)
    # against the usual 1e-4…0.2, as its --floor 2: refused in both forms, naming the field.
    with pytest.raises(tp.InvalidArgument, match=r"TapTestOptions::spacing_m = 15 is so far outside"):
        tp.run_tap_test_study(example, spacing_m=15.0)
    with pytest.raises(tp.InvalidArgument, match=r"TapTestOptions::floor = 2 is so far outside"):
        tp.run_tap_test_study(example, tp.TapTestOptions(spacing_m=0.015, floor=2.0))


def test_identification_and_case_study_options_forms_are_the_keyword_forms(example, model):
    f = example.frequency_hz
    sh = tp.add_measurement_noise(f, model.holder_tip(f), sigma=0.05, seed=1)
    sht = tp.add_measurement_noise(f, model.tool_point(f), sigma=0.05, seed=2)
    data = [tp.IdentificationData(f, sht, B11=sh)]
    o = tp.IdentificationOptions(method="seed", filter=tp.SavgolOptions(window=41, order=2),
                                 fit=tp.JointFitOptions(uncertainty="linearised", threads=1),
                                 verdict=tp.VerdictOptions(forward=tp.ForwardCheckOptions(replicates=60, false_alarm=0.05)))
    ours = tp.run_identification_study(example, data, o)
    assert ours.method == "seed" and ours.to_dict() != {}
    k = tp.run_identification_study(example, data, method="seed", filter=(41, 2), uncertainty="linearised", threads=1)
    # The keyword form has no verdict options: the same identification bar the forward check's replicates.
    assert ours.identified == k.identified and ours.to_dict()["seed"] == k.to_dict()["seed"]
    o.verdict = tp.VerdictOptions()
    assert tp.run_identification_study(example, data, o).to_dict() == k.to_dict()
    # The stated noise judged as the CLI's --sigma: 5 (% meant) refused naming the field
    # (noise_spec_fields: σ within 0…0.5).
    with pytest.raises(tp.InvalidArgument, match=r"NoiseSpec::magnitude_sigma 5 must lie in 0…0.5"):
        tp.run_identification_study(example, data, tp.IdentificationOptions(noise=tp.NoiseSpec(source="stated",
                                                                                               magnitude_sigma=5.0)))
    c = tp.run_case_study(example, tp.CaseStudyOptions(fit=False, noise_sigma=0.02, seed=4))
    assert c.fitted is None and c.to_dict() == tp.run_case_study(example, fit=False, noise_sigma=0.02, seed=4).to_dict()


def test_lobes_options_are_defined_once(example, model):
    """run_lobes_study's option keywords and `toolpoint lobes`' flags derive from one table
    (lobes_study_fields, include/toolpoint/option_fields.hpp): each field is a keyword whose default
    is the C++ one and whose docstring gives its help; set through the keywords and through the flags
    (in their CLI units: %, mm), the options echoed by to_dict() and --json under the field names are
    the values given (to 1e-14 relative: the CLI's unit and back cost an ulp or two)."""
    import re

    fields = tp._toolpoint._option_fields["LobesStudyOptions"]
    # Independent of the table: the keywords run_lobes_study has had since before it.
    assert {f["name"] for f in fields} == {"max_depth_m", "lobes", "tolerance", "steps", "degree", "max_modes", "fit_target",
                                           "pocket_prominence", "pockets", "speed_nodes", "extrapolate_bearings"}
    doc = tp.run_lobes_study.__doc__
    signature = doc.splitlines()[0]
    values, kwargs, flags, switched = {}, {}, [], []
    for f in fields:
        m = re.search(r"\b%s: \w+ = ([\w.\-]+)" % f["name"], signature)
        assert m, f["name"]
        default = {"True": 1.0, "False": 0.0}.get(m.group(1))
        assert (default if default is not None else float(m.group(1))) == f["default"], f["name"]
        assert f["help"] in doc, f["name"]
        # A valid value other than the default, a thousandth of the way into the range.
        v = f["min"] + (f["max"] - f["min"]) * 0.001 if np.isfinite(f["max"]) else f["min"] + 0.001
        if f["kind"] == "flag":
            switched.append(f["name"])
            kwargs[f["name"]] = True
            flags.append(f["flag"])
            continue
        if f["kind"] == "integer":
            v = float(np.floor(v))
        if f["name"] == "degree":
            v = 1.0  # 0, the range's floor, is the semi-discretization's zeroth order only
        assert v != f["default"], f["name"]
        values[f["name"]] = v
        kwargs[f["name"]] = int(v) if f["kind"] == "integer" else v
        if f["flag"]:
            flags += [f["flag"], repr(kwargs[f["name"]] * f["cli_per_unit"] if f["kind"] == "real" else kwargs[f["name"]])]
    f = example.frequency_hz
    cut = tp.CuttingConditions(4, 6e8, 0.3, immersion=0.5, milling="down")
    py = tp.run_lobes_study(cut, (5000.0, 15000.0, 50), frequency_hz=f, xx=tp.milling_frfs(model, f), **kwargs).to_dict()
    assert {k: py["options"][k] for k in values} == pytest.approx(values, rel=1e-14)
    assert all(py["options"][k] is True for k in switched)
    cli = run_cli_json("lobes", "--assembly", EXAMPLE, "--teeth", 4, "--kt", 6e8, "--kr", 0.3, "--immersion", 0.5, "--milling",
                       "down", "--rpm", "5000:15000", "--speeds", 50, "--speed-model", "standstill", *flags)
    expected = {k: v for k, v in values.items() if k not in ("degree", "pockets")}  # no flags: the defaults
    assert {k: cli["options"][k] for k in expected} == pytest.approx(expected, rel=1e-14)
    assert all(cli["options"][k] is True for k in switched)
    assert (cli["options"]["degree"], cli["options"]["pockets"]) == (2, 5)


def test_simulation_and_pitch_options_are_defined_once():
    """simulate_milling's SimulationOptions keywords (simulation_fields) and PitchChoiceOptions'
    attributes (pitch_choice_fields) against their tables: independent of the tables, the names
    written here (the keywords and attributes these had before); each keyword's default in the
    signature and each attribute of a default PitchChoiceOptions is the table's C++ default, and the
    docstring gives each field's help."""
    import re

    sim = tp._toolpoint._option_fields["SimulationOptions"]
    assert [f["name"] for f in sim] == ["revolutions", "steps_per_tooth", "slices", "analysed_fraction", "record",
                                        "memory_revolutions"]
    doc = tp.simulate_milling.__doc__
    signature = doc.splitlines()[0]
    for f in sim:
        m = re.search(r"\b%s: \w+ = ([\w.\-]+)" % f["name"], signature)
        assert m, f["name"]
        default = {"True": 1.0, "False": 0.0}.get(m.group(1))
        assert (default if default is not None else float(m.group(1))) == f["default"], f["name"]
        assert f["help"] in doc, f["name"]
    pitch = tp._toolpoint._option_fields["PitchChoiceOptions"]
    assert {f["name"] for f in pitch} == {"speed_rpm", "min_pitch_rad", "max_pitch_rad", "chatter_hz", "window",
                                          "search_points", "robustness", "steps", "degree", "max_depth_m", "depth_steps"}
    o = tp.PitchChoiceOptions()
    for f in pitch:
        assert f["name"] in tp.PitchChoiceOptions._fields
        assert getattr(o, f["name"]) == f["default"], f["name"]


def test_identification_options_are_defined_once():
    """JointFitOptions, ForwardCheckOptions and IdentificationOptions against their tables
    (joint_fit_fields, forward_check_fields, identification_fields): independent of the tables, the
    names written here; each is an attribute of the class whose default is the table's, and the
    class docstring gives each field's help."""
    expected = {
        "JointFitOptions": {"reciprocal", "bootstrap_samples", "shared_calibration", "check_linearisation", "confidence",
                            "max_iterations"},
        "ForwardCheckOptions": {"min_prominence", "replicates", "false_alarm", "frequency_tolerance", "peak_tolerance",
                                "shared_calibration"},
        "IdentificationOptions": {"width"},
    }
    for name, names in expected.items():
        fields = tp._toolpoint._option_fields[name]
        assert {f["name"] for f in fields} == names, name
        cls = getattr(tp, name)
        o = cls()
        for f in fields:
            assert f["name"] in cls._fields, (name, f["name"])
            assert float(getattr(o, f["name"])) == f["default"], (name, f["name"])
            assert f["help"] in cls.__doc__, (name, f["name"])
