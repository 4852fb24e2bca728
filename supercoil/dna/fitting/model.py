"""The fitted model: hat curves through the DNA model interface, residuals and Jacobian.

For point i of molecule m at force T_i and turns N_i (docs/theory/fitting.md#the-global-fit)::

    z_i = hat(N_i - N0_m ; T_i, dna, model, interaction) + z0_m

``hat`` is any registered :class:`~supercoil.dna.models.base.DNAModel`
(``model.points``), evaluated for the whole data set in one call. The
parameters (:class:`~supercoil.dna.fitting.fit_parameters.FitParameters`) go to the
molecule (DNA fields, at the float level: a :class:`~supercoil.dna.material.DNASI`
with the derived rigidities recomputed), to ``model.replace(...)``, to
``interaction.replace(...)`` or to the per-molecule offsets.

With a ``torque`` column the measured torques are a second channel: the
residual vector is ``[(z_model - z) / sigma_z, (tau_model - tau) / sigma_tau]``
(docs/theory/fitting.md#joint-torque-fit); the turns offsets act on both
channels, the extension offsets on the extensions only.

Calibration nuisance parameters (docs/theory/fitting.md#calibration-nuisance-parameters,
:data:`~supercoil.dna.fitting.fit_parameters.CALIBRATION`; off unless given):
the kernel is evaluated at ``force_scale x`` the data's (nominal) force, and the
measured torque is predicted as ``tau_model / torque_scale`` (model torque =
torque_scale x measured torque); the data and their sigmas are never rescaled.
With a ``force_spread`` s > 0 the kernel points are the Gauss-Hermite average over
the true forces ``force_scale x F x (1 + s xi)`` (:mod:`supercoil.dna.fitting.spread`:
one kernel call at all nodes); at s = 0 the kernel is called exactly as without it.

Numerics
--------
The optimiser works on scaled variables of order one (``value / scale``). The
Jacobian is built in ``n_global + 1`` kernel calls: forward differences for the
global parameters, one central difference in N for all turns offsets at once
(``dz/dN0 = -dz/dN``) and exact columns for the extension offsets and the
torque scale (``d(tau/s)/ds = -tau / s^2``). Kernel
failures (:class:`~supercoil.exceptions.NoEquilibriumError`,
:class:`~supercoil.exceptions.ValidityError`) at a trial point give a
non-finite residual (scipy's TRF then shrinks the trust region).

Caches (within one fit): the unpacked kernel arguments, the residual and the
points at the last few parameter vectors (no repeated evaluation or unpacking
at the same parameters), and the plectoneme
equilibria keyed by :meth:`~supercoil.dna.interactions.base.Interaction.cache_key`
and the force: the key leaves out the length and the twist rigidity C, on which only
``omega = M/C`` and the twist energy depend (for every interaction: (GE2) contains no C);
under the same key, a dict per molecule for the models' C-free results
(:meth:`~supercoil.dna.interactions.base.Interaction.kernel_memo`).
"""

from __future__ import annotations

import math
from collections import OrderedDict

import numpy as np

from supercoil.dna.fitting.fit_parameters import CALIBRATION_OFF
from supercoil.dna.fitting.spread import spread_average, spread_nodes
from supercoil.dna.models.base import HatPoints
from supercoil.exceptions import FitError, NoEquilibriumError, ValidityError
from supercoil.units import BOLTZMANN

__all__ = ["HatCurveModel", "dna_si", "guess_turns_center"]

_KERNEL_ERRORS = (NoEquilibriumError, ValidityError)
_CACHE_SIZE = 8


def evaluate(model, turns, force, dna, thermal, interaction):
    """One kernel call (a module attribute so tests can swap it)."""
    return model.points(turns, force, dna, thermal, interaction, None)


def dna_si(base, values, xi_is_bending):
    """``base`` (DNASI) with DNA fields replaced (SI) and the derived fields recomputed."""
    if not values:
        return base
    d = base._replace(**values)
    kT = BOLTZMANN * d.temperature
    xi = d.bending_persistence if xi_is_bending else d.wlc_persistence
    return d._replace(kT=kT, wlc_persistence=xi, bending_rigidity=d.bending_persistence * kT,
                      torsional_rigidity=d.twist_persistence * kT)


