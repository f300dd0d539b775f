"""The option tables migrated after LobesStudyOptions (include/toolpoint/option_fields.hpp; issue 26)
as Python meets them: TapTestOptions' attributes and add_measurement_noise's keywords are the table's
fields (the names written out here by hand, from the bindings before the tables), with the C++
defaults, their help in the docstrings, and check() refusing a value just outside a range by its
field's name."""
import re

import numpy as np
import pytest

import toolpoint as tp

TABLES = tp._toolpoint._option_fields


def test_tap_test_options_attributes_are_its_fields():
    fields = TABLES["TapTestOptions"]
    assert [f["name"] for f in fields] == ["spacing_m", "points", "sigma", "floor", "averages", "calibration"]
    o = tp.TapTestOptions()
    assert set(f["name"] for f in fields) <= set(tp.TapTestOptions._fields)
    # The header's defaults, written out (tap_test.hpp), and the table's.
    expected = {"spacing_m": 0.0, "points": 3, "sigma": 0.0, "floor": 0.0, "averages": 0, "calibration": 0.0}
    for f in fields:
        value = getattr(o, f["name"])
        assert value == expected[f["name"]] == f["default"], f["name"]
        assert isinstance(value, int if f["kind"] == "integer" else float), f["name"]
        doc = getattr(tp.TapTestOptions, f["name"]).__doc__
        assert f["help"] in doc and f"toolpoint taptest {f['flag']}" in doc, f["name"]


@pytest.mark.parametrize("field,bad", [("spacing_m", 0.0), ("points", 4), ("points", 1), ("sigma", 1.0), ("sigma", -1e-9),
                                       ("floor", 0.5000001), ("averages", 1), ("averages", 10001),
                                       ("calibration", 0.1000001)])
def test_tap_test_check_names_the_field(field, bad):
    o = tp.TapTestOptions(spacing_m=0.01)
    o.check()
    setattr(o, field, bad)
    with pytest.raises(tp.InvalidArgument, match=rf"TapTestOptions::{field}\b"):
        o.check()


def test_integer_fields_refuse_fractions():
    with pytest.raises(TypeError):
        tp.TapTestOptions().points = 2.5


def test_add_measurement_noise_keywords_are_noise_fields():
    fields = TABLES["NoiseOptions"]
    assert [f["name"] for f in fields] == ["sigma", "floor", "calibration", "averages"]
    doc = tp.add_measurement_noise.__doc__
    signature = doc.splitlines()[0]
    expected = {"sigma": 0.05, "floor": 0.0, "calibration": 0.0, "averages": 0}  # signal.hpp's defaults
    for f in fields:
        m = re.search(r"\b%s: \w+ = ([\w.\-]+)" % f["name"], signature)
        assert m, f["name"]
        assert float(m.group(1)) == expected[f["name"]] == f["default"], f["name"]
        assert f["help"] in doc and f"toolpoint noise {f['flag']}" in doc, f["name"]
    f = [100.0, 110.0]
    for kwargs in ({"sigma": -1e-9}, {"floor": 0.51}, {"calibration": 0.11}, {"averages": 1}):
        (name,) = kwargs
        with pytest.raises(tp.InvalidArgument, match=rf"NoiseOptions::{name}\b"):
            tp.add_measurement_noise(np.array(f), np.array([1e-6 + 0j, 2e-6 + 0j]), **kwargs)


def test_tap_noise_attributes_are_its_fields():
    fields = TABLES["TapNoise"]
    assert [f["name"] for f in fields] == ["sigma", "floor", "averages", "calibration", "shared_calibration"]
    assert [f["name"] for f in fields] == list(tp.TapNoise._fields)
    expected = {"sigma": 0.01, "floor": 0.0, "averages": 1, "calibration": 0.0, "shared_calibration": False}  # precision.hpp
    o = tp.TapNoise()
    for f in fields:
        assert getattr(o, f["name"]) == expected[f["name"]] == f["default"], f["name"]
        doc = getattr(tp.TapNoise, f["name"]).__doc__
        assert f["help"] in doc and f"toolpoint precision {f['flag']}" in doc, f["name"]
    for field, bad in (("sigma", 0.5000001), ("floor", -1e-9), ("averages", 0), ("averages", 100001), ("calibration", 0.11)):
        o = tp.TapNoise(floor=0.001)
        o.check()
        setattr(o, field, bad)
        with pytest.raises(tp.InvalidArgument, match=rf"TapNoise::{field}\b"):
            o.check()
