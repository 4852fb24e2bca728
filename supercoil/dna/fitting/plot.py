"""Figures of fits: data, fitted curves and residuals per force (one fit or several models)."""

from __future__ import annotations

import numpy as np

from supercoil import display
from supercoil.dna.fitting.result import fmt_pm
from supercoil.dna.fitting.spread import spread_average, spread_nodes
from supercoil.exceptions import SupercoilError

__all__ = ["plot_comparison", "plot_fit", "save_figure"]

_MARKERS = "osd^v<>p*hX"


def _nm(si):
    return display.to_display(si, "extension")


def _pn_nm(si):
    return display.to_display(si, "torque")


def _z0(solution, mol):
    """Extension offset per point: per molecule, or per curve (``"per-force"`` offsets)."""
    z = solution.extension_offset_points
    return solution.extension_offset[mol] if z is None else z


def _curve(result, force, grid, field="extension"):
    """The fitted hat curve (offset-free, nm; or the torque, pN nm) on ``grid`` turns at
    ``force`` (N)."""
    c = result.solution
    dna, model, inter = c.dna, c.model, c.interaction
    if c.states:  # per-force parameters: the molecule and model at this force
        dna, model, inter = c.states[float(force)]
    scale = c.calibration  # docs/theory/fitting.md#calibration-nuisance-parameters
    spread = scale.get("force_spread", 0.0)
    f = np.full_like(grid, force * scale.get("force_scale", 1.0))
    if spread:  # the average over the molecules' true forces
        turns, f, factor = spread_nodes(grid, f, spread)
        pts = spread_average(model.points(turns, f * factor, dna, result.thermal, inter, None),
                             len(grid))
    else:
        pts = model.points(grid, f, dna, result.thermal, inter, None)
    if field == "extension":
        return _nm(pts.extension)
    return _pn_nm(getattr(pts, field)) / scale.get("torque_scale", 1.0)


def _torque_panels(result, axes, k, f, grid):
    """Rows 3 and 4 of a joint fit: measured torque with the fitted torque, residuals."""
    d, c = result.spec.data, result.solution
    ax, axr = axes[2, k], axes[3, k]
    mol = d.mol_index
    n_eff = d.turns - c.turns_offset[mol]
    for i in range(len(d.labels)):
        m = (d.force == f) & (mol == i)
        if not m.any():
            continue
        kw = {"marker": _MARKERS[i % len(_MARKERS)], "ms": 3, "ls": "none", "alpha": 0.6}
        ax.plot(n_eff[m], _pn_nm(d.torque[m]), **kw)
        axr.plot(n_eff[m], _pn_nm(d.torque[m] - c.torque[m]), **kw)
    try:
        ax.plot(grid, _curve(result, f, grid, "torque"), "k-", lw=1.5)
    except SupercoilError:
        pass  # the points themselves are shown; the model fails between them
    axr.axhline(0, color="k", lw=0.8)
    if k == 0:
        ax.set_ylabel("torque (pN nm)")
        axr.set_ylabel("residual (pN nm)")


def _data_panels(result, axes, k, f):
    d, c = result.spec.data, result.solution
    ax, axr = axes[0, k], axes[1, k]
    mol = d.mol_index
    n_eff = d.turns - c.turns_offset[mol]
    z_corr = _nm(d.extension - _z0(c, mol))
    resid = _nm(d.extension - c.best_fit)
    sel = d.force == f
    for i, lab in enumerate(d.labels):
        m = sel & (mol == i)
        if not m.any():
            continue
        label = f"molecule {lab}" if d.has_molecule and len(d.labels) > 1 else "data"
        kw = {"marker": _MARKERS[i % len(_MARKERS)], "ms": 3, "ls": "none", "alpha": 0.6}
        ax.plot(n_eff[m], z_corr[m], label=label if k == 0 else None, **kw)
        axr.plot(n_eff[m], resid[m], **kw)
    return n_eff[sel]


def save_figure(fig, path, dpi):
    """Save ``fig`` to ``path`` (its folder created) when ``path`` is given; returns ``fig``."""
    if path is not None:
        from pathlib import Path

        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=dpi)
    return fig