class _CachedInteraction:
    """An interaction whose ``equilibrium`` is memoised within one fit."""

    def __init__(self, interaction, store, memos):
        self._inter = interaction
        self._store = store
        self._memos = memos

    def __getattr__(self, name):
        return getattr(self._inter, name)

    def unrecorded(self):
        """Itself: the cache records nothing the shared checks read (trial states stay cached)."""
        return self

    @property
    def wrapped(self):
        """The interaction itself (without the memo)."""
        return self._inter

    def kernel_memo(self, dna):
        """The fit's dict of C-free kernel results for this molecule's :meth:`cache_key`."""
        key = self._inter.cache_key(dna)
        memo = self._memos.get(key)
        if memo is None:
            memo = self._memos[key] = {}
            if len(self._memos) > _CACHE_SIZE:
                self._memos.popitem(last=False)
        else:
            self._memos.move_to_end(key)
        return memo

    def equilibrium(self, tension, dna):
        tension = np.asarray(tension, dtype=float)
        # C-free key (Interaction.cache_key): omega and the twist energy scale with 1/C
        key = (self._inter.cache_key(dna), tension.tobytes())
        hit = self._store.get(key)
        if hit is None:
            state = self._inter.equilibrium(tension, dna)
            self._store[key] = (state, dna.torsional_rigidity)
            if len(self._store) > 4 * _CACHE_SIZE:
                self._store.popitem(last=False)
            return state
        state, c_ref = hit
        if c_ref == dna.torsional_rigidity:
            return state
        omega = state.torque / dna.torsional_rigidity
        return state._replace(omega=omega, twist_energy=0.5 * state.torque * omega)


