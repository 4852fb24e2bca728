"""The phase-ensemble model of real DNA rotation curves (float kernel, SI units).

Derivation and sources: docs/theory/ensemble.md. The molecule (contour L, turns N,
force F) is a tail (stretched worm-like chain that may melt cooperatively,
:func:`supercoil.core.dna.phases.two_state_gibbs`) plus ``m = 0, 1, ..., m_max``
plectoneme domains of total length ``Lp``, each with an end loop
(:func:`~supercoil.core.dna.phases.end_loop_gibbs`). One configuration ``(m, Lp,
chirality)`` at fixed N has the Legendre free energy

    G_c(N) = max_M [ (L - Lp) phi_t(F, M) + Lp phi_p(M) + m eps(F, M) + 2 pi M N ]
             - kT ln w_m(Lp)                                   [ensemble.md#32-fixed-turns]

with the positional weight ``w_m = (Ls/b)^m/m! (Lp/b)^(m-1)/(m-1)! dLp/b``; the
molecule's free energy is ``G = -kT ln sum_c exp(-G_c/kT)`` over the configurations
(midpoint nodes in Lp). Extension and torque are the Boltzmann averages of each
configuration's ``z_c = -dG_c/dF`` and ``M_c`` (its stationary torque), which are
exactly ``-dG/dF`` and ``dG/dN / 2 pi`` of the discrete sum, so the Maxwell relation
holds to the root solver's tolerance [ensemble.md#33-maxwell].

``finite_size=False`` is the thermodynamic limit without domains' entropy or loops:
the common-tangent coexistence of the tail and the plectoneme (Marko 2007 for
constant P, Marko's g and first-order c_s) [ensemble.md#4-limits].
"""

from __future__ import annotations

from math import factorial
from typing import NamedTuple

import numpy as np

from supercoil.core.numerics import find_root
from supercoil.exceptions import ValidityError

from . import ensemble_roots as _roots
from . import melting as _melt
from . import phases as _ph
from .ensemble_roots import TORQUE_BRACKET

__all__ = ["EnsembleParameters", "EnsemblePoints", "coexistence_torque", "configuration",
           "plectoneme_phase", "points", "tail_gibbs"]

_TWO_PI = 2.0 * np.pi
#: configurations provably more than PRUNE_KT kT above the best one are not solved
#: (each weighs less than exp(-PRUNE_KT) = 9e-27 of it) [ensemble.md#34-numerics]
PRUNE_KT = 60.0
_TINY_TORQUE = 1e-40


class EnsembleParameters(NamedTuple):
    """Float parameters of the kernel (SI)."""

    length: float  # L, m
    A: float  # bending persistence, m
    C: float  # twist persistence, m
    kT: float  # J
    softening: float = 1.0  # factor on the Moroz-Nelson term of 1/c_s
    P0: float = 24e-9  # plectoneme twist stiffness at M0, m
    exponent: float = 0.0  # a of P(M) = P0 (M/M0)^a
    M0: float = 1e-20  # reference torque, N m
    nucleation: float = 0.0  # extra free energy per domain, J
    writhe: float = 1.0  # turns absorbed by each end loop's writhe
    melt_energy: float = np.inf  # melted phase's free energy per B-DNA length at F = M = 0, J/m
    melt_cooperativity: float = 0.0  # boundary cost of a bubble (both ends), J
    melt_extension: float = 0.0  # x_m
    melt_twist: float = -_TWO_PI / (10.5 * 0.34e-9)  # Omega_m, rad/m
    segment: float = 0.34e-9  # Zimm-Bragg segment (one base pair), m
    microscopic_length: float = 1e-9  # b of the positional weight, m
    exact_wlc: bool = True
    resummed: bool = True
    physical_loop: bool = True
    max_domains: int = 2
    nodes: int = 70
    finite_size: bool = True
    # melted phase beyond the linear one (docs/theory/melting.md#the-ensembles-melted-phase);
    # the defaults give the linear melted phase bit-identically
    melt_ss_elastic: bool = False  # x_m(F) of two single strands (freely jointed chains)
    melt_twist_stiffness: float = np.inf  # c_m of the melted phase, m (inf: rigid)
    plectoneme_melting: bool = False  # bubbles inside the plectoneme too (no extension there)
    #: (M_k, T_k, tau_k) of a superhelix at fixed torque (phases.tabulated_plectoneme_gibbs)
    #: in place of the power law P(M); None: the power law
    plectoneme_table: tuple | None = None
    #: the stretched phase at the Moroz-Nelson effective tension (phases.effective_tension_gibbs)
    effective_tension: bool = False


