"""The li-zhao hat curve of DNA in a magnetic tweezers (docs/theory/li-zhao.md). Float-only kernel.

Extension z versus turns N at fixed force T, symmetric in N (denaturation
ignored). With ``M_p = C omega`` the plectoneme torque at T (GE1), ``tau`` its
torsion (:func:`supercoil.core.dna.plectoneme.equilibrium`) and ``C_eff`` the
Moroz-Nelson rigidity (``C_eff = C`` when ``thermal=False``):

* stretched phase, ``|N| <= N_b``: tail torque ``M_3 = C_eff 2 pi |N| / L``,
  ``z = zeta(M_3, L) L``;
* buckling at ``N_b = C omega L / (2 pi C_eff)`` (torques match);
* plectoneme phase: torque ``M_p``; linking balance
  ``2 pi |N| = (C/C_eff) omega (L - S) + (omega + tau) S``, i.e.
  ``S = 2 pi (|N| - N_b) / D`` with ``D = tau - (C/C_eff - 1) omega``, and
  ``z = zeta(M_p, L - S) (L - S)``;
* fully coiled for ``S >= L``: ``z = 0`` and S reported as L (the torque is
  kept at M_p: the model has nothing beyond that point).

Post-buckling slope. In the plectoneme phase ``z(l) = zeta_inf l +
B kT / (B T - M_p^2/4)`` is linear in the tail length ``l = L - S``
(``zeta_inf = 1 - Q^(-1/2)/2``, Q the Moroz-Nelson bracket at M_p), and
``dl/d|N| = -2 pi / D``, hence for N > N_b

    dz/dN = -2 pi zeta_inf / D        (athermal: -2 pi / tau),

and ``+2 pi zeta_inf / D`` for N < -N_b. It does not depend on L.

Short tail. As ``l -> 0`` the finite-length term of zeta makes z tend to
``B kT / (B T - M_p^2/4)`` (10-20 nm) instead of 0, and zeta may exceed 1:
the Moroz-Nelson expansion needs ``l`` large compared with the bending
persistence length A = B/kT. Points with ``l < short_tail_length`` (default
``3 A``, 144 nm for the seed set; fully coiled points have l = 0) are computed
as written and flagged ``short_tail``; nothing is smoothed.

Signs: torque carries ``sign(N)``; extension, plectoneme length and phase are
even in N.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from supercoil.core.dna import li_zhao_numba as _fast
from supercoil.core.dna import li_zhao_numpy as _blk
from supercoil.core.dna import moroz_nelson as _mn
from supercoil.core.dna.interface import (
    SHORT_TAIL_PERSISTENCE_LENGTHS,
    HatPoints,
    PointSummary,
)
from supercoil.core.dna.plectoneme import EQUILIBRIUM_RTOL, equilibrium
from supercoil.exceptions import ValidityError

__all__ = [
    "BLOCK",
    "HatParameters",
    "buckling_turns",
    "hat_curve_points",
    "hat_parameters",
    "post_buckling_slope",
]

_TWO_PI = 2.0 * np.pi


def _combined(blocks):
    """One :class:`PointSummary` from the blocks' summaries."""
    f, e_lo, e_hi, m_lo, m_hi, q_lo, over, n_lo, n_hi = zip(*blocks, strict=True)
    return PointSummary(all(f), float(min(e_lo)), float(max(e_hi)), float(min(m_lo)),
                        float(max(m_hi)), float(np.min(q_lo)), any(over), float(min(n_lo)),
                        float(max(n_hi)))


class HatParameters(NamedTuple):
    """Per-force constants of the hat curve (SI arrays of the force's shape)."""

    force: np.ndarray  # N
    torque: np.ndarray  # plectoneme torque M_p = C omega, N m
    omega: np.ndarray  # 1/m
    torsion: np.ndarray  # tau of the plectoneme, 1/m
    twist_ratio: np.ndarray  # C / C_eff (1 athermal)
    effective_twist_rigidity: np.ndarray  # C_eff, N m^2
    buckling_turns: np.ndarray  # N_b
    linking_rate: np.ndarray  # D = tau - (C/C_eff - 1) omega, 1/m
    slope: np.ndarray  # dz/dN for N > N_b, m per turn


