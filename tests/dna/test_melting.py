"""Torque-melted DNA and its melting torque (docs/theory/melting.md#melted-phase)."""

import numpy as np
import pytest
from scipy.optimize import brentq

from supercoil.core.dna import melting as m
from supercoil.core.dna import twist_bend as tb
from supercoil.exceptions import ValidityError

KT = 1.380649e-23 * 296.15
A, C = 50e-9, 100e-9
F = np.array([0.0, 1e-4, 0.02, 0.3, 1.0, 2.0, 4.0])[:, None] * 1e-12
M = np.array([-15.0, -10.0, 0.0, 5.0])[None, :] * 1e-21
FORCES = np.array([0.3, 0.5, 0.75, 1.0, 1.5, 2.0]) * 1e-12


def _fd(fun, x, h):
    return (fun(x + h) - fun(x - h)) / (2 * h)


def test_derivatives_against_finite_differences():
    p = m.melted_gibbs(F, M, KT)
    # the F dependence is g_m alone (phi's constant part would drown it at small F)
    Fp = F[1:, 0]  # central differences need F > 0
    d = m.DEFAULTS
    args = (KT, d["ss_kuhn_length"], d["ss_contour_per_base"], d["ss_stretch_modulus"],
            d["rise_per_bp"])
    dF = _fd(lambda f: m.melted_stretch_gain(f, *args)[0], Fp, 1e-5 * Fp)
    np.testing.assert_allclose(-p.dphi_dF[1:, 0], dF, rtol=1e-6)
    np.testing.assert_allclose(p.dphi_dF[1:], np.broadcast_to(p.dphi_dF[1:, :1], (6, 4)))
    big = F[3:]
    dphi = _fd(lambda f: m.melted_gibbs(f, M, KT).phi, big, 1e-4 * big)
    np.testing.assert_allclose(p.dphi_dF[3:], dphi, rtol=1e-6)
    hM = 1e-23
    dM = _fd(lambda x: m.melted_gibbs(F, x, KT).phi, M, hM)
    np.testing.assert_allclose(p.dphi_dM, dM, rtol=1e-6)
    d2 = _fd(lambda x: m.melted_gibbs(F, x, KT).dphi_dM, M, hM)
    np.testing.assert_allclose(p.d2phi_dM2, d2, rtol=1e-6)
    assert np.all(p.d2phi_dM2 < 0)


def test_series_branches_join_smoothly():
    u = np.array([1e-2 * (1 - 1e-12), 1e-2 * (1 + 1e-12)])
    assert m._log_sinhc(u)[0] == pytest.approx(m._log_sinhc(u)[1], rel=1e-9, abs=0)
    assert m._langevin(u)[0] == pytest.approx(m._langevin(u)[1], rel=1e-9)
    assert m._log_sinhc(np.array([800.0]))[0] == pytest.approx(800 - np.log(1600), rel=1e-15, abs=0)


def test_zero_force_and_torque_is_the_melting_free_energy():
    p = m.melted_gibbs(0.0, 0.0, KT)
    assert p.phi == m.DEFAULTS["melt_free_energy"]
    assert p.dphi_dF == 0.0
    assert -p.dphi_dM == m.DEFAULTS["melt_twist"]


def test_high_force_extension_of_the_single_strands():
    # two strands at F/2 each: x -> (l/r)(1 - kT/(f b) + f/S) per B contour length
    f = 60e-12
    x = -m.melted_gibbs(f, 0.0, KT).dphi_dF
    d = m.DEFAULTS
    fs = f / 2
    ref = d["ss_contour_per_base"] / d["rise_per_bp"] * (1 - KT / (fs * d["ss_kuhn_length"])
                                                          + fs / d["ss_stretch_modulus"])
    # coth(u) - 1 = 2 exp(-2u) / (1 - exp(-2u)) ~ 6e-10 at u = 11
    assert x == pytest.approx(ref, rel=2e-9)
    assert x != pytest.approx(ref, rel=1e-12)


