"""Bound *Options types: keyword-only constructors whose defaults are the C++ ones (the header's
values, include/toolpoint/stability/modal_fit.hpp and peaks.hpp, written out here as the independent
reference), check() raising the library's InvalidArgument naming the field, a repr that rebuilds
the object, and the functions taking them (also as one options object beside their keyword form)."""
import numpy as np
import pytest

import toolpoint as tp
from conftest import EXAMPLE, run_cli


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
    with pytest.raises(tp.InvalidArgument, match=r"ModalFitOptions::max_modes = 0"):
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
    with pytest.raises(tp.InvalidArgument, match=r"UncertaintyOptions::samples = 5"):
        tp.UncertaintyOptions(samples=5).check()
    with pytest.raises(tp.InvalidArgument, match=r"TapTestOptions::points"):
        tp.run_tap_test(tp.load_assembly(str(EXAMPLE)).assembly, tp.TapTestOptions(spacing_m=0.015, points=4))


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
    p = tp.run_prediction(example, tp.PredictOptions(receptance="SH11", peaks=tp.PeakOptions(min_prominence=0.05)))
    q = tp.run_prediction(example, receptance="SH11", min_prominence=0.05)
    assert p.receptance == "SH11" and np.array_equal(p.frf, q.frf) and p.to_dict() == q.to_dict()
    assert np.array_equal(tp.run_prediction(example, options=tp.PredictOptions()).frf, prediction.frf)
    t = tp.run_tap_test(example, tp.TapTestOptions(spacing_m=0.015, sigma=0.005, seed=11))
    k = tp.run_tap_test(example, spacing_m=0.015, sigma=0.005, seed=11)
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
    t = tp.run_tap_test(example, o)
    run_cli("taptest", EXAMPLE, "--at", "tool", "--spacing", 0.015, "--sigma", 0.01, "--seed", 5, "--floor", 0.002,
            "--averages", 4, "--calibration", 0.02, "--binary", "--output", tmp_path / "tap.uff")
    frfs = [d for d in tp.read_uff(str(tmp_path / "tap.uff")).functions if d.function_type == 4]  # 6: their coherences
    assert len(frfs) == len(t.frfs) == 9
    for d in frfs:
        assert np.array_equal(d.y, t.frf(d.response_node - 1, d.reference_node - 1))
    plain = tp.run_tap_test(example, spacing_m=0.015, sigma=0.01, seed=5)
    assert not np.array_equal(plain.frfs[0].values, t.frfs[0].values)  # the extra noise is there