def hat_parameters(force, length, B, C, kT, r0, thermal=True, rtol=EQUILIBRIUM_RTOL,
                   check_zeta=True, equilibrium_state=None):
    """Buckling turns, plectoneme torque and post-buckling slope at each force.

    ``equilibrium_state`` (a :class:`~supercoil.core.dna.plectoneme.PlectonemeState`
    at ``force``) replaces the hard-core equilibrium solve: any interaction's
    plectoneme enters the construction through it (``r0`` and ``rtol`` are
    then unused).

    With ``check_zeta=False`` (used by :func:`hat_curve_points`, which checks
    zeta point by point) the slope is NaN where zeta's bracket is not positive
    at the plectoneme torque instead of raising.

    Raises
    ------
    NoEquilibriumError
        If a force has no plectoneme equilibrium.
    ValidityError
        (thermal) if zeta's bracket is not positive at the plectoneme torque, or
        if ``D <= 0`` (the tail would store more linking per length than the
        plectoneme).
    """
    force = np.asarray(force, dtype=float)
    eq = equilibrium_state
    if eq is None:
        eq = equilibrium(force, B, C, kT, r0, rtol=rtol)
    M, omega, tau = eq.torque, eq.omega, eq.torsion
    if thermal:
        ratio = _mn.twist_rigidity_ratio(force, B, C, kT)
        D = tau - (ratio - 1.0) * omega
        if np.any(D <= 0.0):
            i = np.flatnonzero(D <= 0.0)[0]
            raise ValidityError(
                f"at force {force.flat[i] * 1e12:.6g} pN the fluctuating tail stores more "
                "linking per length than the plectoneme (tau <= (C/C_eff - 1) omega)"
            )
        with np.errstate(invalid="ignore"):
            zeta_inf = _mn.long_tail_factor(force, M, B, kT, check=check_zeta)
        slope = -_TWO_PI * zeta_inf / D
    else:
        ratio = np.ones_like(force)
        D = tau
        slope = -_TWO_PI / tau
    Nb = M * ratio * length / (_TWO_PI * C)
    return HatParameters(force, M, omega, tau, ratio, C / ratio, Nb, D, slope)


def buckling_turns(force, length, B, C, kT, r0, thermal=True):
    """``N_b = C omega L / (2 pi C_eff)`` at each force."""
    return hat_parameters(force, length, B, C, kT, r0, thermal, check_zeta=False).buckling_turns


def post_buckling_slope(force, length, B, C, kT, r0, thermal=True):
    """``dz/dN`` (m per turn) just past buckling, N > 0: ``-2 pi zeta_inf / D``.

    Implements docs/theory/li-zhao.md (LZ4).
    """
    return hat_parameters(force, length, B, C, kT, r0, thermal).slope


def hat_curve_points(turns, force, length, B, C, kT, r0, thermal=True, rtol=EQUILIBRIUM_RTOL,
                     short_tail_length=None, equilibrium_solver=None, fast=None,
                     diagnostics=True):
    """Hat-curve points: one (turns, force) pair per point, equilibrium once per force.

    Implements docs/theory/li-zhao.md (LZ3).

    Parameters
    ----------
    turns : array
        Applied turns N (the linking number), any sign.
    force : array
        Tension T (N), same shape as ``turns`` (or broadcastable to it).
    length : float
        Contour length L (m).
    B, C : float
        Bending and torsional rigidity (N m^2).
    kT : float
        Thermal energy (J).
    r0 : float
        Marko-Siggia hard-core radius (m).
    thermal : bool
        Moroz-Nelson corrections (C_eff, zeta). ``False``: ``C_eff = C``,
        ``zeta = 1``, and no thermal term is computed.
    rtol : float
        Tolerance of the equilibrium solver.
    short_tail_length : float, optional
        Tail length (m) below which points are flagged ``short_tail``;
        default ``3 B/kT``.
    equilibrium_solver : callable, optional
        ``tension -> PlectonemeState`` for another interaction (default: the
        hard-core solver at ``r0``).
    fast : bool, optional
        Use the compiled kernel :mod:`supercoil.core.dna.li_zhao_numba` (numba, the
        ``supercoil[fast]`` extra); it agrees with the numpy path to rounding.
        Default ``None``: only if the environment variable ``SUPERCOIL_FAST``
        is ``1``. The numpy path is the default.
    diagnostics : bool
        Keep the per-point ``zeta`` and ``bracket`` arrays (default). ``False``:
        they are computed block by block in reused buffers and returned as
        None (two arrays, 16 bytes per point, fewer to allocate and fill;
        :attr:`HatPoints.summary` still says whether zeta leaves (0, 1] at a
        long tail and holds the bracket's minimum).

    Returns
    -------
    HatPoints

    Raises
    ------
    NoEquilibriumError
        Naming the force, if a force has no plectoneme equilibrium.
    ValidityError
        (thermal) naming force and torque where zeta's bracket is not positive
        at a point that is not fully coiled.
    ValueError
        For non-finite turns or forces, or a non-positive length.
    ImportError
        If the compiled kernel is asked for and numba is not installed.
    """
    turns = np.asarray(turns, dtype=float)
    force = np.asarray(force, dtype=float)
    if turns.shape != force.shape:
        turns, force = np.broadcast_arrays(turns, force)
    if not (np.isfinite(length) and length > 0):
        raise ValueError(f"length must be positive and finite, got {length!r}")
    if short_tail_length is None:
        short_tail_length = SHORT_TAIL_PERSISTENCE_LENGTHS * B / kT
    if turns.size == 0:
        empty = np.empty(turns.shape)
        return HatPoints(empty, empty, empty, empty.astype(np.int8), empty.astype(bool), empty,
                         None, empty if thermal else None)
    shape = turns.shape
    turns, force = turns.reshape(-1), force.reshape(-1)
    uf, ranges = _forces(force)
    eq = None if equilibrium_solver is None else equilibrium_solver(uf)
    par = hat_parameters(uf, length, B, C, kT, r0, thermal, rtol, False, eq)
    # per-force constants of the per-point formulas (docs/theory/li-zhao.md#hat-curve)
    const = (par.buckling_turns, par.torque, _TWO_PI / par.linking_rate,
             par.effective_twist_rigidity * (_TWO_PI / length), uf * (B / (kT * kT)) - 1.0 / 32)
    out = _fill_points(turns, force, uf, ranges, const, length, B, kT, thermal,
                       short_tail_length, fast, diagnostics)
    if shape != turns.shape:
        out = HatPoints(*(a.reshape(shape) if isinstance(a, np.ndarray) else a for a in out))
    return out


