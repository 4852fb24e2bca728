"""Marko's (2007) two-phase model: closed forms, Maxwell relation, phases, validity.

References used here, independent of the kernel's code path:
* the closed forms transcribed in pN and nm from the public MATLAB
  re-implementation ``WLC_z_G_twist.m`` / ``DNA_fiber_twisted.m`` of
  github.com/arturrsl/MT-chromatin-torsionally-constrained (A. Kaczmarczyk,
  2018): ``tau_buck = sqrt(2 kbT Cp g / (1 - Cp/Ct))``, ``Lk_buck = tau_buck L /
  (2 pi kbT Ct)``, ``z_slope`` and ``z_WLC``;
* finite differences of G (z = -dG/dF, M = dG/dN / 2 pi) and of M (Maxwell);
* the package's Moroz-Nelson C_eff (c_s is its first-order expansion).
"""

import pickle

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import supercoil
from supercoil.core.dna import interface as iface
from supercoil.core.dna import marko2007 as mk
from supercoil.core.dna import moroz_nelson as mn
from supercoil.dna.models.marko2007 import Marko2007
from supercoil.exceptions import ValidityError

KB = 1.380649e-23
TWO_PI = 2 * np.pi


def _dna(A=48.0, C=86.0, L=750.0, T=300.0):
    u = supercoil.ureg
    return supercoil.DNA(length=L * u.nm, bending_persistence=A * u.nm,
                         twist_persistence=C * u.nm, radius=1.75 * u.nm,
                         temperature=T * u.K).si


def _matlab(f, L, A, C, Cp, kbT):
    """The MATLAB re-implementation's formulas, in pN, nm, pN nm (turn counts)."""
    Ct = C * (1 - C / (4 * A) * np.sqrt(kbT / (A * f)))
    g = f - np.sqrt(f * kbT / A)
    tau_buck = np.sqrt(2 * kbT * Cp * g / (1 - Cp / Ct))
    lk_buck = tau_buck * L / (2 * np.pi * kbT * Ct)
    z_slope = (2 * np.pi * (1 - 0.5 * np.sqrt(kbT / (A * f)) - C**2 / (16 * Ct**2)
                            * (kbT / (A * f)) ** 1.5 * (tau_buck / kbT) ** 2)
               / ((tau_buck / kbT) * (1 / Cp - 1 / Ct)))
    return tau_buck, lk_buck, z_slope, Ct


def _z_wlc(f, L, A, C, dlk, kbT):
    return L * ((1 - 0.5 * np.sqrt(kbT / (A * f)))
                - (C**2 / 16) * (2 * np.pi * dlk / L) ** 2 * (kbT / (A * f)) ** 1.5)


@pytest.mark.parametrize(("A", "C", "P"), [(48.0, 86.0, 24.0), (50.0, 100.0, 24.0)])
def test_closed_forms_match_the_matlab_reimplementation(A, C, P):
    dna = _dna(A, C, T=4.114e-21 / KB)  # the MATLAB code's kbT = 4.114 pN nm
    f = np.array([0.5, 1.0, 2.0, 3.0, 4.0])
    tau, lk, slope, Ct = _matlab(f, 750.0, A, C, P, 4.114)
    par = Marko2007(plectoneme_twist_persistence=P * 1e-9).parameters_at(f * 1e-12, dna, True)
    np.testing.assert_allclose(par.torque * 1e21, tau, rtol=1e-12)
    np.testing.assert_allclose(par.buckling_turns, lk, rtol=1e-12)
    np.testing.assert_allclose(-par.slope * 1e9, slope, rtol=1e-12)
    np.testing.assert_allclose(par.twist_stiffness * 1e9, Ct, rtol=1e-12)
    # stretched extension at 3 turns (below buckling at every force here)
    pt = mk.points(3.0, f * 1e-12, dna.length, dna.bending_persistence,
                   dna.twist_persistence, P * 1e-9, dna.kT)
    assert np.all(pt.phase == iface.STRETCHED)
    np.testing.assert_allclose(pt.extension * 1e9, _z_wlc(f, 750.0, A, C, 3.0, 4.114),
                               rtol=1e-12)


def test_stretched_twist_stiffness_is_first_order_moroz_nelson():
    dna = _dna()
    f = np.array([0.5, 1.0, 4.0]) * 1e-12
    cs, _ = mk.stretched_twist_stiffness(f, dna.bending_persistence, dna.twist_persistence,
                                         dna.kT)
    ceff = mn.effective_twist_rigidity(f, dna.bending_rigidity, dna.torsional_rigidity, dna.kT)
    x = mn.twist_rigidity_ratio(f, dna.bending_rigidity, dna.torsional_rigidity, dna.kT) - 1
    # (1 - x) (1 + x) = 1 - x^2
    np.testing.assert_allclose(cs * dna.kT / ceff, 1 - x**2, rtol=1e-13)


