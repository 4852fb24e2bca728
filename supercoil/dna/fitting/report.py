"""The text report of a fit (in the style of lmfit's ``fit_report``)."""

from __future__ import annotations

import numpy as np

from supercoil import display
from supercoil.dna.fitting.consistency import report_lines
from supercoil.units import ureg

__all__ = ["fit_report", "twist_in_trap_units"]


def _in_data_unit(result, nm):
    """``nm`` in the data's extension unit, with nm in brackets when that is another unit."""
    unit = result.spec.data.units.get("extension", "nm") or "nm"
    try:
        v = ureg.Quantity(nm, "nm").m_as(unit)
    except Exception:  # an unusual unit string: stay in nm
        unit, v = "nm", nm
    return f"{v:.4g} {unit}" + ("" if unit == "nm" else f" ({nm:.4g} nm)")


def _statistics(result):
    noise = result.residual_rms.magnitude
    g = result.goodness
    if result.weighting == "unit" and "torque" in result.channels:
        stats = [
            f"    noise estimate     = {_in_data_unit(result, noise)} (extension residual RMS)",
            f"    chi-square         = {result.chi_square:.6g} (both channels, each weighted "
            "by its sigmas or its own noise estimate)",
        ]
        wtext = "per channel (below); no rescaling of the covariance"
    elif result.weighting == "unit":
        stats = [
            f"    noise estimate     = {_in_data_unit(result, noise)} (residual RMS, "
            "sqrt(sum of squared residuals / degrees of freedom))",
            f"    sum of squares     = {result.sum_squares.magnitude:.6g} nm^2 (unit weights: "
            "no chi-square test: the noise level is estimated from the scatter and is the "
            "sigma, so redchi = 1 by construction)",
        ]
        if np.isfinite(g.get("p_value", np.nan)):
            stats.append(f"    goodness of fit    = runs test (Wald-Wolfowitz): "
                         f"{int(g['runs'])} runs of one sign, {g['expected_runs']:.1f} "
                         f"expected, p = {g['p_value']:.3g}")
        wtext = ("unit weights; standard errors scaled by the noise estimate (the residual "
                 "RMS)")
    else:
        stats = [
            f"    chi-square         = {result.chi_square:.6g}",
            f"    reduced chi-square = {result.reduced_chi_square:.6g} (1 when the model and "
            "the sigmas describe the data)",
            f"    goodness of fit    = chi-square test, two-sided p = {g['p_value']:.3g}",
            f"    residual RMS       = {_in_data_unit(result, noise)}",
        ]
        wtext = (f"per-point sigma ({result.weighting}); covariance not rescaled "
                 "(absolute uncertainties)")
    return stats, wtext


def _channel_lines(result):
    """One line per channel of a joint extension and torque fit (none for extension only)."""
    if "torque" not in result.channels:
        return []
    lines = []
    for name, c in result.channels.items():
        rms = c["residual_rms"]
        how = (f"noise estimate {c['noise'].magnitude:.4g} {c['noise'].units:~P} used as "
               "its sigma" if c["noise"] is not None else f"sigmas from the {c['weighting']}")
        lines.append(f"    {name + ' channel':<19}= {c['ndata']} points, residual RMS "
                     f"{rms.magnitude:.4g} {rms.units:~P}, chi-square {c['chi_square']:.6g} "
                     f"for {c['dof']:.1f} degrees of freedom ({how})")
    return lines


def _parameter_lines(result, width):
    lines = [f"    {'name':<{width}}{'value':>12}{'stderr':>16}  {'unit':<6}{'rel.err':>9}"
             f"{'start':>12}  bounds"]
    for name in result.names:
        p = result.params[name]
        v = result.parameters[name].magnitude
        e = result.stderr[name].magnitude
        if name in result.undetermined:
            etext, rel = "not determined", "-"
        else:
            etext = f"{e:.4g}"
            rel = f"{100 * e / abs(v):.2f}%" if v != 0 else "-"
        f = p.factor
        lines.append(f"    {name:<{width}}{v:>12.6g}{etext:>16}  {p.unit:<6}{rel:>9}"
                     f"{result.start[name].magnitude:>12.6g}  ({p.min * f:.4g}, "
                     f"{p.max * f:.4g})")
    return lines


