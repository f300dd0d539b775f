"""The option tables of ParallelOptions, UncertaintyOptions, ZeroOrderOptions, BoundaryOptions,
ModalOptions, BeamStudyOptions, PredictOptions, OverhangStudyOptions, CuttingConditions, SpeedRange,
NoiseSpec and ForceLaw
(include/toolpoint/option_fields.hpp; issue 26) as Python meets them: the tables' fields and
defaults (written out here by hand from the headers, not read from the tables), the bound classes'
attributes with their help and flag in the docstring, the keyword functions documented from their
tables, check() refusing a value just outside the old range by its field's name, and a value the
unit cannot mean (a length in mm, a spin in rad/s) refused."""
import warnings

import numpy as np
import pytest

import toolpoint as tp
from conftest import expect_table_attributes

TABLES = tp._toolpoint._option_fields

# The headers' defaults (parallel.hpp, uncertainty.hpp, stability.hpp, beam.hpp, studies/beam.hpp,
# studies/predict.hpp), written out.
EXPECTED = {
    "ParallelOptions": {"threads": 0},
    "UncertaintyOptions": {"samples": 200, "threads": 0},
    "ZeroOrderOptions": {"lobes": -1, "max_depth_m": 0.0},
    "BoundaryOptions": {"tolerance": 0.01, "steps": 0, "max_steps": 4000, "degree": 2, "max_depth_m": 0.0,
                        "threads": 0},
    "ModalOptions": {"modes": 100, "static_residual": False},
    "BeamStudyOptions": {"length": 0.0, "outer_diameter": 0.0, "inner_diameter": 0.0, "modes": 5, "speed_rpm": 0.0},
    "PredictOptions": {"speed_rpm": 0.0, "extrapolate_bearings": False},
    "OverhangStudyOptions": {"tracking_tolerance": 0.15, "threads": 0},
    "CuttingConditions": {"teeth": 0, "tangential_coefficient": 0.0, "radial_ratio": 0.0, "feed_per_tooth_m": 0.0,
                          "diameter_m": 0.0, "process_damping_n_per_m": 0.0, "helix_slices": 0},
    "SpeedRange": {"min_rpm": 0.0, "max_rpm": 0.0, "points": 1000},
    "ForceLaw": {"tangential_coefficient": 0.0, "radial_ratio": 0.0, "tangential_edge": 0.0, "radial_edge": 0.0,
                 "exponent": 1.0, "reference_chip_m": 1e-4, "process_damping_n_per_m": 0.0},
    "NoiseSpec": {"magnitude_sigma": 0.0, "phase_sigma_rad": 0.0, "floor": 0.0, "calibration": 0.0, "averages": 0},
}
# Bound as classes whose attributes are the table's fields, and the command whose flags they are.
CLASSES = {"UncertaintyOptions": "toolpoint predict", "ModalOptions": "toolpoint beam",
           "BeamStudyOptions": "toolpoint beam", "OverhangStudyOptions": "toolpoint couple",
           "NoiseSpec": "toolpoint identify"}


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_tables_hold_the_fields_with_the_defaults(name):
    expect_table_attributes(name, EXPECTED[name], CLASSES.get(name), bound=name in CLASSES)


def test_keywords_documented_from_their_tables():
    for f in TABLES["ZeroOrderOptions"]:
        assert f["help"] in tp.zero_order_lobes.__doc__
    for f in TABLES["BoundaryOptions"]:
        assert f["help"] in tp.stability_boundary.__doc__
    assert "tolerance, 1e-06…0.5" in tp.stability_boundary.__doc__


# Just outside the old checks' ranges (uncertainty.cpp, parallel.cpp, beam.cpp at b7606b0).
@pytest.mark.parametrize("name,field,bad", [
    ("UncertaintyOptions", "samples", 9), ("UncertaintyOptions", "samples", 1000001),
    ("UncertaintyOptions", "threads", -1), ("UncertaintyOptions", "threads", 1025),
    ("ModalOptions", "modes", 0), ("ModalOptions", "modes", 20001),
    ("OverhangStudyOptions", "tracking_tolerance", 0.0), ("OverhangStudyOptions", "tracking_tolerance", 1.0),
    ("OverhangStudyOptions", "threads", -1),
    ("NoiseSpec", "magnitude_sigma", 0.51), ("NoiseSpec", "phase_sigma_rad", 0.51), ("NoiseSpec", "floor", -0.01),
    ("NoiseSpec", "calibration", 0.11), ("NoiseSpec", "averages", 100001),
])
def test_check_names_the_field(name, field, bad):
    o = getattr(tp, name)()
    o.check()
    setattr(o, field, bad)
    with pytest.raises(tp.InvalidArgument, match=rf"{name}::{field}\b"):
        o.check()


def test_beam_study_judges_its_units():
    # 120 mm given as metres, a diameter of 16 "m", a spin of 20 "rpm": refused, naming the field.
    for kwargs, field in (({"length": 120.0, "outer_diameter": 0.016}, "length"),
                          ({"length": 0.12, "outer_diameter": 16.0}, "outer_diameter"),
                          ({"length": 0.12, "outer_diameter": 0.016, "speed_rpm": 20.0}, "speed_rpm")):
        with pytest.raises(tp.InvalidArgument, match=rf"BeamStudyOptions::{field}\b"):
            tp.run_beam_study(**kwargs)
    # Unusual but possible (500 rpm: rad/s?): a warning, and the study runs.
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = tp.run_beam_study(length=0.12, outer_diameter=0.016, speed_rpm=500.0)
    assert r.whirl is not None
    assert any("BeamStudyOptions::speed_rpm" in str(w.message) for w in caught)
    o = tp.BeamStudyOptions()
    o.length, o.outer_diameter, o.modes = 0.12, 0.016, 3
    assert len(tp.run_beam_study(o).mode_frequency_hz) == 3


def test_the_cut_and_the_speeds_judge_their_units():
    # K_t in MPa, a diameter in mm, speeds in thousands of rpm: refused naming the field (check(),
    # cutting_fields and speed_range_fields); an unusual K_r warned about naming the field.
    with pytest.raises(tp.InvalidArgument, match=r"CuttingConditions::tangential_coefficient = 600 .*cannot be meant"):
        tp.CuttingConditions(4, 600.0, 0.3, immersion=0.5)
    with pytest.raises(tp.InvalidArgument, match=r"CuttingConditions::diameter_m = 16 .*cannot be meant"):
        tp.CuttingConditions(4, 6e8, 0.3, immersion=0.5, diameter_m=16.0)
    with pytest.raises(tp.InvalidArgument, match=r"CuttingConditions::teeth 0 must lie in 1…1000"):
        tp.CuttingConditions(0, 6e8, 0.3, immersion=0.5)
    with pytest.raises(tp.InvalidArgument, match=r"CuttingConditions::process_damping_n_per_m 10 N/m must lie in"):
        tp.CuttingConditions(4, 6e8, 0.3, immersion=0.5, diameter_m=0.02, process_damping_n_per_m=10.0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        c = tp.CuttingConditions(4, 6e8, 2.0, immersion=0.5)
    assert c.radial_ratio == 2.0
    assert [str(w.message) for w in caught if "CuttingConditions::radial_ratio = 2" in str(w.message)]
    f = np.linspace(10.0, 5000.0, 500)
    H = tp.modal_frf([tp.Mode(0.04, 0.03, 900.0)], f)
    with pytest.raises(tp.InvalidArgument, match=r"SpeedRange::max_rpm = 0.5 .*cannot be meant"):
        tp.zero_order_lobes(f, H, c, (5000.0, 0.5, 50))
