"""The CLI's plausibility checks in Python (plausibility.hpp's table, applied by the library's
judge_receptance_data and require_plausible): the commonest unit slips are said or refused, naming
the field, and the right units pass silently.

The oracle is the slip itself: a 1-DOF tool point (40 g, ζ = 3 %, 900 Hz; peak |H| = 1/(2ζk) ≈
1.3e-5 m/N, inside the usual 1e-10…1e-4 m/N) given in mm/N (×1e3: 0.013, unusual → a warning) or
µm/N (×1e6: 13, beyond 1e-4 × 1e4 → refused), its frequencies in rad/s (top 5000 Hz → 31 416,
above the usual 2e4 Hz → a warning), K_t in MPa (600 for 6e8 N/m², below 5e7 / 100 → refused).
"""
import math
import warnings

import numpy as np
import pytest

import toolpoint as tp

F = np.linspace(10.0, 5000.0, 500)
MODE = tp.Mode(0.04, 0.03, 900.0)
H = tp.modal_frf([MODE], F)
CUT = tp.CuttingConditions(4, 6e8, 0.3, immersion=0.5, milling="down")
SPEEDS = (2000.0, 20000.0, 50)


def test_the_right_units_pass_without_a_word():
    assert 1e-5 < np.max(np.abs(H)) < 1e-4  # the oracle's premise: a usual tool point peak
    with warnings.catch_warnings():
        warnings.simplefilter("error", tp.Warning)
        tp.zero_order_lobes(F, H, CUT, SPEEDS)
        tp.fit_modes(F, H, options=tp.ModalFitOptions(max_modes=1))


def test_receptance_in_mm_per_n_is_said_naming_the_argument():
    with pytest.warns(tp.Warning, match=r"xx: the largest receptance magnitude \|H\| \[m/N\] = 0\.01"):
        tp.zero_order_lobes(F, H * 1e3, CUT, SPEEDS)
    with pytest.warns(tp.Warning, match=r"values: the largest receptance magnitude"):
        tp.fit_modes(F, H * 1e3, options=tp.ModalFitOptions(max_modes=1))


def test_receptance_in_um_per_n_is_refused_naming_the_argument():
    with pytest.raises(tp.InputError, match=r"xx: the largest receptance magnitude .* cannot be meant") as e:
        tp.zero_order_lobes(F, H * 1e6, CUT, SPEEDS)
    assert "m/N" in e.value.hint
    with pytest.raises(tp.InputError, match=r"G11: the largest receptance"):
        blocks = np.zeros((len(F), 2, 2), complex)
        blocks[:, 0, 0] = H * 1e6
        tp.IdentificationData(F, blocks)


def test_frequency_in_rad_per_s_is_said_naming_the_argument():
    with pytest.warns(tp.Warning, match=r"xx: the top frequency \[Hz\] = 31415\.9"):
        tp.zero_order_lobes(F * 2 * math.pi, H, CUT, SPEEDS)
    # A modal frequency so high only rad/s explains it (4 kHz = 25 133 rad/s), as the CLI's --mode.
    with pytest.warns(tp.Warning, match=r"Mode::frequency_hz = 25132\.7.*not rad/s"):
        tp.Mode(0.04, 0.03, 4000.0 * 2 * math.pi)


def test_a_stray_frequency_point_is_refused():
    f = F.copy()
    f[-1] = 1e9  # a stray line: 1e9 Hz after 10…5000 Hz
    with pytest.raises(tp.InputError, match=r"xx: its last point, at 1e\+09 Hz"):
        tp.zero_order_lobes(f, H, CUT, SPEEDS)


def test_kt_in_mpa_is_refused_naming_the_field():
    with pytest.raises(tp.InvalidArgument, match=r"CuttingConditions::tangential_coefficient = 600 is so far outside") as e:
        tp.CuttingConditions(4, 600.0, 0.3, immersion=0.5)
    assert "are in N/m^2" in e.value.hint  # the plausible range's (kCuttingCoefficient)
    with pytest.raises(tp.InvalidArgument, match=r"CuttingConditions::radial_ratio = 30 is so far outside"):
        tp.CuttingConditions(4, 6e8, 30.0, immersion=0.5)  # 30 % as 30


def test_speeds_in_thousands_of_rpm_are_refused():
    with pytest.raises(tp.InvalidArgument, match=r"SpeedRange::min_rpm = 0\.2 is so far outside"):
        tp.zero_order_lobes(F, H, CUT, (0.2, 2.0, 50))


def test_point_spacing_in_mm_is_refused_naming_the_field():
    # 15 (mm meant) against the usual 1e-3…0.1 m: beyond 0.1 × 10, as the CLI's --spacing 15.
    H3 = {(0, 0): H, (1, 0): H, (2, 0): H}
    with pytest.raises(tp.InvalidArgument, match=r"RotationalOptions::spacing = 15 is so far outside"):
        tp.rotational_frfs(F, H3, tp.RotationalOptions(spacing=15.0))