def _correlation_lines(result, min_correlation, max_correlations=6):
    """The ``max_correlations`` largest ``|C| >= min_correlation`` (lmfit's ``min_correl``)."""
    pairs = []
    names = result.names
    corr = result.correlation.to_numpy()
    for a in range(len(names)):
        for b in range(a + 1, len(names)):
            if np.isfinite(corr[a, b]) and abs(corr[a, b]) >= min_correlation:
                pairs.append((abs(corr[a, b]), names[a], names[b], corr[a, b]))
    if not pairs:
        return []
    pairs.sort(reverse=True)
    shown = pairs[: max(0, int(max_correlations))]
    more = len(pairs) - len(shown)
    head = f"[[Correlations]] (|C| >= {min_correlation:g}"
    head += f"; the {len(shown)} largest of {len(pairs)}, all in result.correlation)" \
        if more else ")"
    return [head] + [f"    C({a}, {b}) = {v:+.4f}" for _, a, b, v in shown]


def twist_in_trap_units(result):
    """``(C / s, its standard error)`` in nm of a fit with C and the torque scale s free.

    The model's torque is s times the measured one, so its twist persistence C is in the
    model's torque units; ``C / s`` is the twist stiffness in the units of the measured
    torque (docs/theory/ensemble.md#6-validation-without-refitting, section 6.1).
    The error is the first-order propagation of the covariance,
    ``var(C/s) = (var C - 2 (C/s) cov(C, s) + (C/s)^2 var s) / s^2``. None unless both are
    free and determined.
    """
    names = ("twist_persistence", "torque_scale")
    if not all(n in result.names and n not in result.undetermined for n in names):
        return None
    C = result.parameters[names[0]].m_as("nm")
    s = float(result.parameters[names[1]].magnitude)
    cov = result.covariance.loc[list(names), list(names)].to_numpy()  # nm and 1
    r = C / s
    var = (cov[0, 0] - 2.0 * r * cov[0, 1] + r * r * cov[1, 1]) / (s * s)
    return r, float(np.sqrt(max(var, 0.0)))


def _derived_lines(result):
    trap = twist_in_trap_units(result)
    if trap is None:
        return []
    return ["[[Derived]]",
            f"    twist_persistence / torque_scale = {trap[0]:.6g} +/- {trap[1]:.4g} nm "
            "(C in the measured torque's units; "
            "docs/theory/ensemble.md#6-validation-without-refitting)"]


def fit_report(result, min_correlation=0.1, max_correlations=6) -> str:
    """Statistics, parameter table with units, fixed values, correlations, warnings."""
    d = result.spec.data
    forces = np.unique(d.force)
    force_text = ", ".join(f"{f:.4g}" for f in display.to_display(forces, "force"))
    stats, wtext = _statistics(result)
    torque = ", torque = tau(N - turns_offset)" if "torque" in result.channels else ""
    inter = (f", interaction {result.interaction.name!r}" if result.model.uses_interaction
             else "")
    lines = [
        "[[Model]]",
        f"    z = hat(N - turns_offset) + extension_offset{torque}, model "
        f"{result.model.name!r}{inter}, "
        + ("thermal" if result.thermal else "athermal"),
        "[[Fit statistics]]",
        f"    fitting method     = least_squares (trf), {result.nfev} model evaluations "
        f"({result.kernel_calls} kernel calls with the Jacobians), "
        f"{result.seconds:.3g} s",
        f"    data points        = {result.ndata} ({len(forces)} forces: {force_text} pN; "
        f"{len(d.labels)} molecule{'s' if len(d.labels) > 1 else ''})",
        f"    free parameters    = {len(result.names)}",
        f"    degrees of freedom = {result.nfree}",
        *stats,
        f"    Akaike info crit   = {result.aic:.6g}",
        f"    Bayesian info crit = {result.bic:.6g} ({result.n_determined} determined "
        "parameters counted)",
        f"    weighting          = {wtext}",
        *_channel_lines(result),
        *report_lines(result),
        f"    converged          = {result.success} ({result.message})",
        "[[Parameters]]",
    ]
    width = max(len(n) for n in [*result.names, *result.fixed, "name"]) + 2
    lines += _parameter_lines(result, width)
    if result.fixed:
        lines.append("[[Fixed]]")
        for name, q in result.fixed.items():
            lines.append(f"    {name:<{width}}{q.magnitude:>12.6g}  {q.units:~P}")
    lines += _derived_lines(result)
    lines += _correlation_lines(result, min_correlation, max_correlations)
    if result.notes:
        lines.append("[[Notes]]")
        lines.extend(f"    {n}" for n in result.notes)
    if result.warnings:
        lines.append("[[Warnings]]")
        lines.extend(f"    {w}" for w in result.warnings)
    return "\n".join(lines)
