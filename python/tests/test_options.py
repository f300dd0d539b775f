"""Bound *Options types: keyword-only constructors whose defaults are the C++ ones (the header's
values, include/toolpoint/stability/modal_fit.hpp and peaks.hpp, written out here as the independent
reference), check() raising the library's InvalidArgument naming the field, a repr that rebuilds
the object, and the functions taking them."""
import numpy as np
import pytest

import toolpoint as tp


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
