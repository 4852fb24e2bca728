"""Marko-Siggia interaction (docs/theory/plectoneme.md#interaction).

The formula, and analytic partials against finite differences.
"""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from supercoil.core.dna import marko_siggia as ms
from supercoil.units import BOLTZMANN

KT = BOLTZMANN * 300.0
R0 = 1.75e-9
B = 48e-9 * KT


def w_model(alpha, R):
    """docs/theory/plectoneme.md#interaction written out literally, x = pi cot(alpha) = P/(2R)."""
    x = np.pi / np.tan(alpha)
    return ((1 + x**-12) * KT / R0 * (R / R0) ** -12
            + B ** (-1 / 3) * (1 + x ** (-2 / 3)) * KT ** (4 / 3) / R ** (2 / 3))


alphas = st.floats(0.05, 1.45)
radii = st.floats(0.7, 20.0).map(lambda r: r * R0)


@given(alphas, radii)
def test_interaction_is_the_model_formula(alpha, R):
    assert ms.interaction(alpha, R, B, KT, R0) == pytest.approx(w_model(alpha, R), rel=1e-12, abs=0)


def test_interaction_pieces_and_limits():
    # at R = r0 and x -> infinity (alpha -> 0) the hard core gives kT/r0 exactly; the
    # entropic term approaches its limit as x^(-2/3) (1.2e-7 relative at alpha = 1e-9,
    # which the default abs=1e-12 of pytest.approx hid), 1e-11 at alpha = 1e-16
    w = ms.interaction(1e-16, R0, B, KT, R0)
    entropic = B ** (-1 / 3) * KT ** (4 / 3) / R0 ** (2 / 3)
    assert w == pytest.approx(KT / R0 + entropic, rel=1e-9, abs=0)
    # steep repulsion: halving R multiplies the hard-core term by 4096
    a = 0.3
    assert ms.interaction(a, R0 / 2, B, KT, R0) > 1000 * ms.interaction(a, R0, B, KT, R0)


@given(alphas, radii)
def test_partials_match_finite_differences(alpha, R):
    w_a, w_r = ms.interaction_partials(alpha, R, B, KT, R0)
    ha, hr = 1e-6 * alpha, 1e-6 * R
    fd_a = (w_model(alpha + ha, R) - w_model(alpha - ha, R)) / (2 * ha)
    fd_r = (w_model(alpha, R + hr) - w_model(alpha, R - hr)) / (2 * hr)
    assert w_a == pytest.approx(fd_a, rel=1e-6, abs=1e-12 * abs(w_model(alpha, R)))
    assert w_r == pytest.approx(fd_r, rel=1e-6)


@given(alphas, radii)
def test_second_partials_match_finite_differences(alpha, R):
    w_aa, w_ar, w_rr = ms.interaction_second_partials(alpha, R, B, KT, R0)
    ha, hr = 1e-6 * alpha, 1e-6 * R
    pa = ms.interaction_partials(alpha + ha, R, B, KT, R0)
    ma = ms.interaction_partials(alpha - ha, R, B, KT, R0)
    pr = ms.interaction_partials(alpha, R + hr, B, KT, R0)
    mr = ms.interaction_partials(alpha, R - hr, B, KT, R0)
    scale_a = abs(ms.interaction_partials(alpha, R, B, KT, R0)[0]) / alpha
    assert w_aa == pytest.approx((pa[0] - ma[0]) / (2 * ha), rel=1e-5, abs=1e-8 * scale_a)
    assert w_ar == pytest.approx((pr[0] - mr[0]) / (2 * hr), rel=1e-5, abs=1e-8 * scale_a / R)
    assert w_ar == pytest.approx((pa[1] - ma[1]) / (2 * ha), rel=1e-5, abs=1e-8 * scale_a / R)
    assert w_rr == pytest.approx((pr[1] - mr[1]) / (2 * hr), rel=1e-5)


def test_vectorised_and_reduced_units():
    a = np.linspace(0.1, 1.2, 7)[:, None]
    R = np.linspace(1.0, 5.0, 5)[None, :] * R0
    w = ms.interaction(a, R, B, KT, R0)
    assert w.shape == (7, 5)
    beta = (B / (KT * R0)) ** (-1 / 3)
    np.testing.assert_allclose(w * R0 / KT, ms.reduced_interaction(a, R / R0, beta), rtol=1e-13)
    # w > 0 and decreasing in R (repulsion) everywhere
    assert np.all(w > 0)
    assert np.all(ms.interaction_partials(a, R, B, KT, R0)[1] < 0)