def _fill_points(turns, force, uf, ranges, const, length, B, kT, thermal, short_tail_length,
                 fast, diagnostics):
    """Allocate the points and fill them block by block; the summary combined."""
    n = turns.size
    m = n if diagnostics else min(n, BLOCK)  # the zeta and bracket arrays, or block buffers
    zeta_w, bracket_w = np.empty(m), np.empty(m) if thermal else None
    out = HatPoints(np.empty(n), np.empty(n), np.empty(n), np.empty(n, np.int8),
                    np.empty(n, bool), zeta_w if diagnostics else None, None,
                    bracket_w if diagnostics else None)
    fill = _blk.fill_block
    if _fast.wanted(fast):
        _fast.compiled()  # ImportError naming the extra if numba is missing
        fill = _fill_fast
    blocks = []
    for (start, stop), (lo, hi) in zip(_blocks(n), ranges, strict=True):
        sl = slice(start, stop)
        if lo == hi:  # one force in the block (the force-major tables): scalar constants
            i = int(np.searchsorted(uf, lo))
            c = tuple(a[i] for a in const)
        else:
            i = np.searchsorted(uf, force[sl])
            c = tuple(a[i] for a in const)
        w = sl if diagnostics else slice(0, stop - start)
        blocks.append(fill(turns[sl], force[sl], c, length, B, kT, thermal, short_tail_length,
                           out, sl, zeta_w[w], None if bracket_w is None else bracket_w[w]))
    return out._replace(summary=_combined(blocks))


#: points per block of :func:`hat_curve_points`: temporaries stay bounded (a few
#: block-sized arrays, cache-resident) whatever the number of points
BLOCK = 1 << 15


def _blocks(n):
    """``(start, stop)`` of the blocks of ``n`` points."""
    return [(s, min(s + BLOCK, n)) for s in range(0, n, BLOCK)]


def _forces(force):
    """Sorted distinct forces and each block's ``(min, max)``; ValueError if not finite.

    One pass of two cache-resident reductions per block: a block of one force
    (every block but the seams of a force-major table) needs no sort; one force
    broadcast over the points (a stride-0 view) is read once.
    """
    if force.size and force.strides == (0,):  # one value: read once, as blocks.extremes does
        f = force[0]
        if not np.isfinite(f):
            raise ValueError("force must be finite")
        return np.array([f]), [(f, f)] * len(_blocks(force.size))
    ranges, values = [], []
    for start, stop in _blocks(force.size):
        f = force[start:stop]
        lo, hi = f.min(), f.max()  # NaN propagates into both; inf shows in one
        if not (np.isfinite(lo) and np.isfinite(hi)):
            raise ValueError("force must be finite")
        ranges.append((lo, hi))
        values.append(np.array([lo]) if lo == hi else np.unique(f))
    return np.unique(np.concatenate(values)), ranges


def _fill_fast(turns, force, const, length, B, kT, thermal, short_tail_length, out, sl, zeta,
               bracket):
    """The compiled fused loop on one block; the numpy path names any failure.

    Returns the block's summary (:func:`~supercoil.core.dna.li_zhao_numpy.block_summary`).
    """
    code, over = _fast.fill(turns, const, length, B, kT, thermal, short_tail_length, out, sl,
                            zeta, bracket)
    if code != _fast.OK:
        return _blk.fill_block(turns, force, const, length, B, kT, thermal, short_tail_length, out,
                           sl, zeta, bracket)
    return _blk.block_summary(out.extension[sl], out.torque[sl], None, bracket, None,
                              (turns.min(), turns.max()), over)


