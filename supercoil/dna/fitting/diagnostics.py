"""Checks of a finished fit: plausible parameter values and goodness of fit.

docs/theory/fitting.md. Each check returns messages that the fit
issues as :class:`~supercoil.exceptions.FitWarning` and lists in the report.

Goodness of fit
---------------
* With per-point sigmas: the chi-square test. Under the model and Gaussian
  noise of the stated sigmas, ``chi2 = sum(r_i^2 / sigma_i^2)`` follows a
  chi-square distribution with ``nfree`` degrees of freedom; the two-sided
  p-value ``2 min(P(X >= chi2), P(X <= chi2))`` (:func:`scipy.stats.chi2`)
  below :data:`P_THRESHOLD` says the residuals are inconsistent with the
  stated noise (too large: sigmas too small or model wrong; too small: sigmas
  too large).
* With unit weights the noise level is estimated from the residuals, so the
  chi-square says nothing; instead the Wald-Wolfowitz runs test (Wald &
  Wolfowitz, Ann. Math. Statist. 11, 147 (1940)) on the signs of the
  residuals along the rotation curves (points sorted by molecule, force and
  turns, the curves one after the other). Independent residuals change sign
  often; a model that misses the shape of the curves leaves long runs of one
  sign. The number of runs R is compared with its mean
  ``mu = 1 + 2 n+ n- / n`` and variance ``(mu - 1)(mu - 2)/(n - 1)`` (normal
  approximation, valid for n+ and n- above about 10), one-sided (too few
  runs) p-value below :data:`P_THRESHOLD`.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import stats

__all__ = ["P_THRESHOLD", "bound_records", "chi_square_test", "plausibility_messages",
           "runs_test"]

#: p-value below which a goodness-of-fit test warns (a correct fit warns in 1 of 1000)
P_THRESHOLD = 1e-3


def plausibility_messages(params):
    """Messages for free parameters ending at or beyond their plausible range."""
    out = []
    for p in params.free_params():
        msg = p.implausible()
        if msg:
            out.append(msg)
    return out


def chi_square_test(chi2, nfree):
    """Two-sided p-value of ``chi2`` with ``nfree`` degrees of freedom."""
    upper = float(stats.chi2.sf(chi2, nfree))
    lower = float(stats.chi2.cdf(chi2, nfree))
    return min(1.0, 2.0 * min(upper, lower)), upper <= lower


def runs_test(residuals, order):
    """Wald-Wolfowitz runs test on the residual signs in the order ``order``.

    Parameters
    ----------
    residuals : ndarray
        Residuals in the data's row order.
    order : ndarray
        The point order along the curves (:meth:`RotationData.curve_order`:
        by molecule, force and turns). Zero residuals are left out.

    Returns
    -------
    (runs, expected, z, p) : the runs counted, their expected number
    ``1 + 2 n+ n- / n``, the normal score with variance
    ``(mu - 1)(mu - 2) / (n - 1)``, and the one-sided p-value of so few runs
    (NaN when fewer than 2 residuals of each sign: no test).
    """
    r = np.asarray(residuals, dtype=float)[order]
    s = r[r != 0] > 0
    n = len(s)
    npos = int(s.sum())
    nneg = n - npos
    if npos < 2 or nneg < 2:
        return 0, math.nan, math.nan, math.nan
    runs = 1 + int(np.count_nonzero(s[1:] != s[:-1]))
    mu = 1.0 + 2.0 * npos * nneg / n
    var = (mu - 1.0) * (mu - 2.0) / (n - 1.0)
    z = (runs - mu) / math.sqrt(var)
    return runs, mu, z, float(stats.norm.cdf(z))


def goodness_messages(weighting, chi2, nfree, residuals, data):
    """``(messages, summary dict)`` of the goodness-of-fit test that applies."""
    if weighting != "unit":
        p, high = chi_square_test(chi2, nfree)
        info = {"test": "chi-square", "p_value": p}
        if p < P_THRESHOLD:
            side = ("larger than the stated sigmas allow (the sigmas are too small or the "
                    "model does not describe the data)" if high else
                    "smaller than the stated sigmas imply (the sigmas are too large)")
            return [f"goodness of fit: chi-square = {chi2:.6g} for {nfree} degrees of "
                    f"freedom (reduced {chi2 / nfree:.4g}, two-sided p = {p:.2g}): the "
                    f"residuals are {side}"], info
        return [], info
    runs, mu, z, p = runs_test(residuals, data.curve_order())
    info = {"test": "runs", "p_value": p, "runs": runs, "expected_runs": mu}
    if np.isfinite(p) and p < P_THRESHOLD:
        return [f"goodness of fit: the residuals keep their sign over long stretches of the "
                f"curves (Wald-Wolfowitz runs test: {int(runs)} runs of one sign, {mu:.1f} "
                f"expected for independent residuals, z = {z:.2f}, p = {p:.2g}): the model "
                "does not describe the shape of the data"], info
    return [], info


def bound_records(params, u):
    """``("BoundWarning", message)`` for each fitted parameter that ends on a bound."""
    out = []
    lb, ub = params.bounds_vector()
    for j, p in enumerate(params.free_params()):
        for bound, side in ((lb[j], "lower"), (ub[j], "upper")):
            if np.isfinite(bound) and abs(u[j] - bound) <= 1e-6 * max(1.0, abs(bound)):
                f = p.factor
                out.append(("BoundWarning",
                            f"{p.name} = {p.value * f:.6g} {p.unit} sits on its {side} bound "
                            f"({bound * p.scale * f:.6g} {p.unit}); its standard error is not "
                            "meaningful"))
    return out