def test_melting_torque_against_brentq():
    Mm = m.melting_torque(FORCES, A, C, 0.0, KT)
    for f, mm in zip(FORCES, Mm, strict=True):
        def diff(mp, f=f):
            return (tb.stretched_gibbs(f, mp * 1e-21, A, C, 0.0, KT).phi
                    - m.melted_gibbs(f, mp * 1e-21, KT).phi)
        ref = brentq(diff, -40.0, 0.0, xtol=1e-14) * 1e-21
        assert mm == pytest.approx(ref, rel=1e-10, abs=0)


def test_melting_torque_numbers_at_the_defaults():
    # -10.2 ... -10.9 pN nm over 0.3-2 pN: nearly force independent; -10.48 at 1 pN
    # (calibration point, docs/theory/melting.md#calibration)
    Mm = m.melting_torque(FORCES, A, C, 0.0, KT) * 1e21
    np.testing.assert_allclose(Mm, [-10.206, -10.281, -10.380, -10.480, -10.679, -10.869],
                               atol=2e-3)
    assert np.all(np.diff(Mm) < 0)


def test_rigid_melted_twist_and_linear_limit():
    # c_m = c_s(F) makes the equation linear: M = -D / |Omega_m|
    f = 1e-12
    cs = tb.effective_twist_stiffness(f, A, C, 0.0, KT)[0]
    Mm = m.melting_torque(f, A, C, 0.0, KT, melt_twist_stiffness=cs)
    gs = tb.wlc_gibbs_gain(f, A, KT)[0]
    d = m.DEFAULTS
    gm = m.melted_stretch_gain(f, KT, d["ss_kuhn_length"], d["ss_contour_per_base"],
                               d["ss_stretch_modulus"], d["rise_per_bp"])[0]
    assert Mm == pytest.approx(-(d["melt_free_energy"] + gs - gm) / -d["melt_twist"], rel=1e-12,
                               abs=0)


def test_broadcasting():
    p = m.melted_gibbs(F, M, KT)
    assert all(np.shape(a) == (F.size, M.size) for a in p)
    Mm = m.melting_torque(FORCES.reshape(2, 3), A, C, 0.0, KT)
    assert Mm.shape == (2, 3)


@pytest.mark.parametrize("bad", [-1e-12, np.nan, np.inf])
def test_bad_force_is_a_named_error(bad):
    with pytest.raises(ValidityError, match="force"):
        m.melted_gibbs(np.array([1e-12, bad]), 0.0, KT)


def test_melting_torque_needs_positive_force():
    with pytest.raises(ValidityError, match="force 0 pN"):
        m.melting_torque(np.array([1e-12, 0.0]), A, C, 0.0, KT)


def test_no_coexistence_is_a_named_error():
    with pytest.raises(ValidityError, match="no coexistence"):
        m.melting_torque(1e-12, A, C, 0.0, KT, melt_free_energy=-1.0)
    with pytest.raises(ValidityError, match="must be negative"):
        m.melting_torque(1e-12, A, C, 0.0, KT, melt_twist=1e9)
    with pytest.raises(ValidityError, match="c_m"):
        m.melted_gibbs(1e-12, 0.0, KT, melt_twist_stiffness=0.0)


def test_melting_torque_force_derivative_and_maxwell_slope():
    M, dM = m.melting_torque(FORCES, A, C, 0.0, KT, derivative=True)
    h = 1e-5 * FORCES
    fd = (m.melting_torque(FORCES + h, A, C, 0.0, KT)
          - m.melting_torque(FORCES - h, A, C, 0.0, KT)) / (2 * h)
    np.testing.assert_allclose(dM, fd, rtol=1e-6)
    np.testing.assert_array_equal(M, m.melting_torque(FORCES, A, C, 0.0, KT))
    # Maxwell: -2 pi dM/dF = extension lost per melted turn, (x_s - x_m) / (per-turn
    # twist difference); at 1 pN about 2.5 nm per turn (docs/theory/melting.md#calibration)
    slope = -2 * np.pi * dM
    assert np.all((slope > 2.0e-9) & (slope < 3.0e-9))
