"""Torque-melted DNA: the denatured phase of negatively twisted DNA and its melting torque.

docs/theory/melting.md#melted-phase. Float-only kernel (SI units, broadcasting).

Per B-DNA contour length, relative to relaxed B-DNA (a bubble of two single strands that
share the force):

    phi_m(F, M) = Delta - Omega_m M - M^2 / (2 kT c_m) - g_m(F)

* ``Delta`` (N = J/m): melting free energy per B contour length at zero force and torque;
* ``Omega_m`` (rad/m, negative): twist density of the melted state relative to B-DNA,
  ``-2 pi / h`` when the strands are fully unwound (h: helical repeat, m per turn);
* ``c_m`` (m): twist persistence length of the melted state (soft);
* ``g_m(F) = (n / r) [l (kT/b) ln(sinh(u)/u) + l f^2 / (2 S)]`` with ``f = F/n``,
  ``u = f b / kT``: n strands in parallel, each an extensible freely jointed chain (Kuhn
  length b, contour l per nucleotide, stretch modulus S; additive enthalpic term), r the
  B-DNA rise per base pair. ``dg_m/dF = (l/r) [L(u) + f/S]`` with L the Langevin function.

Coexistence with the stretched phase ``phi_s = -g_s(F) - M^2/(2 kT c_s(F))``
(:mod:`supercoil.core.dna.twist_bend`) at ``phi_s = phi_m``:
``a M^2 + Omega_m M - D = 0`` with ``a = (1/c_m - 1/c_s)/(2 kT)``, ``D = Delta + g_s - g_m``;
the negative root ``M_melt = -2 D / (|Omega_m| + sqrt(Omega_m^2 + 4 a D))``
[melting.md#melting-torque].
"""

from __future__ import annotations

import numpy as np

from supercoil.exceptions import ValidityError

from . import twist_bend as _tb
from .phases import PhaseGibbs, simple_melted_gibbs

__all__ = [
    "DEFAULTS",
    "melted_gibbs",
    "melted_stretch_gain",
    "melting_torque",
    "plectoneme_melted_gibbs",
    "tail_melted_gibbs",
]

_KT_296 = 1.380649e-23 * 296.15  # kT at 23 C (J), the temperature of the Qian et al. data
_RISE = 0.34e-9  # B-DNA contour per bp (m)

#: Defaults of the melted phase (SI), each with its source [melting.md#parameters].
DEFAULTS = {
    # Delta: calibrated, not read from a source: chosen so that the coexistence torque
    # with the defaults below (A = 50 nm, C = 100 nm, G = 0, 23 C) is -10.5 pN nm at
    # 1 pN, the value of table: Figure S5D source data of Qian et al. (bioRxiv
    # 10.1101/2024.10.15.618270, 2024), (-) supercoiling column. 1.52 kT per bp
    # (docs/theory/melting.md#calibration). A fit parameter of the model.
    "melt_free_energy": 1.52 * _KT_296 / _RISE,  # N (J/m of B contour)
    # Omega_m: full unwinding, -2 pi per helical repeat h = 3.57 nm (10.5 bp), the
    # package's convention (docs/theory/conventions.md)
    "melt_twist": -2.0 * np.pi / 3.57e-9,  # rad/m
    # c_m: assumed soft twist persistence of the bubble; no measured value read. It sets
    # only the torque dependence of the melted twist (fit parameter)
    "melt_twist_stiffness": 20e-9,  # m
    # ssDNA elasticity: extensible freely jointed chain of persistence 7.5 A (Kuhn length
    # 1.5 nm) and stretch modulus 800 pN (Smith, Cui & Bustamante, Science 271, 795,
    # 1996, abstract); contour 0.56 nm per base and dsDNA rise 0.34 nm/bp (figure 2
    # caption of the force-induced-melting study PMC33432 at pmc.ncbi.nlm.nih.gov, text
    # of the caption; melting.md#sources-and-what-was-read)
    "ss_kuhn_length": 1.5e-9,  # m
    "ss_contour_per_base": 0.56e-9,  # m
    "ss_stretch_modulus": 800e-12,  # N
    "rise_per_bp": _RISE,  # m
    # two single strands in parallel carry the force in a bubble (geometry)
    "strands": 2.0,
}


def _log_sinhc(u):
    """``ln(sinh(u)/u)`` for u >= 0, without cancellation or overflow."""
    small = u < 1e-2
    us = np.where(small, 1.0, u)
    big = u + np.log1p(-np.exp(-2.0 * us)) - np.log(2.0 * us)
    u2 = u * u
    ser = u2 / 6.0 - u2 * u2 / 180.0 + u2 * u2 * u2 / 2835.0
    return np.where(small, ser, big)