def _fd(fun, x, h):
    return (fun(x + h) - fun(x - h)) / (2 * h)


@pytest.mark.parametrize("thermal", [True, False])
@pytest.mark.parametrize("loop", [False, True])
def test_extension_and_torque_are_derivatives_of_G(thermal, loop):
    """z = -dG/dF, M = dG/dN / 2pi (central differences, relative step 1e-5).

    Step: G is smooth inside each phase; the central-difference truncation error
    is ~(h/F)^2 = 1e-10 relative and the round-off ~1e-16/1e-5 = 1e-11, so 1e-7
    is a safe bound. The turns sit at least 0.2 turn from every phase boundary.
    """
    dna = _dna()
    m = Marko2007(end_loop=loop)
    F = 2e-12
    par = m.parameters_at(np.array([F]), dna, thermal)
    nfull = (par.loop_writhe + par.omega_plectoneme * (dna.length - par.loop_length)
             / TWO_PI)[0]
    N = np.array([0.7, 3.0, par.jump_turns[0] - 0.5, par.jump_turns[0] + 0.5,
                  0.5 * (par.jump_turns[0] + nfull), nfull + 2.0, nfull + 10.0])
    N = np.concatenate([N, -N])
    pt = m.points(N, np.full(N.shape, F), dna, thermal)
    assert set(pt.phase) == {0, 1, 2}
    G = lambda f: m.free_energy(N, np.full(N.shape, f), dna, thermal)  # noqa: E731
    z = -_fd(G, F, 1e-5 * F)
    np.testing.assert_allclose(z, pt.extension, rtol=1e-7, atol=1e-7 * dna.length)
    GN = lambda n: m.free_energy(n, np.full(N.shape, F), dna, thermal)  # noqa: E731
    M = _fd(GN, N, 1e-5) / TWO_PI
    np.testing.assert_allclose(M, pt.torque, rtol=1e-7)


@pytest.mark.parametrize("thermal", [True, False])
@pytest.mark.parametrize("loop", [False, True])
def test_maxwell_relation_in_every_phase(thermal, loop):
    """dz/dN|_F = -2 pi dM/dF|_N to 1e-6 relative (or both zero, fully coiled)."""
    dna = _dna()
    m = Marko2007(end_loop=loop)
    F = np.array([1.0, 2.0, 3.5]) * 1e-12
    par = m.parameters_at(F, dna, thermal)
    nfull = par.loop_writhe + par.omega_plectoneme * (dna.length - par.loop_length) / TWO_PI
    for i, f in enumerate(F):
        N = np.array([1.5, par.jump_turns[i] - 0.6, par.jump_turns[i] + 0.6,
                      0.5 * (par.jump_turns[i] + nfull[i]), nfull[i] + 3.0])
        dzdN = _fd(lambda n, f=f: m.points(n, np.full(n.shape, f), dna, thermal).extension,
                   N, 1e-3)
        dMdF = _fd(lambda x, N=N: m.points(N, np.full(N.shape, x), dna, thermal).torque,
                   f, 1e-5 * f)
        scale = np.abs(par.slope[i]) * 1e-6
        np.testing.assert_allclose(dzdN, -TWO_PI * dMdF, rtol=1e-6, atol=scale)
        pt = m.points(N, np.full(N.shape, f), dna, thermal)
        assert list(pt.phase) == [0, 0, 1, 1, 2]


@given(f=st.floats(0.4, 8.0), P=st.floats(10.0, 40.0), thermal=st.booleans())
def test_slope_is_minus_two_pi_dMb_dF(f, P, thermal):
    """Marko's slope -2 pi zhat_s / (Omega_p - Omega_s) equals -2 pi dM_b/dF (Maxwell)."""
    par = Marko2007(plectoneme_twist_persistence=P * 1e-9).parameters_at(
        np.array([f * 1e-12]), _dna(), thermal)
    np.testing.assert_allclose(par.slope, -TWO_PI * par.torque_prime, rtol=1e-10)