class HatCurveModel:
    """Residuals, Jacobian and start values of one fit (float level, SI)."""

    def __init__(self, data, params, dna, model, interaction, thermal, xi_is_bending=True):
        self.data = data
        self.params = params
        self.base_dna = dna
        self.model = model
        self.interaction = interaction
        self.thermal = thermal
        self.xi_is_bending = xi_is_bending
        self.free = params.free_params()
        self.names = [p.name for p in self.free]
        self.scales = params.scales
        self.w = 1.0 / data.sigma
        self.n_ext = data.n
        self.observed = data.extension
        self.weights = self.w
        if data.has_torque:
            self.observed = np.concatenate([data.extension, data.torque])
            self.set_torque_sigma(data.torque_sigma)
        self.n_kernel_failures = 0
        self.n_kernel_calls = 0
        self.last_failure = None
        self.njev = 0
        self._points = OrderedDict()
        self._eq_store = OrderedDict()
        self._memos = OrderedDict()
        self._unpacked = OrderedDict()
        self._jac = None
        # the kernel does not depend on the extension offsets nor on the torque scale: leave
        # them out of the cache key
        self._kernel_mask = np.array([p.kind not in ("extension_offset", "torque_scale")
                                      for p in self.free], bool)
        self._calibration = {p.kind: (j if p.vary else None, p.value)
                             for j, p in enumerate(self.free) if p.owner == "calibration"}
        self._calibration.update({p.kind: (None, p.value) for p in params.values()
                                  if p.owner == "calibration" and not p.vary})
        self._per_force = any(p.shared == "per-force" for p in params.values())

    @property
    def per_force(self) -> bool:
        """Some model or DNA parameter is fitted per force (each force its own state)."""
        return self._per_force

    def set_torque_sigma(self, sigma):
        """Weights of the torque channel: ``1 / sigma`` (N m, scalar or per point)."""
        wt = np.broadcast_to(1.0 / np.asarray(sigma, dtype=float), (self.n_ext,))
        self.weights = np.concatenate([self.w, wt])
        self._jac = None

    def set_extension_sigma(self, sigma):
        """Weights of the extension channel: ``1 / sigma`` (m, scalar or per point)."""
        self.w = np.broadcast_to(1.0 / np.asarray(sigma, dtype=float), (self.n_ext,)).copy()
        self.weights = np.concatenate([self.w, self.weights[self.n_ext:]])
        self._jac = None

    def scale(self, name, u):
        """The calibration parameter ``name`` (``"force_scale"``, ``"torque_scale"``,
        ``"force_spread"``) at ``u`` (its off value when not in the fit)."""
        j, value = self._calibration.get(name, (None, CALIBRATION_OFF[name]))
        return value if j is None else float(u[j] * self.free[j].scale)

    def channels(self, pts, torque_scale=1.0):
        """Kernel points as the model vector (extension, then the predicted measured torque
        ``tau / torque_scale`` if fitted; no offsets)."""
        z = np.array(pts.extension, dtype=float)  # a copy: the points are cached
        if not self.data.has_torque:
            return z
        return np.concatenate([z, np.asarray(pts.torque, dtype=float) / torque_scale])

    def torque_prediction(self, u):
        """The model's torque at the data points (N m): the predicted measured torque
        ``tau / torque_scale`` with torque data, the model torque without."""
        tau = np.asarray(self.points(u)[0].torque, dtype=float)
        return tau / self.scale("torque_scale", u) if self.data.has_torque else tau

    # ---- parameters -> kernel arguments ----
    def unpack(self, u, force=None):
        """``(dna SI, model, interaction, n0 per molecule, z0 per molecule)`` at ``u``.

        Per-force parameters count only at their own ``force`` (N); with
        ``force=None`` they keep the values of the molecule and model given.
        Memoised on ``(u, force)`` for the last few vectors (the optimiser asks
        for the same ``u`` in the residual, the Jacobian and its columns);
        the offset arrays are returned as copies.
        """
        u = np.asarray(u, dtype=float)
        key = (u.tobytes(), force)
        hit = self._unpacked.get(key)
        if hit is None:
            hit = self._unpack(u, force)
            self._unpacked[key] = hit
            if len(self._unpacked) > 4 * _CACHE_SIZE:
                self._unpacked.popitem(last=False)
        dna, model, inter, n0, z0 = hit
        return dna, model, inter, n0.copy(), z0.copy()

    def _unpack(self, u, force):
        groups = {"dna": {}, "model": {}, "interaction": {}}
        n_mol = self.data.n_molecules
        n0, z0 = np.zeros(n_mol), np.zeros(n_mol)
        offsets = {"turns_offset": n0, "extension_offset": z0}
        values = {p.name: p.value for p in self.params.values()}
        for p, x in zip(self.free, u, strict=True):
            values[p.name] = p.scale * x
        for p in self.params.values():
            v = values[p.name]
            if p.shared == "per-force" and (force is None or not math.isclose(
                    p.force, force, rel_tol=1e-9)):
                continue
            if p.owner == "offset":
                target = offsets[p.kind]
                if p.molecule is None:
                    target[:] = v
                else:
                    target[p.molecule] = v
            elif p.owner in groups:  # fixed ones too: a params= set may hold them
                groups[p.owner][p.kind] = v
        dna = dna_si(self.base_dna, groups["dna"], self.xi_is_bending)
        model = self.model.replace(**groups["model"]) if groups["model"] else self.model
        inter = self.interaction
        if groups["interaction"]:
            inter = inter.replace(**groups["interaction"])
        return dna, model, _CachedInteraction(inter, self._eq_store, self._memos), n0, z0

    def kernel(self, turns, force, dna, model, inter):
        self.n_kernel_calls += 1
        return evaluate(model, turns, force, dna, self.thermal, inter)

    def kernel_at(self, turns, force, u):
        """Kernel points at ``u``: one call, or one per force with per-force parameters.

        ``force`` is the data's nominal force: the kernel sees ``force_scale x force``,
        with a force spread the node forces ``force_scale x force x (1 + s xi_k)`` and the
        points are their average.
        """
        fs = self.scale("force_scale", u)
        spread = self.scale("force_spread", u)
        if spread == 0.0:
            return self._kernel_at(turns, force, fs, u)
        turns_k, force_k, factor = spread_nodes(turns, force, spread)
        return spread_average(self._kernel_at(turns_k, force_k, fs * factor, u), len(turns))

    def _kernel_at(self, turns, force, fs, u):
        """Kernel points at ``force x fs`` (``fs`` scalar or per point), grouped by the
        nominal ``force`` for per-force parameters."""
        if not self._per_force:
            dna, model, inter = self.unpack(u)[:3]
            return self.kernel(turns, force * fs, dna, model, inter)
        out = None
        for f in np.unique(force):
            sel = force == f
            pts = self.kernel(turns[sel], force[sel] * (fs[sel] if np.ndim(fs) else fs),
                              *self.unpack(u, f)[:3])
            if out is None:  # arrays only (a kernel's summary, a tuple, covers its own call)
                out = [None if a is None or isinstance(a, tuple)
                       else np.empty(len(turns), np.asarray(a).dtype) for a in pts]
            for arr, a in zip(out, pts, strict=True):
                if arr is not None:
                    arr[sel] = a
        return HatPoints(*out)

    def fitted(self, u, force=None):
        """``(dna SI, model, interaction)`` at ``u`` (at ``force`` with per-force parameters),
        the interaction without the fit's memo (plain picklable instances)."""
        dna, model, inter = self.unpack(u, force)[:3]
        return dna, model, inter.wrapped

    def states(self, u):
        """``{force: (dna, model, interaction)}`` at ``u`` for every force of the data."""
        return {float(f): self.fitted(u, f) for f in np.unique(self.data.force)}

    # ---- model, residual ----
    def points(self, u):
        """``(HatPoints, z0 per point)`` at ``u`` (raises the kernel's errors); cached."""
        u = np.asarray(u, dtype=float)
        key = u[self._kernel_mask].tobytes()
        n0, z0 = self.unpack(u)[3:]
        mol = self.data.mol_index
        pts = self._points.get(key)
        if pts is None:
            pts = self.kernel_at(self.data.turns - n0[mol], self.data.force, u)
            self._points[key] = pts
            if len(self._points) > _CACHE_SIZE:
                self._points.popitem(last=False)
        else:
            self._points.move_to_end(key)
        return pts, z0[mol]

    def extension(self, u):
        pts, z0 = self.points(u)
        return np.asarray(pts.extension, dtype=float) + z0

    def predicted(self, u):
        """The model vector at ``u``: extensions with offsets, then torques (if fitted)."""
        pts, z0 = self.points(u)
        y = self.channels(pts, self.scale("torque_scale", u))
        y[: self.n_ext] += z0
        return y

    def residual(self, u):
        """Weighted residuals ``(model - data) / sigma``; ``inf`` where the kernel fails."""
        try:
            r = (self.predicted(u) - self.observed) * self.weights
        except _KERNEL_ERRORS as exc:
            self.n_kernel_failures += 1
            self.last_failure = f"{type(exc).__name__}: {exc}"
            return np.full(len(self.weights), np.inf)
        if not np.all(np.isfinite(r)):
            return np.full(len(self.weights), np.inf)
        return r

    # ---- Jacobian ----
    def jacobian(self, u):
        """Weighted Jacobian d residual / d u (n x n_free)."""
        u = np.asarray(u, dtype=float)
        if self._jac is not None and np.array_equal(self._jac[0], u):
            return self._jac[1].copy()
        self.njev += 1
        f0 = self.residual(u)
        if not np.all(np.isfinite(f0)):
            raise FitError(f"the model fails at {self.describe(u)}: {self.last_failure}")
        J = np.zeros((len(f0), len(u)))
        lo, hi = self.params.bounds_vector()
        mol = self.data.mol_index
        mol_all = np.concatenate([mol, mol]) if self.data.has_torque else mol
        turns_cols = []
        for j, p in enumerate(self.free):
            if p.owner == "offset" and p.kind == "extension_offset":
                sel = np.flatnonzero(mol == p.molecule)  # extension rows only
                J[sel, j] = p.scale * self.w[sel]
            elif p.kind == "torque_scale":  # torque rows only: d(tau / s)/ds = -tau / s^2
                s = self.scale("torque_scale", u)
                tau = np.asarray(self.points(u)[0].torque, dtype=float)
                J[self.n_ext:, j] = -tau / s**2 * self.weights[self.n_ext:] * p.scale
            elif p.owner == "offset":
                turns_cols.append(j)
            else:
                J[:, j] = self._forward_column(u, j, f0, lo[j], hi[j])
        if turns_cols:
            dzdn = self.dz_dturns(u)
            for j in turns_cols:
                sel = mol_all == self.free[j].molecule
                J[sel, j] = -dzdn[sel] * self.weights[sel] * self.free[j].scale
        self._jac = (u.copy(), J.copy())
        return J

    def _forward_column(self, u, j, f0, lo, hi):
        h = 1e-6 * max(1.0, abs(u[j]))
        for step in (h, -h):
            if not lo <= u[j] + step <= hi:
                continue
            up = u.copy()
            up[j] += step
            try:
                yp = self.predicted(up)
            except _KERNEL_ERRORS:
                continue
            return ((yp - self.observed) * self.weights - f0) / step
        raise FitError(f"cannot differentiate the model in {self.names[j]} at "
                       f"{self.describe(u)}: the kernel fails on both sides")

    def dz_dturns(self, u):
        """dz/dN (then dtau/dN if fitted) at every point: the model's closed-form slopes at
        the points of ``u`` where it has them (:meth:`_model_slopes`), else one kernel call
        at N -/+ h."""
        h = 1e-4
        ts = self.scale("torque_scale", u)
        n0 = self.unpack(u)[3]
        n_eff = self.data.turns - n0[self.data.mol_index]
        force = self.data.force
        slopes = self._model_slopes(u, n_eff, ts)
        if slopes is not None:
            return slopes
        try:
            pts = self.kernel_at(np.concatenate([n_eff - h, n_eff + h]),
                                 np.concatenate([force, force]), u)
            m = len(n_eff)
            # the arrays (a kernel's summary, a tuple, covers both halves: dropped)
            arrays = [None if a is None or isinstance(a, tuple) else np.asarray(a) for a in pts]
            lo_pts = type(pts)(*(None if a is None else a[:m] for a in arrays))
            hi_pts = type(pts)(*(None if a is None else a[m:] for a in arrays))
            return (self.channels(hi_pts, ts) - self.channels(lo_pts, ts)) / (2 * h)
        except _KERNEL_ERRORS:
            pass
        base = self.channels(self.points(u)[0], ts)
        for sgn in (1.0, -1.0):
            try:
                y = self.channels(self.kernel_at(n_eff + sgn * h, force, u), ts)
                return (y - base) / (sgn * h)
            except _KERNEL_ERRORS:
                continue
        raise FitError(f"cannot differentiate the model in turns at {self.describe(u)}")

    def _model_slopes(self, u, n_eff, ts):
        """The model's ``turn_slopes`` at the (cached) points of ``u`` as the channels'
        dN derivative, or None: the model has none, the points are a force spread's
        average or per-force calls, or the torque is fitted and a point has no dM/dN
        (NaN: the free-energy model's fully coiled points)."""
        if self._per_force or self.scale("force_spread", u) != 0.0:
            return None
        dna, model, inter = self.unpack(u)[:3]
        force = self.data.force * self.scale("force_scale", u)
        slopes = model.turn_slopes(n_eff, force, dna, self.thermal, inter, self.points(u)[0])
        if slopes is None:
            return None
        dz, dM = slopes
        if not self.data.has_torque:
            return dz
        return np.concatenate([dz, dM / ts]) if np.all(np.isfinite(dM)) else None

    # ---- text ----
    def describe(self, u=None):
        """``name = value unit, ...`` of the global parameters at ``u`` (default: start)."""
        values = {p.name: p.value for p in self.params.values()}
        if u is not None:
            for p, x in zip(self.free, u, strict=True):
                values[p.name] = p.scale * x
        return ", ".join(f"{p.name} = {values[p.name] * p.factor:.6g} {p.unit}"
                         for p in self.params.values() if p.owner != "offset")


