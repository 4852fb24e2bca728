"""Speed against accuracy across the DNA model family: one point per model and interaction.

For every registered model and (for models with a plectoneme helix) every registered
interaction, read from the registries at call time (:func:`cases`):

* ``hat_seconds``: CPU time of one public :func:`supercoil.hat_curve` at :data:`FORCES`
  over ``turns_points`` turns from -N to N (N: supercoiling density +-0.06, past buckling
  and into the plectoneme phase at every force), median of ``repeat`` interleaved runs;
* ``fit_seconds``: CPU time of one :func:`supercoil.fit_hat_curves` (the model's default
  parameters varied) of rotation curves simulated by the reference model at the same
  forces (110 points per force, 5 nm noise, seed 1);
* ``extension_error`` / ``torque_error``: RMS difference (nm, pN nm) of the model's hat
  curves from the reference model's at the same physical parameters, over the points
  where both give a state (no fit: what the model's physics alone misses);
  ``positive_error``: the same for the extension on the positive side (N >= 0) only, where
  no denaturation enters (the reference melts under negative turns above ~0.5 pN, which
  no other construction models);
* ``fit_rms``: extension residual RMS (nm) of that fit (what a fit hides of it);
* ``measured_rms`` (optional): the extension residual RMS of a fit to a user's measured
  rotation curves (``measured=`` a table in the fit-data layout), e.g. the published curves
  of ``examples/fit_published_curves.py``.

Failures are rows too: ``status`` names the exception of the step that failed. The
reference is :data:`REFERENCE` (the most complete registered construction) unless given.
"""

from __future__ import annotations

import time
import warnings

import numpy as np

#: the reference construction (model, interaction): the most complete one registered, the
#: phase ensemble of real DNA (melting tail, up to two plectoneme domains with end loops,
#: fitted to measured curves); a hat curve costs it 100-1000 times a closed-form model's,
#: which a reference pays once
REFERENCE = ("ensemble", None)
#: forces of the hat curves and of the simulated fits (pN)
FORCES = (0.5, 1.0, 2.0)
#: supercoiling density at the ends of the hat curves
SIGMA_MAX = 0.06
_HELICAL_REPEAT_NM = 3.57
UNITS = {"model": "", "interaction": "", "hat_seconds": "s", "fit_seconds": "s",
         "extension_error": "nm", "positive_error": "nm", "torque_error": "pN nm",
         "fit_rms": "nm",
         "measured_rms": "nm", "status": ""}


def cases():
    """``(key, model name, interaction name or None)`` of every registered combination."""
    from supercoil.dna.interactions import available_interactions
    from supercoil.dna.models import available_models, get_model

    out = []
    for name in available_models():
        if get_model(name).uses_interaction:
            out += [(f"{name}/{i}", name, i) for i in available_interactions()]
        else:
            out.append((name, name, None))
    return out


def _kw(model, inter):
    return {"model": model, **({"interaction": inter} if inter else {})}