def test_athermal_limit():
    dna = _dna()
    F, P = 2e-12, 24e-9
    par = Marko2007().parameters_at(np.array([F]), dna, False)
    C = dna.twist_persistence
    M = np.sqrt(2 * P * dna.kT * F / (1 - P / C))
    np.testing.assert_allclose(par.torque, M, rtol=1e-14)
    np.testing.assert_allclose(par.slope, -TWO_PI * M / (2 * F), rtol=1e-12)
    pt = Marko2007().points(np.array([0.0, 2.0]), np.full(2, F), dna, False)
    np.testing.assert_allclose(pt.extension, dna.length, rtol=1e-15)
    np.testing.assert_allclose(pt.free_energy[0], -F * dna.length, rtol=1e-15)


@pytest.mark.parametrize("thermal", [True, False])
def test_free_energy_continuous_and_smooth_at_phase_boundaries(thermal):
    dna = _dna()
    m = Marko2007()
    F = np.array([1.0, 3.0]) * 1e-12
    par = m.parameters_at(F, dna, thermal)
    L, K = dna.length, m.values["plectoneme_twist_persistence"] * dna.kT
    Nb = par.buckling_turns
    Gb = m.free_energy(Nb, F, dna, thermal)  # stretched branch at N_b
    np.testing.assert_allclose(Gb, -L * par.gamma + TWO_PI * par.torque * Nb, rtol=1e-12)
    Np = L * par.omega_plectoneme / TWO_PI
    line = -L * par.gamma + TWO_PI * par.torque * Np
    np.testing.assert_allclose(0.5 * K * (TWO_PI * Np / L) ** 2 * L, line, rtol=1e-12)
    # extension and torque continuous at N_b (no jump without the end loop)
    d = 1e-7
    lo = m.points(Nb - d, F, dna, thermal)
    hi = m.points(Nb + d, F, dna, thermal)
    np.testing.assert_allclose(lo.extension, hi.extension, rtol=1e-7)
    np.testing.assert_allclose(lo.torque, hi.torque, rtol=1e-7)


def test_symmetry_in_turns():
    dna = _dna()
    for m in (Marko2007(), Marko2007(end_loop=True)):
        N = np.linspace(0.3, 40, 57)
        F = np.full(N.shape, 1.5e-12)
        a, b = m.points(N, F, dna, True), m.points(-N, F, dna, True)
        np.testing.assert_array_equal(a.extension, b.extension)
        np.testing.assert_array_equal(a.free_energy, b.free_energy)
        np.testing.assert_array_equal(a.torque, -b.torque)
        np.testing.assert_array_equal(a.phase, b.phase)


def test_validity_errors_name_the_quantity_and_limit():
    dna = _dna()
    m = Marko2007()
    with pytest.raises(ValidityError, match=r"g\(F\).*kT/A"):
        m.parameters_at(np.array([0.05e-12]), dna, True)
    with pytest.raises(ValidityError, match=r"c_s.*P = 80 nm"):
        Marko2007(plectoneme_twist_persistence=80e-9).parameters_at(
            np.array([1e-12]), dna, True)
    # athermal: c_s = C = 70 nm < P -> same error
    with pytest.raises(ValidityError, match="no buckling"):
        Marko2007(plectoneme_twist_persistence=60e-9).replace(
            plectoneme_twist_persistence=75e-9).parameters_at(np.array([1e-12]),
                                                              _dna(C=70.0), False)
    # low-force warning messages (the public layer warns them)
    msgs = m._validity(None, np.array([0.2e-12, 1e-12]), None, dna, True)
    assert msgs and "kT/A" in msgs[0]
    assert m._validity(None, np.array([1e-12]), None, dna, True) == []
    assert m._validity(None, np.array([0.2e-12]), None, dna, False) == []


def test_model_object():
    u = supercoil.ureg
    m = Marko2007(plectoneme_twist_persistence=0.024 * u.um)
    assert m.values["plectoneme_twist_persistence"] == pytest.approx(24e-9, rel=1e-15, abs=0)
    assert m == Marko2007()
    assert pickle.loads(pickle.dumps(Marko2007(end_loop=True))) == Marko2007(end_loop=True)
    assert m.replace(end_loop=True).end_loop and not m.end_loop
    assert m.replace(end_loop=True).options() == {"end_loop": True}
    assert m.replace(end_loop=True) != m
    assert m.has_free_energy(True) and m.has_free_energy(False)
    assert Marko2007.name == "marko2007" and not Marko2007.uses_interaction
    with pytest.raises(TypeError, match="end_loop"):
        Marko2007(end_loop="yes")
    with pytest.raises(TypeError, match="no parameter"):
        Marko2007(persistence=3.0)
    with pytest.raises(ValueError, match="allowed range"):
        Marko2007(plectoneme_twist_persistence=200 * u.nm)
    with pytest.raises(AttributeError):
        m.end_loop = True
    # unit invariance at the model level: P in nm or um gives the same curve
    dna = _dna()
    N, F = np.linspace(-30, 30, 31), np.full(31, 2e-12)
    a = m.points(N, F, dna, True)
    b = Marko2007(plectoneme_twist_persistence=24 * u.nm).points(N, F, dna, True)
    np.testing.assert_allclose(a.extension, b.extension, rtol=1e-14)
    # plectoneme length is what is not in the tail; short tails flagged
    assert np.all(a.plectoneme_length[a.phase == 0] == 0)
    assert np.all(a.short_tail[a.phase == 2])


