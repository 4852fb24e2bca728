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
from scipy import special  # the functions of scipy.stats' chi2 and norm, without stats

from supercoil import display

__all__ = ["LENGTH_OFFSET_CORRELATION", "P_THRESHOLD", "bound_records", "chi_square_test",
           "length_offset_messages", "plausibility_messages", "runaway_hint", "runs_test"]

#: p-value below which a goodness-of-fit test warns (a correct fit warns in 1 of 1000)
P_THRESHOLD = 1e-3


#: |correlation| of the length with an extension offset from which the two are one
#: direction of the cost (the extension then fixes only ``L g(F) + z0``)
LENGTH_OFFSET_CORRELATION = 0.99
#: ... and reported as running away when the length is also this poorly determined
#: (relative standard error) or this far (ratio) from the length the extensions imply
LENGTH_RUNAWAY = {"relative_error": 0.02, "ratio": 1.25}


def _data_length(data, n0, dna):
    """The length (m) the extensions imply with no offset: the median over the molecules of
    the worm-like-chain inversion of the start values (None without an estimate)."""
    from supercoil.dna.fitting.start import length_start

    est = [length_start(data.turns[g], data.extension[g], data.force[g], n0[i], dna)
           for i, g in enumerate(data.groups())]
    est = [e for e in est if e is not None and np.isfinite(e) and e > 0]
    return float(np.median(est)) if est else None


def _length_offset_correlation(params, names, cov, undetermined):
    """``(offset name, correlation)`` of the length with its most correlated extension offset
    (NaN when either is undetermined); None when they are not both free."""
    if "length" not in names:
        return None
    i = names.index("length")
    best = None
    for j, n in enumerate(names):
        if params[n].kind != "extension_offset":
            continue
        if undetermined[i] or undetermined[j]:
            return n, math.nan
        denom = math.sqrt(cov[i, i] * cov[j, j])
        c = cov[i, j] / denom if denom > 0 else 0.0
        if best is None or abs(c) > abs(best[1]):
            best = (n, c)
    return best


def length_offset_messages(params, names, cov, undetermined, data, n0, dna):
    """A message when the contour length runs away along an extension offset.

    With the tails' relative extension ``g(F)`` of nearly the same shape at
    every force, ``z = L g(F) + z0`` leaves the fit a flat valley in
    ``(L, z0)``: on real data, where the model misses the curves' shape, the
    length runs off along it (to 1e7 nm) with the offset following. Reported
    when both are free, either is undetermined or their correlation reaches
    :data:`LENGTH_OFFSET_CORRELATION` in magnitude, and the length is poorly
    determined or far from the length the extensions imply
    (:data:`LENGTH_RUNAWAY`; a well-determined length on good data is highly
    correlated with the offset too, and is not reported). ``cov`` is the
    covariance of the free parameters ``names`` (SI, after the fit), ``n0`` the
    fitted turns offsets per molecule, ``dna`` the fitted molecule (SI).
    Returns a list of 0 or 1 messages.
    """
    names = list(names)
    found = _length_offset_correlation(params, names, cov, np.asarray(undetermined, bool))
    if found is None:
        return []
    offset, r = found
    if np.isfinite(r) and abs(r) < LENGTH_OFFSET_CORRELATION:
        return []
    p = params["length"]
    implied = _data_length(data, n0, dna)
    if np.isfinite(r):
        rel = p.stderr / abs(p.value) if p.value else math.inf
        ratio = p.value / implied if implied else 1.0
        if rel <= LENGTH_RUNAWAY["relative_error"] and (
                1 / LENGTH_RUNAWAY["ratio"] <= ratio <= LENGTH_RUNAWAY["ratio"]):
            return []
    how = "undetermined" if not np.isfinite(r) else f"correlation {r:+.4f}"
    seen = "" if implied is None else (
        f", the extensions imply about {display.text(implied, 'length', '.5g')} with no offset")
    return [f"length and {offset} are degenerate ({how}; fitted length "
            f"{p.value * p.factor:.6g} ± {p.stderr * p.factor:.2g} {p.unit}{seen}): with both "
            "free the extensions fix only L g(F) + extension_offset, a flat valley along which "
            "the length runs away. Fix one of them: hold the extension offset at 0 "
            "(fit_extension_offset=False) when the instrument measures absolute extensions, "
            "or hold the length at your molecule's (dna.replace(length=...), length not in "
            "vary); "
            "docs/theory/fitting.md#start-values"]


#: a length that ends this factor from its start (either way) in a fit that did not
#: converge ran along the valley of the length and an extension offset
LENGTH_RUNAWAY_FACTOR = 3.0


def runaway_hint(params, u):
    """The fix to append to a did-not-converge FitError when the length ran away.

    ``u`` is the optimiser's last vector (scaled, in the order of the free
    parameters); the parameters still hold their start values. Returns "" unless
    the length and an extension offset are both free and the length ended more
    than :data:`LENGTH_RUNAWAY_FACTOR` from its start.
    """
    free = params.free_params()
    names = [p.name for p in free]
    if "length" not in names or not any(p.kind == "extension_offset" for p in free):
        return ""
    j = names.index("length")
    p = free[j]
    last = float(u[j]) * p.scale
    if not (p.value > 0 and last > 0) or (
            1 / LENGTH_RUNAWAY_FACTOR <= last / p.value <= LENGTH_RUNAWAY_FACTOR):
        return ""
    f = p.factor
    return (f"; the length ran from its start {p.value * f:.6g} {p.unit} to {last * f:.6g} "
            f"{p.unit}: with the length and the extension offset both free the extensions fix "
            "only L g(F) + extension_offset, a flat valley. Fix one of them: hold the extension "
            "offset at 0 (fit_extension_offset=False) when the instrument measures absolute "
            "extensions, or hold the length at your molecule's (dna.replace(length=...), "
            "length not in vary)")


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
    upper = float(special.chdtrc(nfree, chi2))  # scipy.stats.chi2.sf
    lower = float(special.chdtr(nfree, chi2))  # scipy.stats.chi2.cdf
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
    return runs, mu, z, float(special.ndtr(z))  # scipy.stats.norm.cdf


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