def _langevin(u):
    """``coth(u) - 1/u`` for u >= 0."""
    small = u < 1e-2
    us = np.where(small, 1.0, u)
    big = 1.0 / np.tanh(us) - 1.0 / us
    u2 = u * u
    ser = u / 3.0 - u * u2 / 45.0 + 2.0 * u * u2 * u2 / 945.0
    return np.where(small, ser, big)


def melted_stretch_gain(F, kT, ss_kuhn_length, ss_contour_per_base, ss_stretch_modulus,
                        rise_per_bp, strands=2.0):
    """``g_m(F)`` (N) and ``x_m = dg_m/dF`` (1) of the melted state per B contour length.

    Implements docs/theory/melting.md (MT7).
    """
    f = _tb.check_force(F, "melted-DNA stretching", allow_zero=True) / strands
    b, ell = ss_kuhn_length, ss_contour_per_base
    u = f * b / kT
    per_base = ell * kT / b * _log_sinhc(u) + ell * f * f / (2.0 * ss_stretch_modulus)
    g = strands * per_base / rise_per_bp
    x = ell * (_langevin(u) + f / ss_stretch_modulus) / rise_per_bp
    return g, x


def melted_gibbs(F, M, kT, melt_free_energy=DEFAULTS["melt_free_energy"],
                 melt_twist=DEFAULTS["melt_twist"],
                 melt_twist_stiffness=DEFAULTS["melt_twist_stiffness"],
                 ss_kuhn_length=DEFAULTS["ss_kuhn_length"],
                 ss_contour_per_base=DEFAULTS["ss_contour_per_base"],
                 ss_stretch_modulus=DEFAULTS["ss_stretch_modulus"],
                 rise_per_bp=DEFAULTS["rise_per_bp"], strands=DEFAULTS["strands"]):
    """Melted phase: ``phi_m = Delta - Omega_m M - M^2/(2 kT c_m) - g_m(F)`` (N).

    Implements docs/theory/melting.md (MT6, MT7).

    Parameters
    ----------
    F : float or array
        Force (N), non-negative.
    M : float or array
        Torque (N m), broadcast with F.
    kT : float
        Thermal energy (J).
    melt_free_energy, melt_twist, melt_twist_stiffness : float
        Delta (N), Omega_m (rad/m), c_m (m); see :data:`DEFAULTS`.
    ss_kuhn_length, ss_contour_per_base, ss_stretch_modulus, rise_per_bp, strands : float
        Single-strand elasticity (m, m, N), B rise per bp (m), strands sharing the force.

    Returns
    -------
    PhaseGibbs
        ``phi`` (N), ``dphi_dF = -x_m``, ``dphi_dM = -(Omega_m + M/(kT c_m))`` (1/m),
        ``d2phi_dM2 = -1/(kT c_m)``.

    Raises
    ------
    ValidityError
        Naming the force where F < 0 or not finite, or a non-positive c_m.
    """
    F, M = np.broadcast_arrays(np.asarray(F, dtype=float), np.asarray(M, dtype=float))
    _check_twist_stiffness(melt_twist_stiffness)
    g, x = melted_stretch_gain(F, kT, ss_kuhn_length, ss_contour_per_base,
                               ss_stretch_modulus, rise_per_bp, strands)
    kc = kT * melt_twist_stiffness
    phi = melt_free_energy - melt_twist * M - M * M / (2.0 * kc) - g
    return PhaseGibbs(phi, -x, -(melt_twist + M / kc), np.full(F.shape, -1.0 / kc))


def _check_twist_stiffness(c_m):
    """ValidityError unless c_m > 0 (``inf``: a torsionally rigid melted phase)."""
    if not (np.isposinf(c_m) or np.all(np.asarray(c_m, float) > 0.0)):
        _tb.check_positive(c_m, "melt_twist_stiffness c_m", "melted DNA")