class EnsemblePoints(NamedTuple):
    """Ensemble averages at each (N, F) (SI arrays of the points' shape)."""

    extension: np.ndarray  # <z>, m
    torque: np.ndarray  # <M>, N m
    free_energy: np.ndarray  # G(N, F), J
    plectoneme_length: np.ndarray  # <Lp>, m
    melted_length: np.ndarray  # <(L - Lp) theta>, m
    domains: np.ndarray  # <m>
    stretched_probability: np.ndarray  # P(m = 0) (limit: 1 stretched, 0 else)


def tail_gibbs(F, M, par, wlc=None):
    """The tail phase: stretched WLC, cooperatively mixed with the melted phase.

    ``wlc``: ``(g, x)`` of the exact WLC at ``F`` (computed if None).
    Returns ``(PhaseGibbs, theta)`` (theta the melted fraction).
    """
    s = _ph.stretched_gibbs(F, M, par.A, par.C, par.kT, par.softening, par.exact_wlc,
                            par.resummed, wlc, par.effective_tension)
    if not np.isfinite(par.melt_energy):
        return s, np.zeros(np.shape(s.phi))
    m = _melt.tail_melted_gibbs(F, M, par)  # the melted phase (melting.py)
    return _ph.two_state_gibbs(s, m, par.segment, par.melt_cooperativity, par.kT)


def plectoneme_phase(F, M, par):
    """The plectoneme phase's Gibbs energy and derivatives at force ``F`` and torque ``M``
    (SI; a torque below the smallest resolved one is raised to it)."""
    M = np.where(np.abs(M) < _TINY_TORQUE, _TINY_TORQUE, M)
    if par.plectoneme_table is not None:
        p = _ph.tabulated_plectoneme_gibbs(F, M, par.plectoneme_table, par.C, par.kT)
    else:
        p = _ph.plectoneme_gibbs(F, M, par.P0, par.exponent, par.M0, par.kT)
    if par.plectoneme_melting and np.isfinite(par.melt_energy):  # bubbles in the plectoneme
        p = _ph.two_state_gibbs(p, _melt.plectoneme_melted_gibbs(F, M, par), par.segment,
                                par.melt_cooperativity, par.kT)[0]
    return p


def wlc_at(F, par):
    """``(g, x)`` of the exact WLC at F (None for Marko's expansion)."""
    return _ph.wlc_exact_free_energy_gain(F, par.A, par.kT) if par.exact_wlc else None


def configuration(F, M, par, Lp, m, chirality, wlc=None):
    """One configuration ``(m, Lp, chirality)`` at torque ``M`` (SI arrays).

    Returns ``(Phi, link, z, theta, dlink)``: Phi(M) (J), the linking ``-dPhi/dM``
    (rad), the extension ``-dPhi/dF`` (m), the tail's melted fraction and the linking's
    slope ``-d^2 Phi/dM^2`` (rad/(N m)) [ensemble.md#32-fixed-turns].
    """
    t, theta = tail_gibbs(F, M, par, wlc)
    p = plectoneme_phase(F, M, par)
    Ls = par.length - Lp
    Phi = Ls * t.phi + Lp * p.phi
    link = -(Ls * t.dphi_dM + Lp * p.dphi_dM)
    dlink = -(Ls * t.d2phi_dM2 + Lp * p.d2phi_dM2)
    z = -Ls * t.dphi_dF
    if np.ndim(m) or m:  # m (and chirality) an array: configurations of several groups
        e, e_F, e_M = _ph.end_loop_gibbs(t, M, par.A, par.C, par.kT, par.writhe, chirality,
                                         par.nucleation, par.physical_loop)
        s = _ph.end_loop_torque_slope(t, M, par.A, par.C, par.kT, par.physical_loop)
        loop = (Phi + m * e, link - m * e_M, z - m * e_F, dlink - m * s)
        if np.ndim(m):  # those without a domain keep their own terms (their loop may be NaN)
            loop = tuple(np.where(np.asarray(m) > 0, a, b)
                         for a, b in zip(loop, (Phi, link, z, dlink), strict=True))
        Phi, link, z, dlink = loop
    return Phi, link, z, theta, dlink