# ---- public layer (model="marko2007") -------------------------------------------------
def test_public_layer_units_and_registry():
    u = supercoil.ureg
    dna = supercoil.load_parameters("dna")
    turns = np.linspace(0, 30, 13)
    a = supercoil.hat_curve(dna, [1.0, 2.5] * u.pN, turns, model="marko2007")
    b = supercoil.hat_curve(dna.replace(length=0.75 * u.um), [1e-12, 2.5e-12] * u.N,
                            turns * 2 * np.pi * u.rad, model=Marko2007())
    for col in ("extension", "torque", "free_energy", "plectoneme_length"):
        np.testing.assert_allclose(a[col], b[col], rtol=1e-12, atol=1e-12)
    # the table is the kernel's numbers in display units
    pt = Marko2007().points(np.tile(turns, 2), np.repeat([1e-12, 2.5e-12], 13), dna.si, True)
    np.testing.assert_allclose(a["extension"], pt.extension * 1e9, rtol=1e-13)
    np.testing.assert_allclose(a["free_energy"], pt.free_energy * 1e21, rtol=1e-13)
    nb = supercoil.buckling_turns(dna, 2 * u.pN, model="marko2007")
    slope = supercoil.post_buckling_slope(dna, 2 * u.pN, model="marko2007")
    par = Marko2007().parameters_at(np.array([2e-12]), dna.si, True)
    assert nb.to("turn").magnitude[0] == pytest.approx(par.buckling_turns[0], rel=1e-13, abs=0)
    assert slope.to("nm/turn").magnitude[0] == pytest.approx(par.slope[0] * 1e9, rel=1e-13)
    looped = supercoil.buckling_turns(dna, 2 * u.pN, model=Marko2007(end_loop=True))
    assert looped.magnitude[0] > nb.magnitude[0]


def test_public_layer_failures():
    u = supercoil.ureg
    dna = supercoil.load_parameters("dna")
    with pytest.raises(supercoil.exceptions.ModelError, match="no plectoneme helix state"):
        supercoil.hat_curve(dna, 1 * u.pN, [5.0], model="marko2007", interaction="screened")
    with pytest.raises(ValidityError, match="kT/A"):
        supercoil.hat_curve(dna, 0.05 * u.pN, [5.0], model="marko2007")
    with pytest.warns(supercoil.ValidityWarning, match="marko2007: force 0.3 pN"):
        supercoil.hat_curve(dna, 0.3 * u.pN, [2.0], model="marko2007")


@pytest.mark.parametrize("end_loop", [False, True])
def test_blocked_points_equal_one_block(monkeypatch, end_loop):
    """Points computed in blocks (bounded temporaries) equal one unblocked pass, bit for
    bit, every phase, mixed forces, with and without the end loop."""
    dna = _dna()
    N = np.tile(np.linspace(-40, 40, 301), 3)
    F = np.repeat(np.array([0.5, 1.0, 3.0]) * 1e-12, 301)
    args = (dna.length, dna.bending_persistence, dna.twist_persistence, 24e-9, dna.kT, True,
            end_loop)
    whole = mk.points(N, F, *args)
    assert set(whole.phase.tolist()) == {iface.STRETCHED, iface.PLECTONEME, iface.FULLY_COILED}
    monkeypatch.setattr(mk, "BLOCK", 7)
    blocked = mk.points(N, F, *args)
    for name, a, b in zip(whole._fields, whole, blocked, strict=True):
        assert a.dtype == b.dtype, name
        np.testing.assert_array_equal(b, a, err_msg=name)
    shaped = mk.points(N.reshape(3, 301), F.reshape(3, 301), *args)  # any shape, blocked
    np.testing.assert_array_equal(shaped.extension.ravel(), whole.extension)
