"""The pitch choice (choose_pitch, PitchChoiceOptions) against `toolpoint pitch --json` (the same
doubles), and bad input naming the field."""
import math

import pytest

import toolpoint as tp
from conftest import run_cli_json

BENCH = tp.Mode(0.03993, 0.011, 922.0)  # docs/reference.md §7


def test_choose_pitch_is_the_cli_one():
    cut = tp.CuttingConditions(4, 6e8, 0.3, immersion=0.5, milling="down")
    o = tp.PitchChoiceOptions(speed_rpm=4130.0, min_pitch_rad=math.radians(60), max_pitch_rad=math.radians(120))
    r = tp.choose_pitch([BENCH], [], cut, o)
    assert len(r.pitch_rad) == 4 and math.isclose(sum(r.pitch_rad), 2 * math.pi, abs_tol=1e-12)
    assert r.pattern == "alternating" and r.gain > 1.5
    assert r.uniform_depth_m < r.chosen_depth_m
    cli = run_cli_json("pitch", "--mode-x", "0.03993,0.011,922", "--rigid-y", "--teeth", 4, "--kt", 6e8, "--kr", 0.3,
                       "--immersion", 0.5, "--milling", "down", "--rpm", 4130, "--min-pitch", 60, "--max-pitch", 120)
    d = r.to_dict()
    assert cli["choice"]["pitch_rad"] == d["pitch_rad"] == list(r.pitch_rad)
    assert cli["choice"]["chosen"]["depth_m"] == d["chosen"]["depth_m"] == r.chosen_depth_m


def test_bad_limits_name_the_field():
    cut = tp.CuttingConditions(4, 6e8, 0.3, immersion=0.5, milling="down")
    o = tp.PitchChoiceOptions(speed_rpm=5000.0, min_pitch_rad=math.radians(95), max_pitch_rad=math.radians(120))
    with pytest.raises(tp.InvalidArgument, match="PitchChoiceOptions::min_pitch_rad"):
        tp.choose_pitch([BENCH], [], cut, o)
    with pytest.raises(tp.InvalidArgument, match="pattern"):
        tp.PitchChoiceOptions(pattern="zigzag")


def test_three_angle_is_the_cli_one():
    """The two-parameter pattern: three angles repeated, P0 = 120° − u, P1 = 120° + u − v,
    P2 = 120° + v for 3 teeth; the same doubles as `toolpoint pitch --pattern three-angle --json`."""
    cut = tp.CuttingConditions(3, 6e8, 0.3, immersion=0.5, milling="down")
    o = tp.PitchChoiceOptions(speed_rpm=5000.0, pattern="three-angle", search_points=5)
    r = tp.choose_pitch([BENCH], [], cut, o)
    assert r.pattern == "three-angle"
    even = 2 * math.pi / 3
    u, v = r.variation_rad, r.second_variation_rad
    assert r.pitch_rad == pytest.approx([even - u, even + u - v, even + v], abs=1e-15)
    assert r.chosen_depth_m > r.uniform_depth_m
    cli = run_cli_json("pitch", "--mode-x", "0.03993,0.011,922", "--rigid-y", "--teeth", 3, "--kt", 6e8, "--kr", 0.3,
                       "--immersion", 0.5, "--milling", "down", "--rpm", 5000, "--pattern", "three-angle",
                       "--search-points", 5)
    d = r.to_dict()
    assert cli["choice"]["second_variation_rad"] == d["second_variation_rad"] == v
    assert cli["choice"]["pitch_rad"] == d["pitch_rad"] == list(r.pitch_rad)
    assert all("second_variation_rad" in s for s in d["samples"])


def test_three_angle_needs_a_multiple_of_three_teeth():
    cut = tp.CuttingConditions(4, 6e8, 0.3, immersion=0.5, milling="down")
    o = tp.PitchChoiceOptions(speed_rpm=5000.0, pattern="three-angle")
    with pytest.raises(tp.InvalidArgument, match="PitchChoiceOptions::pattern three-angle"):
        tp.choose_pitch([BENCH], [], cut, o)