def points(turns, force, par):
    """Ensemble extension, torque and free energy at (N, F) (1-D arrays, same shape).

    Implements docs/theory/ensemble.md (E6, E7); the torque of each configuration from
    the linking tables of :mod:`supercoil.core.dna.ensemble_roots`, and only for the
    configurations within :data:`PRUNE_KT` kT of the best one [ensemble.md#34-numerics].
    """
    N = np.asarray(turns, float)
    F = np.asarray(force, float)
    if not par.finite_size:
        return _limit_points(N, F, par)
    G, z, M, Lpk, melt, mk = _configurations(N, F, par)
    Gmin = G.min(axis=1, keepdims=True)
    none = ~np.isfinite(Gmin[:, 0])
    if np.any(none):  # every configuration failed (its torque solve or z <= 0)
        i = int(np.flatnonzero(none)[0])
        raise ValidityError(
            f"ensemble model at force {F[i] * 1e12:.6g} pN, turns {N[i]:.6g}: no state of "
            "finite free energy (no configuration's torque solve succeeded with a positive "
            "extension; the tail is too weakly stretched for this stiffness)")
    w = np.exp(-(G - Gmin) / par.kT)
    Z = w.sum(axis=1)
    w /= Z[:, None]
    avg = [np.where(w > 0.0, w * a, 0.0).sum(axis=1) for a in (z, M, Lpk, melt, mk)]
    return EnsemblePoints(avg[0], avg[1], Gmin[:, 0] - par.kT * np.log(Z), avg[2], avg[3],
                          avg[4], w[:, 0])


class _ConfigurationGroup:
    """The configurations ``(m, Lp, chirality)`` of one ``(m, chirality)`` at every point:
    bounds of their free energies from the tables, exact values solved on demand."""

    def __init__(self, tables, N, lp, m, c, par):
        L, K, b = par.length, par.nodes, par.microscopic_length
        self.tables, self.m, self.c, self.kT = tables, m, c, par.kT
        self.N, self.Lp = np.broadcast_arrays(N[:, None], lp[None, :])
        self.entropy = np.zeros(self.N.shape)
        if m:  # kT ln w_m (E7)
            self.entropy = par.kT * np.log(
                ((L - self.Lp) / b) ** m / factorial(m) * (self.Lp / b) ** (m - 1)
                / factorial(m - 1) * (L / K) / b)
        self.cr = _roots.crossings(tables, self.N, self.Lp, m, c)
        self.lower, self.upper = (self._per_element(v) for v in (self.cr.lower, self.cr.upper))
        self.solved = np.zeros(self.N.shape, bool)
        self.G = np.full(self.N.shape, np.inf)
        self.z, self.M, self.melt = (np.full(self.N.shape, np.nan) for _ in range(3))

    def _per_element(self, v):
        """An element's bound from its crossings' (the largest), minus its entropy."""
        a = np.full(self.N.size, -np.inf)
        np.maximum.at(a, self.cr.elem, v)
        return np.where(a > -np.inf, a, np.inf).reshape(self.N.shape) - self.entropy

    def left_out(self, best):
        """The configurations not solved whose lower bound is within the cut of ``best``."""
        return (np.isfinite(self.lower) & ~self.solved
                & (self.lower <= best[:, None] + PRUNE_KT * self.kT))

    def request(self, want):
        """What :func:`supercoil.core.dna.ensemble_roots.refine_many` needs to solve ``want``."""
        return self.cr, self.N, self.Lp, self.m, self.c, want.ravel()[self.cr.elem]

    def store(self, want, solved):
        """Keep the solved ``want``: G (E6 - kT ln w, infinite without a state), z, M."""
        M, ok, Phi, z, theta = solved
        G = Phi + _TWO_PI * M * self.N - self.entropy
        G = np.where(ok & np.isfinite(G) & (z > 0.0), G, np.inf)
        melt = theta * (self.tables.par.length - self.Lp)
        for out, v in ((self.G, G), (self.z, z), (self.M, M), (self.melt, melt)):
            out[want] = v[want]
        self.solved |= want


