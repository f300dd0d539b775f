"""The library's exceptions as Python exceptions (one class per toolpoint error type, all derived
from toolpoint.Error) with the same message and hint; results as plain data."""
import json
import traceback

import numpy as np
import pytest

import toolpoint as tp


def test_one_class_per_error_type_all_derived_from_error():
    for cls in (tp.InvalidArgument, tp.InputError, tp.NumericalError, tp.VerdictFailure, tp.IoError):
        assert issubclass(cls, tp.Error) and cls.__module__ == "toolpoint"
    assert issubclass(tp.Error, Exception) and issubclass(tp.InvalidArgument, ValueError)
    assert issubclass(tp.Warning, UserWarning)


def test_message_and_hint_are_the_library_ones(example):
    # The message and hint of TapTestOptions::check (src/studies/tap_test.cpp), as the CLI prints them.
    with pytest.raises(tp.InvalidArgument) as e:
        tp.run_tap_test_study(example, spacing_m=-1.0)
    # (The range and the hint from the field's definition, tap_test_fields: option_fields.hpp.)
    assert str(e.value) == "TapTestOptions::spacing_m -1 m must be > 0"
    assert e.value.hint.startswith("give TapTestOptions::spacing_m a value > 0 m (distance s between neighbouring points "
                                   "(0.01 for 10 mm)")
    shown = "".join(traceback.format_exception(e.value))
    assert "fix: " + e.value.hint in shown  # the hint as a note under the message


def test_each_error_type_is_raised_where_the_library_raises_it(tmp_path):
    steel = tp.Material("steel", youngs_modulus=2e11, density=7800)  # undamped: exact resonances exist
    s = tp.Segment.tube(0.1, 0.016, 0.0, steel)
    f1 = tp.free_free_frequencies(s, 1)
    with pytest.raises(tp.NumericalError):
        tp.exact_receptance(s, f1)  # an exact undamped natural frequency: the receptance is unbounded
    with pytest.raises(tp.IoError):
        tp.load_assembly(str(tmp_path / "none.toml"))
    (tmp_path / "a.toml").write_text("[analysis]\nstart_hz = 10\nstop_hz = 100\nstep_hz = 1\n[modell]\n")
    with pytest.raises(tp.InputError) as e:
        tp.load_assembly(str(tmp_path / "a.toml"))
    assert "a.toml" in str(e.value)
    with pytest.raises(tp.InputError, match=r"frequency_hz: an array of shape \(2, 2\)"):
        tp.AssemblyModel(_example()).tool_point(np.ones((2, 2)))
    with pytest.raises(tp.InvalidArgument, match="side"):
        tp.run_tap_test_study(_example(), spacing_m=0.01, side="spindle")
    with pytest.raises(tp.InvalidArgument, match="not > 0|> 0"):
        tp.AssemblyModel(_example()).tool_point([0.0])


def _example():
    from conftest import EXAMPLE
    return tp.load_assembly(str(EXAMPLE)).assembly


@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")
def test_a_failing_progress_callback_does_not_break_the_computation(example):
    def bad(fraction):
        raise RuntimeError("callback failed")

    p = tp.run_prediction_study(example, progress=bad)  # reported as unraisable, ignored
    assert p.frf.shape == (4991, 2, 2)
    with pytest.raises(tp.InvalidArgument):
        tp.run_prediction_study(example, progress=3)


def test_results_are_plain_data(example, prediction):
    d = prediction.to_dict()
    assert json.loads(json.dumps(d)) == d  # only dict, list, str, float, int, bool, None
    t = tp.run_tap_test_study(example, spacing_m=0.01, points=2, hammer="tip")
    assert json.loads(json.dumps(t.to_dict())) == t.to_dict()
    assert tp.seed_table1_joint().to_dict()["c_tm"] == 1.0


def test_every_function_and_method_has_a_docstring():
    # pybind11 puts the signature on the first line; a description must follow it.
    import inspect
    missing = []
    for name in tp.__all__:
        obj = getattr(tp, name)
        if inspect.isclass(obj):
            if issubclass(obj, BaseException):
                continue
            if not (obj.__doc__ or "").strip():
                missing.append(name)
            for member, value in vars(obj).items():
                if not member.startswith("_") and callable(value) and not isinstance(value, property):
                    if len([line for line in (value.__doc__ or "").splitlines() if line.strip()]) < 2:
                        missing.append(f"{name}.{member}")
        elif callable(obj) and len([line for line in (obj.__doc__ or "").splitlines() if line.strip()]) < 2:
            missing.append(name)
    assert not missing
