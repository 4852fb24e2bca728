"""Thermodynamically consistent hat curve, ``model="free-energy"``. Float-only kernel.

Derivation: docs/theory/free-energy.md. At fixed force F the molecule of
length L holding N turns has the free energy

    G(N, F) = min_S max_M [ (L - S) g_s(F, M) + S g_p(M) + 2 pi N M ],

the Legendre transform in the linking number of two phases that exchange
length S (plectoneme) and share the torque M:

* fluctuating tail (Moroz-Nelson, with the -1/32 term kept *inside* the free
  energy so that every derivative below is consistent):
  ``g_s(F, M) = -F + (kT^2/B) sqrt(Q) - M^2/(2C)``,
  ``Q = B F/kT^2 - M^2/(4 kT^2) - 1/32``;
  ``-dg_s/dF = zeta_inf = 1 - Q^(-1/2)/2`` (extension per length),
  ``-dg_s/dM = l_s = M/C + M/(4 B sqrt(Q))`` (2 pi x linking per length);
  athermal (``thermal=False``): ``g_s = -F - M^2/(2C)``;
* plectoneme (any interaction): ``g_p(M) = -T_p(M) - M^2/(2C)``, ``T_p(M)`` the
  tension of the uniform plectoneme equilibrium with torque M; ``dT_p/dM = tau``,
  so ``-g_p'(M) = l_p = M/C + tau``.

Results (the envelope theorem gives z and M):

* stretched, ``|N| <= N_b``: M solves ``l_s(F, M) = 2 pi |N| / L``;
  ``z = L zeta_inf(F, M)``, ``G = L g_s + 2 pi |N| |M|``;
* coexistence: ``g_s(F, M*) = g_p(M*)``, i.e. the plectoneme is in equilibrium
  at the tail's effective pull ``T_eff = F - (kT^2/B) sqrt(Q(F, M*))`` with
  ``M* = M_p(T_eff)`` (solved by Newton in T_eff; ``dM_p/dT = 1/tau``);
  ``N_b = L l_s(M*) / (2 pi)``;
* plectoneme phase: ``S = 2 pi (|N| - N_b) / D`` with
  ``D = l_p - l_s = tau - M*/(4 B sqrt(Q*))`` (> 0 required),
  ``z = (L - S) zeta_inf(F, M*)``, ``G = L g_s(F, M*) + 2 pi |N| M*``,
  slope ``dz/dN = -2 pi zeta_inf / D``;
* fully coiled, ``S = L``: M solves ``l_p(M) = 2 pi |N| / L`` on the plectoneme
  branch (the torque rises again), ``z = 0``, ``G = L g_p(M) + 2 pi |N| M``.

No finite-length term: the paper's ``B kT / (l (B T - M^2/4))`` has no
counterpart in this free energy and is omitted (z -> 0 as the tail vanishes);
tails shorter than ``short_tail_length`` are still flagged.

Optional end loop (``end_loop=True``, docs/theory/end-loop.md#7-free-energy): the
coexisting and fully coiled states carry one circular loop (radius
``R = sqrt(B/(2 T))`` at the plectoneme's tension T, writhe 1, twist at the common
torque); buckling becomes a jump at the crossing ``N* > N_b`` of the stretched
branch with the coexistence raised by the loop's excess free energy.

With ``thermal=False`` every formula reduces, operation for operation, to the
athermal li-zhao construction of :mod:`supercoil.core.dna.li_zhao`.

``equilibrium`` is a callable ``T -> PlectonemeState`` (1-D SI tensions), e.g.
``lambda T: interaction.equilibrium(T, dna)``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from supercoil.core.blocks import extremes
from supercoil.core.blocks import outside as _outside
from supercoil.core.blocks import select as _select
from supercoil.core.dna import branch_memo as _memo
from supercoil.core.dna import coiled_points as _points
from supercoil.core.dna import coiled_table as _table
from supercoil.core.dna import end_loop as _loop
from supercoil.core.dna import free_energy_fill as _fill
from supercoil.core.dna.free_energy_tail import (  # re-exported: the tail at its torque
    TAIL_RTOL,
    tail_bracket,
    tail_free_energy,
    tail_settled,
    tail_torque,
)
from supercoil.core.dna.free_energy_tail import check_bracket as _check_bracket
from supercoil.core.dna.interface import (
    FULLY_COILED,
    PLECTONEME,
    SHORT_TAIL_PERSISTENCE_LENGTHS,
    STRETCHED,
)
from supercoil.exceptions import ValidityError

__all__ = [
    "TAIL_RTOL",
    "Coexistence",
    "FreeEnergyPoints",
    "coexistence",
    "free_energy",
    "hat_points",
    "loop_constants",
    "plectoneme_torque_at_linking",
    "tail_bracket",
    "tail_free_energy",
    "tail_settled",
    "tail_torque",
]

_TWO_PI = 2.0 * np.pi
#: Newton on T_eff stops once a step is below this fraction of F (quadratic
#: convergence: the accepted T_eff is then within ~1e-15 F of the root)
_PULL_RTOL = 1e-13
_PULL_MAXITER = 12
#: last Newton step (fraction of F) applied to the state by first-order extrapolation
_PULL_EXTRAPOLATE = 1e-8


class Coexistence(NamedTuple):
    """Per-force constants of the free-energy hat curve (SI arrays of the force's shape)."""

    force: np.ndarray  # F, N
    torque: np.ndarray  # coexistence torque M*, N m
    pull: np.ndarray  # T_eff = F - (kT^2/B) sqrt(Q*), N (= F athermal)
    torsion: np.ndarray  # tau of the plectoneme at T_eff, 1/m
    bracket: np.ndarray  # Q* (inf athermal)
    long_tail_factor: np.ndarray  # zeta_inf(F, M*) (1 athermal)
    tail_linking: np.ndarray  # l_s(M*), rad/m
    linking_rate: np.ndarray  # D = l_p - l_s, rad/m
    buckling_turns: np.ndarray  # N_b
    slope: np.ndarray  # dz/dN past +N_b, m per turn
    free_energy_density: np.ndarray  # g_s(F, M*) = g_p(M*), J/m


class FreeEnergyPoints(NamedTuple):
    """Hat-curve points with the free energy, same-shape SI arrays."""

    extension: np.ndarray  # m
    torque: np.ndarray  # N m, sign of N
    plectoneme_length: np.ndarray  # m
    phase: np.ndarray  # int8
    short_tail: np.ndarray  # bool
    zeta: np.ndarray  # extension / tail length (1 athermal, 0 fully coiled)
    free_energy: np.ndarray  # G(N, F), J


def _plectoneme(equilibrium, tension):
    st = equilibrium(np.asarray(tension, float))
    return np.asarray(st.torque, float), np.asarray(st.torsion, float)


def _pull(force, B, C, kT, equilibrium):
    """Newton for ``h(T) = T - F + (kT^2/B) sqrt(Q(F, M_p(T))) = 0``: (T, M, tau, Q).

    ``h' = 1 - M / (4 B sqrt(Q) tau) = D / tau`` is exact (``dM_p/dT = 1/tau``).
    Started from the M = 0 estimate (18 % low at 0.3 pN), the steps fall as
    2e-1, 2e-4, 1e-10 (relative, seed set): after the third equilibrium call the
    last Newton step ``delta`` (<= 1e-8 F) is applied to the state to first
    order, ``M -= delta / tau`` (exact derivative, error ~ delta^2) and
    ``tau -= delta dtau/dT`` (secant of the last two calls, error ~ 1e-4 delta),
    instead of a fourth equilibrium call: 3 calls per force instead of 4.
    """
    if force.size == 1:  # one force on floats (the same operations); None: the checks raise
        got = _pull_one(float(force.flat[0]), B, kT, equilibrium)
        if got is not None:
            return tuple(np.full(force.shape, v) for v in got)
    s = kT * kT / B
    Q0 = tail_bracket(force, 0.0, B, kT)
    _check_bracket(Q0, force, np.zeros_like(force))  # F <= kT^2/(32 B): no tail at all
    T = force - s * np.sqrt(Q0)  # M = 0 estimate
    prev = None
    for _ in range(_PULL_MAXITER):
        if np.any(T <= 0.0):
            i = np.flatnonzero(T <= 0.0)[0]
            raise ValidityError(
                f"at force {force[i] * 1e12:.6g} pN the fluctuating tail pulls with no "
                "positive tension (F <= (kT^2/B) sqrt(Q)): no plectoneme coexists")
        M, tau = _plectoneme(equilibrium, T)
        Q = tail_bracket(force, M, B, kT)
        _check_bracket(Q, force, M)
        r = np.sqrt(Q)
        step = (T - force + s * r) / (1.0 - M / (4.0 * B * r * tau))
        if np.all(np.abs(step) <= _PULL_RTOL * force):
            return T, M, tau, Q
        if prev is not None and np.all(np.abs(step) <= _PULL_EXTRAPOLATE * force):
            dT = T - prev[0]
            dtau = np.divide(tau - prev[1], dT, out=np.zeros_like(dT), where=dT != 0.0)
            T, M, tau = T - step, M - step / tau, tau - step * dtau
            return T, M, tau, tail_bracket(force, M, B, kT)
        prev = (T, tau)
        T = T - step
    raise ValidityError(  # pragma: no cover - Newton on a nearly linear h
        f"the tail's effective pull did not converge in {_PULL_MAXITER} steps")


def _pull_one(F, B, kT, equilibrium):
    """:func:`_pull` at one force on Python floats, operation for operation (a third of
    its CPU besides the equilibrium calls), or None where a check fails (the array
    version then raises, naming the force)."""
    s = kT * kT / B
    Q0 = B * F / (kT * kT) - 0.25 * 0.0 * 0.0 - 1.0 / 32.0
    if not Q0 > 0.0:
        return None
    T = F - s * math.sqrt(Q0)
    prev = None
    for _ in range(_PULL_MAXITER):
        if not T > 0.0:
            return None
        st = equilibrium(np.array([T]))
        M, tau = float(st.torque[0]), float(st.torsion[0])
        m = M / kT
        Q = B * F / (kT * kT) - 0.25 * m * m - 1.0 / 32.0
        if not Q > 0.0:
            return None
        r = math.sqrt(Q)
        step = (T - F + s * r) / (1.0 - M / (4.0 * B * r * tau))
        if abs(step) <= _PULL_RTOL * F:
            return T, M, tau, Q
        if prev is not None and abs(step) <= _PULL_EXTRAPOLATE * F:
            dT = T - prev[0]
            dtau = (tau - prev[1]) / dT if dT != 0.0 else 0.0
            T, M, tau = T - step, M - step / tau, tau - step * dtau
            m = M / kT
            return T, M, tau, B * F / (kT * kT) - 0.25 * m * m - 1.0 / 32.0
        prev = (T, tau)
        T = T - step
    return None


def coexistence(force, length, B, C, kT, equilibrium, thermal=True, memo=None):
    """Coexistence torque, effective pull, buckling turns and slope at each force.

    Implements docs/theory/free-energy.md (FE4, FE5, FE8, FE9). ``memo``: a caller's
    dict keeping the C-free pull per force (:mod:`supercoil.core.dna.branch_memo`).

    Raises
    ------
    NoEquilibriumError
        From ``equilibrium``, naming the tension, where no plectoneme exists.
    ValidityError
        (thermal) where the tail bracket closes at the coexistence torque, the
        tail pulls with no positive tension, or ``D <= 0`` (the tail would store
        more linking per length than the plectoneme).
    """
    force = np.atleast_1d(np.asarray(force, float))
    if thermal:
        T, M, tau, Q = _memo.remember(memo, ("pull", B, kT, force.tobytes()),
                                      lambda: _pull(force, B, C, kT, equilibrium))
        r = np.sqrt(Q)
        zinf = 1.0 - 0.5 / r
        extra = M / (4.0 * B * r)
        ls = M / C + extra
        D = tau - extra
        g = -force + (kT * kT / B) * r - M * M / (2.0 * C)
        if np.any(D <= 0.0):
            i = np.flatnonzero(D <= 0.0)[0]
            raise ValidityError(
                f"at force {force[i] * 1e12:.6g} pN the fluctuating tail stores more linking "
                "per length than the plectoneme (tau <= M/(4 B sqrt(Q)))")
        Nb = ls * length / _TWO_PI
        slope = -_TWO_PI * zinf / D
    else:
        T = force
        M, tau = _plectoneme(equilibrium, force)
        Q = np.full(force.shape, np.inf)
        zinf = np.ones_like(force)
        ls = M / C
        D = tau
        g = -force - M * M / (2.0 * C)
        Nb = M * 1.0 * length / (_TWO_PI * C)  # the li-zhao expression, operation for operation
        slope = -_TWO_PI / tau
    return Coexistence(force, M, T, tau, Q, zinf, ls, D, Nb, slope, g)


def plectoneme_torque_at_linking(linking, pull, helix_linking, C, equilibrium, loop=None):
    """Fully coiled: ``(M, T_p)`` on the plectoneme branch with ``M/C + tau = linking``.

    With the end loop, ``loop = (B, L)`` and the equation is
    ``M/C + tau (1 - l(T)/L) = linking``, ``l(T) = 2 pi sqrt(B/(2T))`` (also
    increasing in T) [end-loop.md#7-free-energy].

    From :data:`~supercoil.core.dna.coiled_table.MIN_POINTS` points on, the secant
    only brackets the largest target (1-5 calls on one tension) and one Chebyshev
    table of the branch from the smallest ``T_eff`` to that bracket solves every point
    (:func:`supercoil.core.dna.coiled_table.torque_at_linking`; within 6e-14 of
    scipy brentq in M and T): 1.2 pN, seed set, about a fifth of the secant's CPU time
    at 74 points, 1/24 at 7,362 points. Fewer points, or a table that does not converge (a
    kink in l_p, e.g. at hard contact): the secant below on all of them.

    Secant: ``l_p(T) = M_p(T)/C + tau(T)`` increases with the tension from
    ``helix_linking = l_p(T_eff)`` at full coiling, so the root in ``u = log T``
    lies above ``log T_eff``. Safeguarded secant in u (bisection once the root
    is bracketed and a secant step leaves the bracket), started from
    ``(log T_eff, l_p(T_eff))``, which is known, and ``u0 + 2 log(linking / l_p)``
    (``l_p ~ sqrt(T)``): 5-11 equilibrium calls (200 points at 0.3-5 pN between
    full coiling and 3 times its turns). Measured against scipy
    ``bracket_root`` + ``find_root`` on 74 fully coiled points at 1.2 pN: half the
    time, same torque to 4e-14, which is why it is hand-written (each equilibrium
    call costs nearly the same whatever the number of points). The state
    returned is the one evaluated last, within 1e-13 (relative) of the root in T.
    """
    shape = np.broadcast_shapes(np.shape(linking), np.shape(pull), np.shape(helix_linking))
    x, pull, helix_linking = (np.broadcast_to(np.asarray(a, float), shape).reshape(-1)
                              for a in (linking, pull, helix_linking))
    got = None
    if x.size >= _table.MIN_POINTS:
        top = slice(np.argmax(x), np.argmax(x) + 1)
        _, T_hi = _table.secant(x[top], pull[top], helix_linking[top], C, equilibrium, loop,
                                upper=_table.DOMAIN_OVERSHOOT)
        got = _table.torque_at_linking(x, (pull.min(), T_hi[0]), C, equilibrium, loop)
    if got is None:
        got = _table.secant(x, pull, helix_linking, C, equilibrium, loop)
    return got[0].reshape(shape), got[1].reshape(shape)


def loop_constants(co, length, B, C, kT, thermal=True):
    """End-loop constants (:class:`~supercoil.core.dna.end_loop.LoopedCoexistence`) of ``co``.

    The stretched torque at the jump solves ``L [g_s(M) - g* + l_s(M) (M - M*)] = eps*``
    below the closing of the Moroz-Nelson bracket (thermal) or in closed form
    ``dM = sqrt(2 eps* C / L)`` (athermal) [end-loop.md#7-free-energy].
    """
    def tail(f, m):
        return tail_free_energy(f, m, B, C, kT, thermal)

    upper = None
    if thermal:
        upper = 2.0 * kT * np.sqrt(tail_bracket(co.force, 0.0, B, kT)) * (1.0 - 2.0**-30)
    return _loop.looped_coexistence(co, length, B, C, tail, _loop.LOOP_WRITHE, upper)


def hat_points(turns, force, length, B, C, kT, equilibrium, thermal=True,
               short_tail_length=None, trial_equilibrium=None, end_loop=False, memo=None):
    """Free-energy hat-curve points, one (turns, force) pair per point.

    Implements docs/theory/free-energy.md (FE6, FE7).

    Parameters
    ----------
    turns, force : array
        Turns N (any sign) and force F (N), same shape (broadcast).
    length, B, C, kT : float
        Contour length (m), rigidities (N m^2), thermal energy (J).
    equilibrium : callable
        ``T -> PlectonemeState`` (the interaction's plectoneme equilibrium).
    thermal : bool
        Moroz-Nelson tail; ``False``: the athermal limit (li-zhao athermal).
    short_tail_length : float, optional
        Flag tails shorter than this (m); default ``3 B/kT``.
    trial_equilibrium : callable, optional
        Used instead of ``equilibrium`` for the secant's trial tensions of the
        fully coiled points (and their table); ``equilibrium`` then solves the
        states at the smallest and largest of their final tensions
        (:func:`supercoil.core.dna.coiled_points.record_extremes`): a caller
        recording states for validity checks sees those, not the trials.
    end_loop : bool
        Add the plectoneme end loop (docs/theory/end-loop.md#7-free-energy); the
        returned plectoneme length then includes the loop's contour.
    memo : dict, optional
        The caller's store of C-free results for this ``equilibrium`` across calls (the
        pull, the fully coiled branch: :mod:`supercoil.core.dna.branch_memo`).

    Returns
    -------
    FreeEnergyPoints
    """
    turns, force = np.broadcast_arrays(np.asarray(turns, float), np.asarray(force, float))
    if not (np.isfinite(length) and length > 0):
        raise ValueError(f"length must be positive and finite, got {length!r}")
    f_lo, f_hi = extremes(force.reshape(-1)) if force.size else (1.0, 1.0)
    t_lo, t_hi = (turns.min(), turns.max()) if turns.size else (0.0, 0.0)
    if not all(np.isfinite([f_lo, f_hi, t_lo, t_hi])):  # NaN propagates
        raise ValueError("turns and force must be finite")
    if short_tail_length is None:
        short_tail_length = SHORT_TAIL_PERSISTENCE_LENGTHS * B / kT
    if turns.size == 0:
        e = np.empty(turns.shape)
        return FreeEnergyPoints(e, e, e, e.astype(np.int8), e.astype(bool), e, e)
    one = f_lo == f_hi  # one force: skip the sort of np.unique
    uf = force.reshape(-1)[:1].copy() if one else np.unique(force)
    co = coexistence(uf, length, B, C, kT, equilibrium, thermal, memo)
    loop = loop_constants(co, length, B, C, kT, thermal) if end_loop else None
    branch = _points.call_branch(turns.reshape(-1), force.reshape(-1), uf, co, loop, length,
                                 B, C, trial_equilibrium or equilibrium, BLOCK, memo,
                                 (t_lo, t_hi))

    out = _fill.fill_blocks(turns.reshape(-1), force.reshape(-1), uf, one, co, loop, length, B,
                            C, kT, equilibrium, thermal, short_tail_length, trial_equilibrium,
                            branch, BLOCK, _assemble)
    if turns.ndim == 1:  # the arrays themselves (owned: the public layer scales them in place)
        return out
    return FreeEnergyPoints(*(a.reshape(turns.shape) for a in out))


#: points per block of :func:`hat_points` (the per-point constants and phases are
#: ~15 arrays: peak memory 1.74x the public table at 1e6 points unblocked); the
#: fully coiled points of each block are solved together
BLOCK = 1 << 15


def _assemble(n, turns, force, inv, co, loop, length, B, C, kT, equilibrium, thermal,
              short_tail_length, trial_equilibrium, branch, out):
    """Phases, torque, extension and G of :func:`hat_points` (``loop`` None: no end loop),
    written into ``out`` (:class:`FreeEnergyPoints` of the block's slices of the result).

    ``inv`` None: every point at the one force ``co.force[0]``, whose constants enter as
    scalars (no gathers).
    """
    def at(a):
        return a[0] if inv is None else a[inv]

    if loop is None:
        Nb = at(co.buckling_turns)
        stretched = n <= Nb
        S = np.subtract(n, Nb, out=out.plectoneme_length)
        np.maximum(S, 0.0, out=S)
        S *= _TWO_PI / at(co.linking_rate)
        room = length
    else:  # (link) with the loop's w + t turns and its contour l [end-loop.md#7-free-energy]
        ell = at(loop.length)
        stretched = n <= at(loop.jump_turns)
        S = (_TWO_PI * (n - at(loop.linking)) - (length - ell) * at(co.tail_linking)) \
            / at(co.linking_rate)
        S = np.where(stretched, 0.0, np.maximum(S, 0.0))
        room = length - ell
    coiled = S >= room
    np.minimum(S, room, out=S)
    tail = room - S
    if loop is not None:  # the stretched molecule has no loop
        tail = np.where(stretched, length, tail)
    M, g = out.torque, out.free_energy  # |M| and g in place: signed and turned into G last
    M[...] = co.torque[0] if inv is None else co.torque[inv]
    g[...] = co.free_energy_density[0] if inv is None else co.free_energy_density[inv]
    zeta = out.zeta
    zeta[...] = co.long_tail_factor[0] if inv is None else co.long_tail_factor[inv]
    stretched, coiled = _select(stretched), _select(coiled)
    any_stretched, any_coiled = stretched is not None, coiled is not None
    if any_stretched:
        f_s, n_s = (force[0] if inv is None else force[stretched]), n[stretched]
        if thermal:
            M_s = tail_torque(_TWO_PI * n_s / length, f_s, B, C, kT)
        else:  # the li-zhao expression: C_eff (2 pi / L) n with C_eff = C / 1.0
            M_s = C / 1.0 * (_TWO_PI / length) * n_s
        M[stretched] = M_s
        g[stretched], zeta[stretched], _ = tail_free_energy(f_s, M_s, B, C, kT, thermal)
    if any_coiled:
        Mc, Tc = _points.solve(n[coiled], inv, coiled, co, loop, length, B, C, equilibrium,
                               trial_equilibrium, branch)
        M[coiled] = Mc
        g[coiled] = -Tc - Mc * Mc / (2.0 * C)
        zeta[coiled] = 0.0
    np.multiply(zeta, tail, out=out.extension)
    G = g  # L g + (2 pi N) M: the sum of the two products, as (2 pi N) M + L g
    G *= length
    G += np.multiply(n, _TWO_PI) * M
    if loop is not None:
        G[...] = np.where(_outside(n.size, stretched, coiled), G + at(loop.excess), G)
        if any_coiled:  # -(L - 2 l) T - L M^2/(2C) + 2 pi (|N| - w) M, l T = pi B / R
            lc = _loop.loop_length(Tc, B)
            G[coiled] = -(length - 2.0 * lc) * Tc - length * Mc * Mc / (2.0 * C) \
                + _TWO_PI * (n[coiled] - _loop.LOOP_WRITHE) * Mc
        S += ell
        if any_stretched:
            S[stretched] = 0.0
        out.plectoneme_length[...] = S
    phase = out.phase
    phase.fill(PLECTONEME)
    if any_stretched:
        phase[stretched] = STRETCHED
    if any_coiled:
        phase[coiled] = FULLY_COILED
    np.copysign(M, turns, out=M)
    np.less(tail, short_tail_length, out=out.short_tail)


def free_energy(turns, force, length, B, C, kT, equilibrium, thermal=True, end_loop=False):
    """``G(N, F)`` (J) at each point: :func:`hat_points` ``.free_energy``."""
    return hat_points(turns, force, length, B, C, kT, equilibrium, thermal,
                      end_loop=end_loop).free_energy