def _configurations(N, F, par):
    """G, z, M, Lp, melted length and m of every configuration (points x configurations);
    G infinite where a configuration has no state or lies provably more than
    :data:`PRUNE_KT` kT above the best one (not solved)."""
    K = par.nodes
    Lp = (np.arange(K) + 0.5) * par.length / K
    tables = _roots.LinkTables(
        F, par, lambda F, M, w: (tail_gibbs(F, M, par, w)[0], plectoneme_phase(F, M, par)),
        configuration, lambda F: wlc_at(F, par))
    groups = [_ConfigurationGroup(tables, N, lp, m, c, par)
              for m, lp, c in [(0, np.zeros(1), 1.0)]
              + [(m, Lp, c) for m in range(1, par.max_domains + 1) for c in (1.0, -1.0)]]
    # the best configuration's G is below the smallest upper bound: solve what may lie
    # within PRUNE_KT of it, then check the cut against the smallest G solved
    best = np.min([g.upper.min(axis=1) for g in groups], axis=0)
    while True:
        todo = [(g, w) for g in groups if (w := g.left_out(best)).any()]
        solved = _roots.refine_many(tables, [g.request(w) for g, w in todo])
        for (g, w), r in zip(todo, solved, strict=True):
            g.store(w, r)
        best = np.min([g.G.min(axis=1) for g in groups], axis=0)
        if not any(g.left_out(best).any() for g in groups):
            break
    def joined(column):
        return np.concatenate([column(g) for g in groups], axis=1)

    return (joined(lambda g: g.G), joined(lambda g: g.z), joined(lambda g: g.M),
            joined(lambda g: g.Lp), joined(lambda g: g.melt),
            joined(lambda g: np.full(g.N.shape, g.m, float)))


def coexistence_torque(force, par, sign=1.0, strict=True):
    """Thermodynamic-limit coexistence torque of tail and plectoneme (N m, sign ``sign``).

    Root of ``phi_t(F, M) = phi_p(M)`` (the common tangent) with ``|M|`` below
    :data:`TORQUE_BRACKET`. ``strict=False``: NaN where there is none (a melting tail
    that is more compliant than the plectoneme); else :class:`ValidityError`.
    """
    F = np.asarray(force, float)

    def f(M, F):
        return tail_gibbs(F, M, par)[0].phi - plectoneme_phase(F, M, par).phi

    a = np.full(F.shape, sign * 1e-24)
    b = np.full(F.shape, sign * TORQUE_BRACKET)
    res = find_root(f, (np.minimum(a, b), np.maximum(a, b)), args=(F,))
    if not strict:
        return np.where(res.success, res.x, np.nan)
    if not np.all(res.success):
        i = np.flatnonzero(~res.success)[0]
        raise ValidityError(f"ensemble model at force {F.flat[i] * 1e12:.6g} pN: no coexistence "
                            "of the tail and the plectoneme (the plectoneme is not more "
                            "twist-compliant than the tail)")
    return res.x


def _single(F, N, par, phase):
    """Stretched (phase 0) or fully plectonemic (1) molecule: G, M, z."""
    def h(M, F, N):
        g = tail_gibbs(F, M, par)[0] if phase == 0 else plectoneme_phase(F, M, par)
        return -par.length * g.dphi_dM - _TWO_PI * N

    lo = np.full(N.shape, -TORQUE_BRACKET)
    M = find_root(h, (lo, -1.03 * lo), args=(F, N)).x
    g = tail_gibbs(F, M, par)[0] if phase == 0 else plectoneme_phase(F, M, par)
    return par.length * g.phi + _TWO_PI * M * N, M, -par.length * g.dphi_dF


def _limit_points(N, F, par):
    """Thermodynamic limit (``finite_size=False``): common-tangent coexistence."""
    L = par.length
    G, M, z = _single(F, N, par, 0)
    Lp = np.zeros_like(N)
    melt = L * tail_gibbs(F, M, par)[1]
    st = np.ones_like(N)
    for sgn in (1.0, -1.0):
        side = np.sign(N) == sgn
        if not np.any(side):
            continue
        Mb = coexistence_torque(F[side], par, sgn, strict=False)  # NaN: no coexistence
        t, th = tail_gibbs(F[side], Mb, par)
        om_t, om_p = -t.dphi_dM, -plectoneme_phase(F[side], Mb, par).dphi_dM
        n = N[side]
        Ls = (om_p * L - _TWO_PI * n) / (om_p - om_t)
        co = (n * sgn > L * om_t * sgn / _TWO_PI) & (Ls > 0.0)
        Gc = L * t.phi + _TWO_PI * Mb * n
        Gf, Mf, _ = _single(F[side], n, par, 1)
        full = (Ls <= 0.0)
        idx = np.flatnonzero(side)
        for sel, g_, m_, z_, lp_, me_ in ((co, Gc, Mb, Ls * -t.dphi_dF, L - Ls, Ls * th),
                                          (full, Gf, Mf, 0.0 * n, L + 0.0 * n, 0.0 * n)):
            j = idx[sel]
            G[j], M[j], z[j] = g_[sel], m_[sel], z_[sel]
            Lp[j], melt[j], st[j] = lp_[sel], me_[sel], 0.0
    return EnsemblePoints(z, M, G, Lp, melt, 1.0 - st, st)