def tail_melted_gibbs(F, M, par):
    """The melted phase of the ensemble's tail (docs/theory/melting.md#the-ensembles-melted-phase).

    Implements docs/theory/melting.md (MT9).

    ``par``: :class:`supercoil.core.dna.ensemble.EnsembleParameters`. With
    ``melt_ss_elastic=False`` and ``melt_twist_stiffness=inf`` (the defaults) the linear
    phase ``e - x_m F - Omega_m M`` of :func:`~supercoil.core.dna.phases.simple_melted_gibbs`
    (bit-identical); ``melt_ss_elastic``: ``-x_m F`` becomes ``-g_m(F)`` of two single
    strands (:func:`melted_stretch_gain`, constants of :data:`DEFAULTS`); a finite
    ``melt_twist_stiffness`` c_m (m) adds ``-M^2/(2 kT c_m)``.
    """
    cm = par.melt_twist_stiffness
    if par.melt_ss_elastic:
        return melted_gibbs(F, M, par.kT, par.melt_energy, par.melt_twist, cm)
    m = simple_melted_gibbs(F, M, par.melt_energy, par.melt_extension, par.melt_twist)
    if np.isposinf(cm):
        return m
    _check_twist_stiffness(cm)
    kc = par.kT * cm
    return PhaseGibbs(m.phi - M * M / (2.0 * kc), m.dphi_dF, m.dphi_dM - M / kc,
                      m.d2phi_dM2 - 1.0 / kc)


def melting_torque(F, A, C, G, kT, writhe_factor=1.0, derivative=False, **melt):
    """Coexistence torque ``M_melt(F)`` (N m, negative) of stretched B-DNA with melted DNA.

    Implements docs/theory/melting.md (MT8).

    ``phi_s(F, M) = phi_m(F, M)`` solved in closed form (module docstring)
    [melting.md#melting-torque]. ``melt`` takes the keywords of :func:`melted_gibbs`.
    With ``derivative=True`` returns ``(M_melt, dM_melt/dF)`` (N m, m), the latter by
    implicit differentiation, ``dM/dF = (x_s - x_m) / (Omega_m - Omega_s)`` at M_melt:
    the Maxwell relation makes ``-2 pi dM/dF`` the extension change per turn on the
    melting plateau.

    Raises
    ------
    ValidityError
        Naming the force where F <= 0, where Omega_m >= 0, or where no coexistence
        exists (``D <= 0``: melted DNA stable at zero torque; or a negative discriminant).
    """
    p = {**DEFAULTS, **melt}
    F = _tb.check_force(F, "melting torque")
    om = p["melt_twist"]
    if not om < 0.0:
        raise ValidityError(f"melting torque: the melted twist Omega_m = {om:.4g} rad/m "
                            "must be negative (unwinding)")
    gs, _, _ = _tb.wlc_gibbs_gain(F, A, kT)
    cs, _ = _tb.effective_twist_stiffness(F, A, C, G, kT, writhe_factor)
    gm, _ = melted_stretch_gain(F, kT, p["ss_kuhn_length"], p["ss_contour_per_base"],
                                p["ss_stretch_modulus"], p["rise_per_bp"], p["strands"])
    D = p["melt_free_energy"] + gs - gm
    a = (1.0 / p["melt_twist_stiffness"] - 1.0 / cs) / (2.0 * kT)
    disc = om * om + 4.0 * a * D
    bad = ~(D > 0.0) | ~(disc >= 0.0)
    if np.any(bad):
        i = np.flatnonzero(np.broadcast_to(bad, np.shape(D)))[0]
        raise ValidityError(f"melting torque undefined at force {np.ravel(F)[i] * 1e12:.6g}"
                            " pN: no coexistence of B-DNA with melted DNA (Delta + g_s - g_m "
                            "must be positive and Omega_m^2 + 4 a D non-negative)")
    M = -2.0 * D / (-om + np.sqrt(disc))
    if not derivative:
        return M
    s_ = _tb.stretched_gibbs(F, M, A, C, G, kT, writhe_factor)
    m_ = melted_gibbs(F, M, kT, **{k: p[k] for k in DEFAULTS})
    return M, -(s_.dphi_dF - m_.dphi_dF) / (s_.dphi_dM - m_.dphi_dM)


def plectoneme_melted_gibbs(F, M, par):
    """Melted DNA inside a plectoneme: the tail's melted phase without the force terms.

    Implements docs/theory/melting.md (MT10).

    The plectoneme has no extension, so its melted segments gain no work from the force:
    ``phi = e - Omega_m M - M^2/(2 kT c_m)`` (:func:`tail_melted_gibbs` at ``F = 0``) and
    ``dphi/dF = 0`` (docs/theory/melting.md#bubbles-in-plectonemes).
    """
    F, M = np.broadcast_arrays(np.asarray(F, dtype=float), np.asarray(M, dtype=float))
    m = tail_melted_gibbs(np.zeros_like(F), M, par)
    return PhaseGibbs(m.phi + 0.0 * F, np.zeros_like(F), m.dphi_dM + 0.0 * F,
                      m.d2phi_dM2 + 0.0 * F)
