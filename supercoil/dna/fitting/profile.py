"""Profile-likelihood confidence intervals of a fit (on request).

docs/theory/fitting.md#profile-likelihood. In the spirit of lmfit's
``conf_interval`` and pylake's ``profile_likelihood``: one parameter is held
at a sequence of values stepping out from its estimate, all others are
refitted at each, and the rise of the chi-square

    Delta(v) = (chi2(v) - chi2_min) / s^2

is compared with the chi-square quantile of one degree of freedom (1 for
one sigma, 68.27 %; 4 for two). ``s^2`` is 1 with stated sigmas (and in a
joint fit, whose channels are weighted by their noise estimates, held at the
best fit's), and the residual variance ``chi2_min / nfree`` with unit weights
(the noise estimate; pylake does the same, lmfit uses an F test instead).
The interval ends where ``Delta`` crosses the quantile, found by linear
interpolation of the signed root ``sqrt(Delta)`` (exact for a linear model,
where ``Delta`` is a parabola). For a linear model the interval is the
estimate -/+ its standard error; for a non-linear one it may be asymmetric.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pandas as pd
from scipy import special  # what scipy.stats' chi2 calls, without importing all of scipy.stats

from supercoil.exceptions import FitError

__all__ = ["ProfileLikelihood", "conf_interval", "profile_likelihood", "sigma_level"]


def _chi2_ppf_1(level):
    """``scipy.stats.chi2.ppf(level, 1)``: the same function, ``2 P^-1(1/2, level)``."""
    return float(2.0 * special.gammaincinv(0.5, float(level)))


def sigma_level(sigma):
    """Two-sided confidence level of ``sigma`` standard deviations (1 -> 0.6827)."""
    return float(special.chdtr(1, float(sigma) ** 2))  # scipy.stats.chi2.cdf


@dataclasses.dataclass
class ProfileLikelihood:
    """The profile of one parameter (display units) and its confidence interval.

    Attributes
    ----------
    name, unit : str
        The parameter and its display unit.
    best, stderr : float
        The estimate and its standard error from the Jacobian.
    values, delta_chi2 : ndarray
        The profiled values (sorted) and ``Delta`` at each (0 at ``best``).
    confidence_level : float
        The level of ``lower_bound`` / ``upper_bound``.
    lower_bound, upper_bound : float
        The interval ends (NaN when the profile does not reach the quantile
        within the steps taken or a bound: the interval is open there).
    """

    name: str
    unit: str
    best: float
    stderr: float
    values: np.ndarray
    delta_chi2: np.ndarray
    confidence_level: float
    lower_bound: float = math.nan
    upper_bound: float = math.nan

    def interval(self, confidence_level=None):
        """``(lower, upper)`` at ``confidence_level`` (default: the profile's own)."""
        level = self.confidence_level if confidence_level is None else float(confidence_level)
        t = _chi2_ppf_1(level)
        return (_crossing(self.values, self.delta_chi2, self.best, t, -1),
                _crossing(self.values, self.delta_chi2, self.best, t, +1))

    def plot(self, ax=None, path=None, dpi=120):
        """The profile, the quantile and the Jacobian parabola; returns the Figure.

        ``ax``: draw into these axes (default a new figure); ``path``: also save
        the figure there. Nothing is shown here: in a script call
        ``matplotlib.pyplot.show()`` or save (``path=``), as for
        :meth:`FitResult.plot`.
        """
        import matplotlib.pyplot as plt

        if ax is None:
            fig, ax = plt.subplots(figsize=(4.8, 3.6), layout="constrained")
        else:
            fig = ax.figure
        # the profile through its minimum (the best fit, at zero), not a chord across it
        x, y = np.append(self.values, self.best), np.append(self.delta_chi2, 0.0)
        order = np.argsort(x, kind="stable")
        ax.plot(x[order], y[order], "o-", ms=3, label="profile")
        if np.isfinite(self.stderr) and self.stderr > 0:
            grid = np.linspace(self.values.min(), self.values.max(), 200)
            ax.plot(grid, ((grid - self.best) / self.stderr) ** 2, "k--", lw=0.8,
                    label="Jacobian (parabola)")
        t = _chi2_ppf_1(self.confidence_level)
        ax.axhline(t, color="grey", lw=0.8,
                   label=f"{100 * self.confidence_level:.3g} % level")
        for b in (self.lower_bound, self.upper_bound):
            if np.isfinite(b):
                ax.axvline(b, color="C3", lw=0.8)
        ax.set_xlabel(f"{self.name} [{self.unit}]" if self.unit else self.name)
        ax.set_ylabel("Δχ²")
        ax.set_ylim(0, max(1.5 * t, float(np.nanmax(self.delta_chi2))))
        ax.legend(fontsize=8)
        from supercoil.dna.fitting.plot import save_figure

        return save_figure(fig, path, dpi)


def _crossing(values, delta, best, t, side):
    """Where the signed root of ``delta`` crosses ``sqrt(t)`` on ``side`` of ``best``."""
    sel = values > best if side > 0 else values < best
    v = np.concatenate([[best], values[sel][:: side]])
    d = np.concatenate([[0.0], delta[sel][:: side]])
    root = np.sqrt(np.clip(d, 0, None))
    above = np.flatnonzero(root >= math.sqrt(t))
    if not len(above):
        return math.nan
    k = int(above[0])
    r0, r1 = root[k - 1], root[k]
    return float(v[k - 1] + (math.sqrt(t) - r0) * (v[k] - v[k - 1]) / (r1 - r0))


def _problem(result, params):
    """The fitted model with ``params`` and the best fit's weights (noise estimates)."""
    from supercoil.dna.fitting import offsets
    from supercoil.dna.fitting.model import HatCurveModel

    spec = dataclasses.replace(result.spec, params=params)
    cls = offsets.PerForceOffsetModel if offsets.has_per_force_offsets(params) \
        else HatCurveModel
    prob = cls(spec.data, params, spec.dna, spec.model, spec.interaction, spec.thermal,
               spec.xi_is_bending)
    ch = result.solution.channels
    if ch["extension"]["noise"] is not None:
        prob.set_extension_sigma(ch["extension"]["noise"])
    if "torque" in ch and ch["torque"]["noise"] is not None:
        prob.set_torque_sigma(ch["torque"]["noise"])
    return spec, prob


def _chi2_at(result, params, name, value_si):
    """Raw chi-square with ``name`` held at ``value_si``, the others refitted (and ``u``)."""
    from supercoil.dna.fitting.fit import solve

    params[name].value = value_si
    spec, prob = _problem(result, params)
    res = solve(spec, prob, params.vector())
    params.set_vector(res.x)
    r = prob.residual(res.x)
    return float(r @ r)


def profile_likelihood(result, name, confidence_level=0.6827, max_steps=12, step=0.5):
    """Profile of parameter ``name`` of a :class:`FitResult`: a :class:`ProfileLikelihood`.

    Parameters
    ----------
    result : FitResult
    name : str
        A free parameter (``result.names``).
    confidence_level : float
        The level of the interval (default 0.6827, one sigma).
    max_steps : int
        Steps on each side at most.
    step : float
        Step size in standard errors (the Jacobian's; 10 % of the value for
        an undetermined parameter).

    Raises
    ------
    FitError
        ``name`` is not a free parameter, or the level is not in (0, 1).
    """
    if name not in result.names:
        raise FitError(f"cannot profile {name!r}: not a free parameter of the fit "
                       f"(have {result.names})")
    if not 0 < confidence_level < 1:
        raise FitError(f"confidence_level must lie in (0, 1), got {confidence_level!r}")
    base = result.spec.params.copy()
    p = base[name]
    p.vary = False
    if not base.free:
        raise FitError(f"cannot profile {name!r}: it is the only free parameter")
    best, err = p.value, p.stderr if p.stderr is not None else math.inf
    h = step * (err if np.isfinite(err) and err > 0 else 0.1 * max(abs(best), 1e-12))
    sol = result.solution
    s2 = sol.chi_square / sol.chisqr if sol.chisqr else 1.0
    chi2_min = float(sol.chi_square)
    t = _chi2_ppf_1(confidence_level)
    vals, deltas = [], []
    for side in (-1, +1):
        params = base.copy()
        for k in range(1, int(max_steps) + 1):
            v = best + side * k * h
            if not p.min < v < p.max:
                break
            try:
                chi2 = _chi2_at(result, params, name, v)
            except FitError:
                break
            vals.append(v)
            deltas.append(max(0.0, (chi2 - chi2_min) / s2))
            if deltas[-1] > t:
                break
    order = np.argsort(vals)
    f = p.factor
    prof = ProfileLikelihood(name, p.unit, best * f, err * f,
                             np.asarray(vals)[order] * f, np.asarray(deltas)[order],
                             float(confidence_level))
    prof.lower_bound, prof.upper_bound = prof.interval()
    return prof


def conf_interval(result, names=None, sigmas=(1, 2), max_steps=12, step=0.5):
    """Profile-likelihood intervals of several parameters at several sigmas: a table.

    One row per parameter (``names``, default all free ones): ``best``,
    ``stderr`` (Jacobian) and ``lower_<s>sigma``, ``upper_<s>sigma`` for each
    ``s`` in ``sigmas`` (display units, ``attrs["units"]``; NaN where the
    profile does not reach the level). The profiles are stepped out to the
    largest sigma; lmfit's ``conf_interval`` with ``sigmas`` in sigma units.
    """
    names = list(result.names if names is None else ([names] if isinstance(names, str)
                                                      else names))
    sigmas = [float(s) for s in sigmas]
    if not sigmas or min(sigmas) <= 0:
        raise FitError(f"sigmas must be positive numbers, got {sigmas!r}")
    rows, units = [], {}
    for name in names:
        prof = profile_likelihood(result, name, sigma_level(max(sigmas)), max_steps, step)
        row = {"parameter": name, "best": prof.best, "stderr": prof.stderr}
        for s in sigmas:
            lo, hi = prof.interval(sigma_level(s))
            row[f"lower_{s:g}sigma"], row[f"upper_{s:g}sigma"] = lo, hi
        rows.append(row)
        units[name] = prof.unit
    table = pd.DataFrame(rows).set_index("parameter")
    table.attrs["units"] = units
    return table