def guess_turns_center(turns, z, force):
    """Centre of symmetry of the hat: shift c minimising the mismatch of z(N) and z(2c - N).

    Vectorised over the 241 trial centres (one interpolation per force for all
    of them). Returns 0 when the curves are too short to tell.
    """
    span = np.ptp(turns) if len(turns) else 0.0
    if span <= 0 or len(turns) < 6:
        return 0.0
    grid = np.linspace(turns.min() + 0.25 * span, turns.max() - 0.25 * span, 241)
    total = np.zeros_like(grid)
    weight = np.zeros_like(grid)
    for f in np.unique(force):
        sel = force == f
        nf, zf = turns[sel], z[sel]
        if len(nf) < 6 or np.ptp(nf) <= 0:
            continue
        nu, inv = np.unique(nf, return_inverse=True)
        zu = np.bincount(inv, weights=zf) / np.bincount(inv)
        scale = np.var(zf) or 1.0
        mirror = 2 * grid[:, None] - nf[None, :]
        inside = (mirror >= nu[0]) & (mirror <= nu[-1])
        d = np.where(inside, zf[None, :] - np.interp(mirror, nu, zu), 0.0)
        count = inside.sum(axis=1)
        ok = count >= max(4, 0.3 * len(nf))
        mean = np.divide((d * d).sum(axis=1), count, out=np.zeros_like(grid), where=ok)
        total += np.where(ok, mean / scale, 0.0)
        weight += ok
    ok = weight > 0
    if not ok.any():
        return 0.0
    cost = np.where(ok, total / np.maximum(weight, 1), np.inf)
    return float(grid[int(np.argmin(cost))])
