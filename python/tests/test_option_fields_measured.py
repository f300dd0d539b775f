"""The option tables of SavgolOptions, PeakChangeOptions, RotationalOptions, TapTestFileOptions,
PeakOptions, NoiseEstimateOptions, ReadoutOptions, VerdictOptions, UffWriteOptions, PlotOptions and
FrfFigureOptions (include/toolpoint/option_fields.hpp; issue 26) as Python meets them: the bound classes' attributes are the tables' fields (names and
defaults written out here by hand from the headers, not read from the tables), each with its help
and, where the CLI has it, its flag in the docstring, and check() refusing a value just outside the
old check()'s range by its field's name."""
import math

import pytest

import toolpoint as tp
from conftest import expect_table_attributes

TABLES = tp._toolpoint._option_fields

# The headers' defaults (signal.hpp, peaks.hpp, noise.hpp, identify.hpp, identification.hpp,
# rotational.hpp) and the command whose flags the fields are, written out.
EXPECTED = {
    "SavgolOptions": ({"window": 5, "order": 2}, "toolpoint filter"),
    "PeakChangeOptions": ({"min_prominence": 0.2, "min_height": 0.05, "warn_above": 0.02, "noise_prominence": 8.0}, None),
    "RotationalOptions": ({"order": 2, "spacing": 0.0, "symmetrise": False, "assume_reciprocity": False},
                          "toolpoint rotational"),
    "TapTestFileOptions": ({"order": 2}, None),
    "PeakOptions": ({"min_prominence": 0.02}, None),
    "NoiseEstimateOptions": ({"window": 201, "floor": True}, None),
    "ReadoutOptions": ({"cond_warning": 1e6, "reciprocity_warning": 0.1, "gain_warning": 20.0}, None),
    "VerdictOptions": ({"residual_doubt": 1.5, "residual_fail": 3.0}, None),
    "UffWriteOptions": ({"binary": False, "byte_order": 1}, None),  # uff.hpp
    "PlotOptions": ({"timeout_s": 60.0}, None),  # plot.hpp
    "FrfFigureOptions": ({"mode_labels": 0, "min_peak_ratio": 2.0}, None),
}
# Not bound as classes: their tables documented as keywords (tap_test_frfs, write_uff) or as data.
NOT_CLASSES = {"PeakChangeOptions", "TapTestFileOptions", "UffWriteOptions", "PlotOptions", "FrfFigureOptions"}


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_tables_hold_the_fields_with_the_defaults(name):
    defaults, command = EXPECTED[name]
    expect_table_attributes(name, defaults, command, bound=name not in NOT_CLASSES)


def test_keywords_documented_from_their_tables():
    (order,) = TABLES["TapTestFileOptions"]
    assert order["flag"] == "--order"
    assert order["help"] in tp.tap_test_frfs.__doc__
    binary, byte_order = TABLES["UffWriteOptions"]
    assert binary["flag"] == "--binary" and byte_order["flag"] is None
    for f in (binary, byte_order):
        assert f["help"] in tp.write_uff.__doc__
    assert "byte_order, 1…2" in tp.write_uff.__doc__


# Just outside the old checks' ranges (signal.cpp, peaks.cpp, noise.cpp, identify.cpp,
# identification.cpp at f7cd67b).
@pytest.mark.parametrize("name,field,bad", [
    ("SavgolOptions", "window", 0), ("SavgolOptions", "window", 4), ("SavgolOptions", "order", -1),
    ("SavgolOptions", "order", 5),
    ("RotationalOptions", "order", 0), ("RotationalOptions", "order", 3), ("RotationalOptions", "spacing", 0.0),
    ("PeakOptions", "min_prominence", 1.0), ("PeakOptions", "min_prominence", -1e-9),
    ("NoiseEstimateOptions", "window", 19), ("NoiseEstimateOptions", "window", 22),
    ("ReadoutOptions", "cond_warning", 1.0), ("ReadoutOptions", "gain_warning", 0.0),
    ("ReadoutOptions", "reciprocity_warning", math.nan),
    ("VerdictOptions", "residual_doubt", 1.0), ("VerdictOptions", "residual_fail", math.inf),
])
def test_check_names_the_field(name, field, bad):
    o = getattr(tp, name)()
    if name == "RotationalOptions":
        o.spacing = 0.01
    o.check()
    setattr(o, field, bad)
    with pytest.raises(tp.InvalidArgument, match=rf"{name}::{field}\b"):
        o.check()


def test_edges_accepted():
    s = tp.SavgolOptions()
    s.window, s.order = 1, 0
    s.check()
    r = tp.RotationalOptions()
    r.spacing, r.order = 1e-12, 1
    r.check()
    p = tp.PeakOptions()
    p.min_prominence = 0.0
    p.check()
    n = tp.NoiseEstimateOptions()
    n.window = 21
    n.check()
    readout = tp.ReadoutOptions()
    readout.cond_warning = math.inf  # never warn: accepted before the table and after
    readout.check()
    v = tp.VerdictOptions()
    v.residual_doubt = v.residual_fail = 2.0
    v.check()