def plot_fit(result, fig=None, n_curve=300, path=None, dpi=120):
    """Data, fit and residuals per force (offset-corrected); returns the Figure.

    Top row: extension minus the molecule's extension offset against turns
    minus its turns offset, with the fitted hat curve. Second row: residuals
    ``data - model``. With torque data (a joint fit) two more rows: the
    measured torque with the fitted torque, and the torque residuals.

    Parameters
    ----------
    result : FitResult
    fig : matplotlib.figure.Figure, optional
        Draw into this (empty) figure; default a new one from ``pyplot``.
    n_curve : int
        Points of each fitted curve.
    path : str or Path, optional
        Also save the figure there (format from the suffix; folder created).
    dpi : float
        Resolution of the saved file (dots per inch).

    Returns
    -------
    matplotlib.figure.Figure
        Shown by nothing here: a notebook displays it, a script calls
        ``matplotlib.pyplot.show()`` (an interactive backend; on Agg, the
        default without a display, nothing appears) or saves it (``path=``
        or ``fig.savefig``).
    """
    import matplotlib.pyplot as plt

    d, c = result.spec.data, result.solution
    forces = np.unique(d.force)
    nf = len(forces)
    torque = d.has_torque
    if fig is None:
        fig = plt.figure(figsize=(min(4.2 * nf, 16), 9.0 if torque else 5.2),
                         layout="constrained")
    axes = fig.subplots(4 if torque else 2, nf, sharex="col", squeeze=False,
                        gridspec_kw={"height_ratios": [3, 1, 3, 1] if torque else [3, 1]})
    for k, f in enumerate(forces):
        ax, axr = axes[0, k], axes[1, k]
        n_sel = _data_panels(result, axes, k, f)
        grid = np.linspace(n_sel.min(), n_sel.max(), n_curve)
        try:
            ax.plot(grid, _curve(result, f, grid), "k-", lw=1.5, label="fit" if k == 0 else None)
        except SupercoilError:
            sel = d.force == f
            order = np.argsort(n_sel)
            z = _nm((c.best_fit[sel] - _z0(c, d.mol_index)[sel])[order])
            ax.plot(n_sel[order], z, "k-", lw=1.5, label="fit" if k == 0 else None)
        ax.set_title(f"F = {display.to_display(f, 'force'):.3g} pN")
        axr.axhline(0, color="k", lw=0.8)
        if torque:
            _torque_panels(result, axes, k, f, grid)
        axes[-1, k].set_xlabel("turns - turns offset")
        if k == 0:
            ax.set_ylabel("extension - offset (nm)")
            axr.set_ylabel("residual (nm)")
    axes[0, 0].legend(fontsize="small")
    text = ", ".join(
        f"{k} = {fmt_pm(result.parameters[k].magnitude, result.stderr[k].magnitude)} "
        f"{result.units[k]}" for k in result.names if result.params[k].owner != "offset")
    if result.weighting == "unit":  # the reduced chi-square is 1 by construction here
        stat = f"noise estimate (residual RMS) {result.residual_rms.magnitude:.3g} nm"
    else:
        stat = f"reduced chi-square {result.reduced_chi_square:.3g}"
    fig.suptitle(f"hat-curve fit ({result.model.name}): {text}; {stat}", fontsize="medium")
    return save_figure(fig, path, dpi)


def plot_comparison(results, fig=None, n_curve=300):
    """Several fits of the same data (one per model): data, every fit and its residuals.

    ``results`` maps a label (the model name) to a :class:`FitResult`. Each
    fit's curve is drawn with its own offsets removed from the data it shows
    (the data points are drawn with the first fit's offsets).
    """
    import matplotlib.pyplot as plt

    first = next(iter(results.values()))
    d = first.spec.data
    forces = np.unique(d.force)
    nf = len(forces)
    if fig is None:
        fig = plt.figure(figsize=(min(4.2 * nf, 16), 5.6), layout="constrained")
    axes = fig.subplots(2, nf, sharex="col", squeeze=False,
                        gridspec_kw={"height_ratios": [3, 1.4]})
    for k, f in enumerate(forces):
        ax, axr = axes[0, k], axes[1, k]
        c = first.solution
        sel = d.force == f
        n_eff = (d.turns - c.turns_offset[d.mol_index])[sel]
        ax.plot(n_eff, _nm(d.extension - _z0(c, d.mol_index))[sel], "o", ms=3,
                color="0.6", label="data" if k == 0 else None)
        grid = np.linspace(n_eff.min(), n_eff.max(), n_curve)
        for j, (label, r) in enumerate(results.items()):
            color = f"C{j}"
            rc = r.solution
            shift = (rc.turns_offset[0] - c.turns_offset[0])
            try:
                ax.plot(grid, _curve(r, f, grid - shift)
                        + _nm(rc.extension_offset[0] - c.extension_offset[0]),
                        "-", color=color, lw=1.4, label=label if k == 0 else None)
            except SupercoilError:
                pass
            resid = _nm(r.spec.data.extension - rc.best_fit)[sel]
            axr.plot(n_eff, resid, ".", ms=3, color=color)
        ax.set_title(f"F = {display.to_display(f, 'force'):.3g} pN")
        axr.axhline(0, color="k", lw=0.8)
        axr.set_xlabel("turns - turns offset")
        if k == 0:
            ax.set_ylabel("extension - offset (nm)")
            axr.set_ylabel("residual (nm)")
    axes[0, 0].legend(fontsize="small")
    fig.suptitle("model comparison: " + ", ".join(
        f"{label}: {r.headline(3)}" for label, r in results.items()), fontsize="medium")
    return fig
