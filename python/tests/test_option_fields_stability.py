"""The modal fit's option table (modal_fit_fields, include/toolpoint/stability/modal_fit.hpp; issue
26) as Python meets it: ModalFitOptions' attributes are the table's fields (the names and defaults
written out here by hand, from modal_fit.hpp), their docstrings carry the help and the `toolpoint
modes` flag, and check() refuses a value just outside the ranges the hand-written check had (1…20
modes, a prominence > 0 dB, at least 10 evaluations) naming the field."""
import pytest

import toolpoint as tp

TABLES = tp._toolpoint._option_fields


def test_modal_fit_options_attributes_are_its_fields():
    fields = TABLES["ModalFitOptions"]
    assert [f["name"] for f in fields] == ["max_modes", "min_prominence_db", "residual_terms", "max_evaluations"]
    assert set(f["name"] for f in fields) <= set(tp.ModalFitOptions._fields)
    expected = {"max_modes": 3, "min_prominence_db": 3.0, "residual_terms": True, "max_evaluations": 2000}
    o = tp.ModalFitOptions()
    for f in fields:
        value = getattr(o, f["name"])
        assert value == expected[f["name"]] == f["default"], f["name"]
        kind = {"integer": int, "real": float, "flag": bool}[f["kind"]]
        assert type(value) is kind, f["name"]
        doc = getattr(tp.ModalFitOptions, f["name"]).__doc__
        assert f["help"] in doc, f["name"]
        if f["flag"]:
            assert f"toolpoint modes {f['flag']}" in doc, f["name"]
    assert {f["name"]: f["flag"] for f in fields if f["flag"]} == {"max_modes": "--max-modes",
                                                                  "min_prominence_db": "--min-prominence"}


@pytest.mark.parametrize("field,good,bad", [("max_modes", [1, 20], [0, 21]), ("min_prominence_db", [1e-9, 40.0], [0.0, -1.0]),
                                            ("max_evaluations", [10, 100000], [9])])
def test_modal_fit_check_names_the_field(field, good, bad):
    for v in good:
        o = tp.ModalFitOptions(**{field: v})
        o.check()
    for v in bad:
        with pytest.raises(tp.InvalidArgument, match=rf"ModalFitOptions::{field}\b"):
            tp.ModalFitOptions(**{field: v}).check()


def test_keyword_construction_keeps_the_band():
    o = tp.ModalFitOptions(max_modes=2, band_hz=(500.0, 3000.0))
    assert o.max_modes == 2 and tuple(o.band_hz) == (500.0, 3000.0)
    with pytest.raises(tp.InvalidArgument, match=r"ModalFitOptions::band_hz"):
        tp.ModalFitOptions(band_hz=(3000.0, 500.0)).check()


@pytest.mark.parametrize("name,command,expected", [
    # The headers' defaults, written out (case_study.hpp, precision.hpp).
    ("CaseStudyOptions", "demo", {"noise_sigma": 0.05, "apply_filter": True, "band_width": 0.02, "fit": True}),
    ("PrecisionOptions", "precision", {"reciprocal": True, "confidence": 0.95}),
])
def test_case_study_and_precision_attributes_are_their_fields(name, command, expected):
    fields = TABLES[name]
    assert [f["name"] for f in fields] == list(expected)
    cls = getattr(tp, name)
    o = cls()
    for f in fields:
        assert getattr(o, f["name"]) == expected[f["name"]] == f["default"], f["name"]
        doc = getattr(cls, f["name"]).__doc__
        assert f["help"] in doc, f["name"]
        if f["flag"]:
            assert f"toolpoint {command} {f['flag']}" in doc, f["name"]


def test_case_study_and_precision_check_name_the_field():
    # The ranges the hand-written checks had: σ in [0, 1), the band in (0, 0.5), confidence in (0.5, 1).
    for kwargs in ({"noise_sigma": 1.0}, {"noise_sigma": -1e-9}, {"band_width": 0.0}, {"band_width": 0.5}):
        (field,) = kwargs
        with pytest.raises(tp.InvalidArgument, match=rf"CaseStudyOptions::{field}\b"):
            tp.CaseStudyOptions(**kwargs).check()
    tp.CaseStudyOptions(noise_sigma=0.0, band_width=0.49).check()
    taps = {"tool": tp.TapTestOptions(side="tool", spacing_m=0.015), "holder": tp.TapTestOptions(side="holder", spacing_m=0.02)}
    for bad in (0.5, 1.0):
        with pytest.raises(tp.InvalidArgument, match=r"PrecisionOptions::confidence\b"):
            tp.PrecisionOptions(**taps, confidence=bad).check()
    tp.PrecisionOptions(**taps, confidence=0.99).check()