def _cpu(func, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.process_time()
        value = func()
        times.append(time.process_time() - t0)
    return value, float(np.median(times))


def _hat(dna, turns, model, inter):
    import supercoil as sc

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return sc.hat_curve(dna, list(FORCES) * sc.ureg.pN, turns, **_kw(model, inter))


def _fit(data, dna, model, inter):
    import supercoil as sc

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return sc.fit_hat_curves(data, dna, **_kw(model, inter))


def _rms(a, b):
    d = np.asarray(a, float) - np.asarray(b, float)
    d = d[np.isfinite(d)]
    return float(np.sqrt(np.mean(d * d))) if d.size else np.nan


def _fit_rms(fit):
    return float(fit.residual_rms.m_as("nm"))


def family_precision(dna=None, turns_points=201, repeat=3, reference=REFERENCE,
                     measured=None, only=None, log=None, fit_budget=None):
    """The work-precision rows of every registered model and interaction (dict of lists).

    Parameters
    ----------
    dna : DNA, optional
        The molecule (default the ``dna_150mM_nacl`` set: the screened interaction needs
        a salt).
    turns_points : int
        Turns values per hat curve.
    repeat : int
        CPU-time samples per hat curve (median); fits are timed once.
    reference : (str, str or None)
        The reference construction.
    measured : pandas.DataFrame, optional
        Measured rotation curves (fit-data layout) for ``measured_rms``.
    only : iterable of str, optional
        Keys of :func:`cases` to measure (default all).
    log : callable, optional
        Called with one line per case.
    fit_budget : float, optional
        Skip the fit (``fit_seconds`` and ``fit_rms`` NaN, ``status`` "ok, fit skipped")
        of a construction whose hat curve costs more than this (s): a fit makes ~30-100
        such calls (in ``supercoil bench --quick`` the ensemble's fit was most of the section).
    """
    import supercoil as sc

    dna = dna or sc.load_parameters("dna_150mM_nacl")
    nmax = SIGMA_MAX * dna.length.m_as("nm") / _HELICAL_REPEAT_NM
    turns = np.linspace(-nmax, nmax, turns_points)
    ref = _hat(dna, turns, *reference)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = sc.simulate_rotation_curves(dna, list(FORCES) * sc.ureg.pN, noise=5 * sc.ureg.nm,
                                           seed=1, **_kw(*reference))
    rows = {k: [] for k in UNITS}
    for key, model, inter in cases():
        if only is not None and key not in only:
            continue
        row = dict.fromkeys(UNITS, np.nan)
        row.update(model=model, interaction=inter or "", status="ok")
        try:
            hat, row["hat_seconds"] = _cpu(lambda m=model, i=inter: _hat(dna, turns, m, i),
                                           repeat)
            row["extension_error"] = _rms(hat["extension"], ref["extension"])
            pos = (ref["turns"] >= 0).to_numpy()
            row["positive_error"] = _rms(hat["extension"][pos], ref["extension"][pos])
            row["torque_error"] = _rms(hat["torque"], ref["torque"])
            if fit_budget is not None and row["hat_seconds"] > fit_budget:
                row["status"] = "ok, fit skipped"
            else:
                fit, row["fit_seconds"] = _cpu(lambda m=model, i=inter: _fit(data, dna, m, i),
                                               1)
                row["fit_rms"] = _fit_rms(fit)
            if measured is not None:
                row["measured_rms"] = _fit_rms(_fit(measured, dna, model, inter))
        except Exception as exc:  # a failing model is a row of the chart, named
            row["status"] = f"{type(exc).__name__}: {exc}"[:200]
        for k in UNITS:
            rows[k].append(row[k])
        if log:
            log(f"  {model}/{inter or '-'}: hat {row['hat_seconds']:.3g} s, fit "
                f"{row['fit_seconds']:.3g} s, error {row['extension_error']:.3g} nm "
                f"(N >= 0: {row['positive_error']:.3g} nm) "
                f"({row['status']})")
    return rows


def plot(table, path, reference=REFERENCE):
    """Two panels: error against the reference versus cost per hat curve and per fit."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    ok = table[table["status"].str.startswith("ok")]
    for ax, cost, label in ((axes[0], "hat_seconds", "CPU time per hat curve [s]"),
                            (axes[1], "fit_seconds", "CPU time per fit [s]")):
        for k, (_, r) in enumerate(ok.iterrows()):
            inter = r["interaction"]  # "" or NaN (read back from CSV) without interaction
            name = r["model"] + (f"/{inter}" if isinstance(inter, str) and inter else "")
            err, pos = float(r["extension_error"]), float(r["positive_error"])
            if not err > 0:  # the reference itself: its cost as a line (0 has no log place)
                ax.axvline(r[cost], color="k", ls="--", lw=0.8)
                ax.annotate(f"{name} (reference)", (r[cost], 0.5), xycoords=("data", "axes "
                            "fraction"), rotation=90, fontsize=7, ha="right", va="center")
                continue
            (dot,) = ax.loglog(r[cost], err, "o")
            if np.isfinite(pos) and pos > 0:
                ax.loglog(r[cost], pos, "^", mfc="none", color=dot.get_color())
            ax.annotate(name, (r[cost], err), fontsize=7, xytext=(3, 3 + 8 * (k % 3)),
                        textcoords="offset points")
        ax.set_xlabel(label)
        ax.set_ylabel("RMS extension difference from the reference [nm]\n"
                      "(dots: all turns; open triangles: N >= 0)", fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
    fig.suptitle("DNA model family: cost against difference from the reference "
                 f"({' / '.join(x for x in reference if x)})", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
