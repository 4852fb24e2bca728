"""Stationary torques of the ensemble's configurations from one linking table per force.

Float kernel (SI). A configuration ``(m, Lp, chirality)`` of the ensemble
(:mod:`supercoil.core.dna.ensemble`) at force F has the linking

    Lk(M) = (L - Lp) omega_t(F, M) + Lp omega_p(F, M) + m lambda_c(F, M)

(tail, plectoneme and end-loop linking per length or per loop), linear in ``Lp`` and
``m``. Its stationary torque solves ``Lk(M) = 2 pi N``. The three functions and their
slopes are tabulated once per distinct force on :data:`TORQUE_NODES`; each element's
values at the nodes are then gathers, the cell of its root is found by bisection over
the node indices, the root estimated by inverse Hermite interpolation of the cell and
finished by Newton's method on the exact configuration
(:mod:`supercoil.core.table_roots`) [ensemble.md#34-numerics].

Where the tabulated linking of a configuration is not increasing in M (end loops beside a
melting tail), it has several stationary torques; each increasing crossing is refined and
the one of largest ``Phi(M) + 2 pi M N`` kept: the Legendre maximum of (E6).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from supercoil.core.numerics import find_root
from supercoil.core.table_roots import bracketed_newton, cell_search, hermite_inverse

from . import phases as _ph

__all__ = ["NEWTON_ATOL", "NEWTON_MAXITER", "NEWTON_RTOL", "TORQUE_BRACKET", "TORQUE_NODES",
           "Crossings", "LinkTables", "configuration_torques", "crossings", "refine",
           "refine_many"]

_TWO_PI = 2.0 * np.pi
#: bracket of the torque solves, N m (200 pN nm: far beyond B-DNA's torques)
TORQUE_BRACKET = 2e-19
_BRACKET = (-TORQUE_BRACKET, 1.03 * TORQUE_BRACKET)
_SCALE = 5e-21  # N m: node spacing about 0.09 pN nm at M = 0, 3.5 pN nm at 200 pN nm
#: torque nodes of the linking tables (N m): sinh-spaced over the bracket, dense near 0
TORQUE_NODES = _SCALE * np.sinh(np.linspace(np.arcsinh(_BRACKET[0] / _SCALE),
                                            np.arcsinh(_BRACKET[1] / _SCALE), 257))
TORQUE_NODES[[0, -1]] = _BRACKET
#: Newton ends when its next step is below NEWTON_RTOL |M| + NEWTON_ATOL; elements not done
#: after NEWTON_MAXITER evaluations (a cell across the melting jump of the tail) go to find_root
NEWTON_RTOL, NEWTON_ATOL, NEWTON_MAXITER = 1e-13, 1e-34, 16
_FLAT = 1e-13  # relative round-off allowed in a linking that is flat (a fully melted tail)
_SHARED = 4  # elements per (force, Lp) function from which its node values are tabulated


class LinkTables:
    """Tail, plectoneme and end-loop linking and slopes of each distinct force on the nodes.

    ``phases(F, M) -> (tail PhaseGibbs, plectoneme PhaseGibbs)`` and
    ``configuration(F, M, Lp, m, chirality, wlc) -> (Phi, link, z, theta, dlink)`` are
    the ensemble's (:func:`supercoil.core.dna.ensemble.configuration`); ``wlc(F)`` its
    exact-WLC pair (or None).
    """

    def __init__(self, force, par, phases, configuration, wlc):
        F = np.asarray(force, float)
        self.par, self.configuration = par, configuration
        self.forces, self.index = np.unique(F, return_inverse=True)
        self.index = self.index.reshape(F.shape)
        self.wlc = wlc(self.forces)  # at each distinct force
        FF, MM = np.broadcast_arrays(self.forces[:, None], TORQUE_NODES[None, :])
        w = self.wlc
        w = None if w is None else tuple(np.broadcast_to(a[:, None], MM.shape) for a in w)
        with np.errstate(invalid="ignore", divide="ignore"):
            t, p = phases(FF, MM, w)
            self.tail = (-t.dphi_dM, -t.d2phi_dM2, t.phi)
            self.plectoneme = (-p.dphi_dM, -p.d2phi_dM2, p.phi)
            self.loop = {}
            for c in (1.0, -1.0):
                e, _, e_M = _ph.end_loop_gibbs(t, MM, par.A, par.C, par.kT, par.writhe, c,
                                               par.nucleation, par.physical_loop)
                slope = _ph.end_loop_torque_slope(t, MM, par.A, par.C, par.kT,
                                                  par.physical_loop)
                self.loop[c] = (-e_M, -slope, e)

    def linking(self, fi, Lp, m, c, k=slice(None), kind=0):
        """Tabulated linking (``kind`` 0), its slope (1) or Phi (2) of configurations at
        forces ``fi`` and nodes ``k`` (``k`` a slice: every node, with ``Lp`` a column)."""
        j = kind
        t, p = self.tail[j][fi, k], self.plectoneme[j][fi, k]
        out = (self.par.length - Lp) * t + Lp * p
        return out + m * self.loop[c][j][fi, k] if m else out


def _increasing(link):
    """Whether each row of tabulated linking is finite and increasing (flat to round-off
    allowed: a fully melted tail)."""
    d = np.diff(link, axis=-1)
    tol = _FLAT * (np.abs(link[..., 1:]) + np.abs(link[..., :-1]))
    return np.all(np.isfinite(link), axis=-1) & np.all(d >= -tol, axis=-1)


class _Group:
    """Node values of one configuration group ``(m, c)``'s elements.

    Each distinct (force, Lp) is one function of M. Where the functions are few beside
    the elements (:data:`_SHARED` elements per function or more: a few forces, the hat
    curve's one), their node values are tabulated once and the elements gather from the
    table; else each gather combines the force's tail, plectoneme and loop tables.
    """

    def __init__(self, tables, fi, lp, K, m, c):
        self.tables, self.fi, self.lp, self.m, self.c = tables, fi, lp, m, c
        nodes = lp[:K]
        nf, G = tables.forces.size, TORQUE_NODES.size
        self.shared = fi.size >= _SHARED * nf * K
        if self.shared:
            f_all = np.repeat(np.arange(nf), K)
            lp_all = np.tile(nodes, nf)[:, None]
            self.V = tables.linking(f_all, lp_all, m, c).ravel()
            self.row = (fi * K + np.tile(np.arange(K), fi.size // K)) * G
            self.mono = _increasing(self.V.reshape(-1, G))[self.row // G]
            return
        # linear in Lp: increasing at the extreme Lp nodes means increasing at every one
        f_all = np.arange(nf)
        both = (_increasing(tables.linking(f_all, np.full((nf, 1), nodes.min()), m, c))
                & _increasing(tables.linking(f_all, np.full((nf, 1), nodes.max()), m, c)))
        self.mono = both[fi]
        bad = np.flatnonzero(~both)
        if bad.size and K > 1:
            per = _increasing(tables.linking(np.repeat(bad, K), np.tile(nodes, bad.size)[:, None],
                                             m, c))
            table = np.ones((nf, K), bool)
            table[bad] = per.reshape(bad.size, K)
            self.mono = table[fi, np.tile(np.arange(K), fi.size // K)]

    def value(self, e, k, kind=0):
        """Linking (``kind`` 0), slope (1) or Phi (2) of elements ``e`` at their nodes ``k``
        (or at every node)."""
        if self.shared and not kind:
            if isinstance(k, slice):
                return self.V[self.row[e, None] + np.arange(TORQUE_NODES.size)]
            return self.V[self.row[e] + k]
        lp = self.lp[e, None] if isinstance(k, slice) else self.lp[e]
        return self.tables.linking(self.fi[e], lp, self.m, self.c, k, kind)


class Crossings(NamedTuple):
    """The increasing crossings of ``2 pi N`` by the tabulated linking of one group's
    elements (one per element almost everywhere), each in its node cell."""

    elem: np.ndarray  # flat index of the element
    xa: np.ndarray  # the cell, N m
    xb: np.ndarray
    x0: np.ndarray  # inverse-Hermite estimate of the torque, N m
    lower: np.ndarray  # bounds of the element's max_M [Phi + 2 pi M N] (E6), J
    upper: np.ndarray


def crossings(tables, N, Lp, m, c):
    """Cells, estimates and free-energy bounds of each element's torque (2-D ``N``,
    ``Lp``: points x Lp nodes).

    ``lower`` is ``Phi + 2 pi M N`` at the better node of the cell: a lower bound of the
    maximum (E6) at any torque. ``upper`` adds ``(2 pi N - Lk) dM`` at the cell's lower
    node, the tangent's bound where ``Phi`` is concave on the cell [ensemble.md#34-numerics].
    """
    fi = np.broadcast_to(tables.index[:, None], N.shape).ravel()
    n, lp = N.ravel(), Lp.ravel()
    target = _TWO_PI * n
    grp = _Group(tables, fi, lp, Lp.shape[1], m, c)
    # one crossing per element on increasing tables (bisection over node indices) ...
    e1 = np.flatnonzero(grp.mono)
    k1 = cell_search(lambda k: grp.value(e1, k) - target[e1], TORQUE_NODES.size, e1.shape)
    # ... every increasing crossing elsewhere
    e2 = np.flatnonzero(~grp.mono)
    h2 = grp.value(e2, slice(None)) - target[e2, None]
    r, k2 = np.nonzero((h2[:, :-1] <= 0.0) & (h2[:, 1:] > 0.0))
    elem, k = np.concatenate([e1, e2[r]]), np.concatenate([k1, k2])
    ha = grp.value(elem, k) - target[elem]
    hb = grp.value(elem, k + 1) - target[elem]
    cell = np.isfinite(ha) & np.isfinite(hb) & (ha <= 0.0) & (hb > 0.0)
    elem, k, ha, hb = elem[cell], k[cell], ha[cell], hb[cell]
    xa, xb = TORQUE_NODES[k], TORQUE_NODES[k + 1]
    x0 = hermite_inverse(xa, xb, ha, hb, grp.value(elem, k, 1), grp.value(elem, k + 1, 1))
    ga = grp.value(elem, k, 2) + xa * target[elem]
    gb = grp.value(elem, k + 1, 2) + xb * target[elem]
    return Crossings(elem, xa, xb, x0, np.maximum(ga, gb), ga - ha * (xb - xa))


def refine(tables, cr, N, Lp, m, c, use):
    """Stationary torques of the elements of the crossings ``use`` (a mask of ``cr``, whole
    elements) and what their configurations have there.

    Returns ``(M, ok, Phi, z, theta)`` of the points x Lp shape, NaN and ``ok`` False where
    not refined or no crossing converged; an element with several crossings keeps the
    Legendre maximum of (E6).
    """
    return refine_many(tables, [(cr, N, Lp, m, c, use)])[0]


def refine_many(tables, groups):
    """:func:`refine` of several groups ``(cr, N, Lp, m, c, use)`` at once: one Newton
    iteration (one exact evaluation per step) for all their elements, so that the few
    elements that need many steps pay the per-call cost once, not once per group."""
    if not groups:
        return []
    parts = []
    for cr, N, Lp, m, c, use in groups:
        fi = np.broadcast_to(tables.index[:, None], N.shape).ravel()
        elem = cr.elem[use]
        parts.append((elem, fi[elem], N.ravel()[elem], Lp.ravel()[elem],
                      np.full(elem.size, float(m)), np.full(elem.size, float(c)),
                      cr.x0[use], cr.xa[use], cr.xb[use]))
    cat = [np.concatenate([p[j] for p in parts]) for j in range(9)]
    M, (Phi, z, theta), done = _refine(tables, *cat[6:], *cat[1:6])
    out, start = [], 0
    for grp, p in zip(groups, parts, strict=True):
        part = slice(start, start + p[0].size)
        start = part.stop
        out.append(_legendre_pick(grp[1], p[0], M[part], Phi[part], z[part], theta[part],
                                  done[part]))
    return out


def _legendre_pick(N, elem, M, Phi, z, theta, done):
    """Per element the crossing of the largest Phi + 2 pi M N (one almost everywhere),
    as arrays of the points x Lp shape."""
    n = N.ravel()
    G = Phi + _TWO_PI * M * n[elem]
    G = np.where(np.isfinite(G), G, -np.inf)
    pick = np.arange(elem.size)
    if elem.size and np.bincount(elem).max() > 1:  # some element has several crossings
        order = np.lexsort((-G, elem))
        first = np.ones(order.size, bool)
        first[1:] = elem[order][1:] != elem[order][:-1]
        pick = order[first]
    out = [np.full(n.shape, np.nan) for _ in range(4)]
    for o, v in zip(out, (M, Phi, z, theta), strict=True):
        o[elem[pick]] = v[pick]
    ok = np.zeros(n.shape, bool)
    ok[elem[pick]] = done[pick] & np.isfinite(G[pick])
    return (out[0].reshape(N.shape), ok.reshape(N.shape), *(o.reshape(N.shape)
                                                              for o in out[1:]))


def configuration_torques(tables, N, Lp, m, c):
    """:func:`refine` of every crossing: the stationary torque of each configuration
    ``(m, Lp, c)`` at turns ``N`` (2-D arrays of points x Lp nodes).

    Returns ``(M, ok, Phi, z, theta)``; ``ok`` False where no increasing crossing of
    ``2 pi N`` exists in the bracket (the caller gives those an infinite free energy).
    """
    cr = crossings(tables, N, Lp, m, c)
    return refine(tables, cr, N, Lp, m, c, np.ones(cr.elem.size, bool))


def _refine(tables, x0, xa, xb, fi, n, lp, m, c):
    """Newton from the tabulated estimates; scipy's find_root where it does not converge
    (per-candidate force index, turns, Lp, domains and chirality)."""
    par, conf = tables.par, tables.configuration
    wlc = tables.wlc

    def at(x, idx):
        f = fi[idx]
        w = None if wlc is None else (wlc[0][f], wlc[1][f])
        Phi, link, z, theta, dlink = conf(tables.forces[f], x, par, lp[idx], m[idx], c[idx], w)
        return link - _TWO_PI * n[idx], dlink, (Phi, z, theta)

    M, extras, done = bracketed_newton(at, x0, xa, xb, NEWTON_RTOL, NEWTON_ATOL,
                                      NEWTON_MAXITER)
    slow = np.flatnonzero(~done)
    if slow.size:
        res = find_root(lambda x, i: at(x, i.astype(np.intp))[0], (xa[slow], xb[slow]),
                        args=(slow.astype(float),))
        M[slow] = res.x
        _, _, ex = at(res.x, slow)
        for store, e in zip(extras, ex, strict=True):
            store[slow] = e
        done[slow] = res.success
    return M, extras, done
