"""Model comparison: fit several DNA models to the same data, rank them by AIC and BIC.

Statistics as lmfit defines them (lmfit documentation, "Goodness-of-Fit
Statistics"), with N data points, ``N_varys`` free parameters (offsets
included) and ``chi2`` the sum of squared weighted residuals:

* ``chi_square = chi2``; ``reduced_chi_square = chi2 / (N - N_varys)``;
* ``aic = N ln(chi2 / N) + 2 N_varys`` (Akaike information criterion);
* ``bic = N ln(chi2 / N) + ln(N) N_varys`` (Bayesian information criterion),

computed by :class:`~supercoil.dna.fitting.result.FitResult` (``aic``,
``bic``); ``N_varys`` counts only the parameters the data determine (an
undetermined one, a flat direction of the Jacobian, buys nothing and costs
nothing).

Lower is better; only differences between models fitted to the same data with
the same weights mean anything (``delta_aic``, ``delta_bic`` from the best).
With unit weights ``chi2`` in the criteria is the sum of squares in nm^2, which
shifts every model's AIC by the same constant (the table's ``chi_square`` is
the dimensionless one, :attr:`FitResult.chisqr`).

A joint extension + torque fit has one such term per channel c with n_c
points, ``sum_c n_c ln(chi2_c / n_c)`` (the Gaussian log-likelihood with each
channel's noise profiled out). ``chi2_c`` uses the channel's stated sigmas, or
its fixed unit scale (1 nm, 1 pN nm) where the fit estimated the noise: the
estimated noise itself differs between models and must not enter the
criterion (with it every model's ``chi2`` would be ``N``).
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import pandas as pd

from supercoil._checks import check_flag
from supercoil.dna.fitting.fit import emit, run_fit
from supercoil.dna.fitting.options import DEFAULT_VARY, DEFAULTS, FitOptions
from supercoil.dna.fitting.prepare import prepare
from supercoil.dna.fitting.result import FitResult
from supercoil.dna.models import get_model
from supercoil.exceptions import SupercoilError
from supercoil.tables import make_table, provenance

__all__ = ["Comparison", "compare_models", "information_criteria", "model_labels"]


def information_criteria(chi2, ndata, nvarys):
    """``(aic, bic)`` as lmfit defines them (see the module docstring)."""
    core = ndata * math.log(chi2 / ndata)
    return core + 2 * nvarys, core + math.log(ndata) * nvarys


def _fit_one(data, dna, model, vary, own, options):
    m = get_model(model)
    added = [k for k in m.parameters if own and k not in vary]
    names = list(vary) + added
    # the default DNA fields and the model's own parameters added here are dropped when the
    # model does not use them (marko2007 has no radius; without the loop, no loop writhe)
    optional = added + (list(DEFAULT_VARY) if tuple(vary) == DEFAULT_VARY else [])
    interaction = options.interaction if m.uses_interaction else None
    spec = prepare(data, dna, options.replace(vary=names, model=m, interaction=interaction),
                   optional=optional)
    return FitResult(run_fit(spec, time_curve=True), spec, data, dna)


def _row(label, result, error):
    text = "" if error is None else f"{type(error).__name__}: {error}"
    argument = getattr(error, "argument", None)
    argument = ", ".join(argument) if isinstance(argument, (tuple, list)) else argument or ""
    row = {"model": label, "success": result is not None, "error": text,
           "error_argument": argument}
    if result is None:
        return row, {}
    n, k = result.ndata, result.n_determined
    aic, bic = result.aic, result.bic  # undetermined parameters are not counted
    row.update(nparams=k, ndata=n, chi_square=result.chi_square,
               reduced_chi_square=result.reduced_chi_square, aic=aic, bic=bic,
               cpu_seconds=result.cpu_seconds, curve_cpu_seconds=result.curve_cpu_seconds,
               residual_rms=result.residual_rms.m_as("nm"),
               goodness_p=result.goodness.get("p_value", np.nan),
               warnings="; ".join(result.warnings))
    units = {"residual_rms": "nm", "cpu_seconds": "s", "curve_cpu_seconds": "s"}
    for name in result.names:
        row[name] = result.parameters[name].magnitude
        row[f"{name}_stderr"] = result.stderr[name].magnitude
        units[name] = units[f"{name}_stderr"] = result.units[name]
    return row, units


def _assemble(rows, units):
    stats = ["model", "success", "error", "error_argument", "nparams", "ndata", "chi_square",
             "reduced_chi_square", "aic", "bic", "delta_aic", "delta_bic", "cpu_seconds",
             "curve_cpu_seconds", "residual_rms", "goodness_p"]
    params = list(dict.fromkeys(k for r in rows for k in r if k not in stats
                                and k != "warnings"))
    aics = [r.get("aic", np.nan) for r in rows]
    bics = [r.get("bic", np.nan) for r in rows]
    best_a = np.nanmin(aics) if np.isfinite(aics).any() else np.nan
    best_b = np.nanmin(bics) if np.isfinite(bics).any() else np.nan
    cols = {}
    for key in [*stats, *params, "warnings"]:
        col = []
        for r, a, b in zip(rows, aics, bics, strict=True):
            if key == "delta_aic":
                col.append(a - best_a)
            elif key == "delta_bic":
                col.append(b - best_b)
            else:
                col.append(r.get(key, "" if key in ("error", "error_argument", "warnings")
                                 else np.nan))
        cols[key] = col
    cols["nparams"] = [int(v) if np.isfinite(v) else 0 for v in cols["nparams"]]
    cols["ndata"] = [int(v) if np.isfinite(v) else 0 for v in cols["ndata"]]
    all_units = {k: units.get(k, "") for k in cols}
    return cols, all_units


def compare_models(data, dna, models, vary=DEFAULTS.vary, fixed=DEFAULTS.fixed,
                   bounds=DEFAULTS.bounds, *, start=DEFAULTS.start, sigma=DEFAULTS.sigma,
                   fit_turns_offset=DEFAULTS.fit_turns_offset,
                   fit_extension_offset=DEFAULTS.fit_extension_offset,
                   thermal=DEFAULTS.thermal, interaction=DEFAULTS.interaction,
                   max_nfev=DEFAULTS.max_nfev, tol=DEFAULTS.tol, return_results=None):
    """Fit several DNA models to the same data, rank them by AIC: a :class:`Comparison`.

    Parameters
    ----------
    data, dna, fixed, bounds, start, sigma, fit_turns_offset, fit_extension_offset,
    thermal, max_nfev, tol
        As for :func:`fit_hat_curves` (the same for every model; e.g. ``start=
        {"turns_offset": 0.0}`` for one-sided curves, where the guess from the
        centre of symmetry fails).
    vary : sequence of str, or dict of model name -> sequence of str
        A sequence: the DNA fields fitted for every model, each model's own
        parameters (``model.parameters``) varied as well. A dict: exactly the
        parameters varied per model (DNA fields and model parameters; a model
        missing from it gets the default ``("twist_persistence", "radius")``);
        a key is a row's label or a model name.
    models : sequence of str or DNAModel
        The models (registered names or instances), at least one, each once.
        A row's ``model`` label (and the key of its result) is the model's
        name, followed by the options and parameters that differ from the
        defaults: ``"marko2007(end_loop=True)"`` (:func:`model_labels`).
    interaction : str or Interaction
        For the models with a plectoneme helix (others take none).
    return_results : bool, optional
        Deprecated: ``True`` returns the old pair ``(comparison.table,
        comparison.results)``; the :class:`Comparison` holds both.

    Returns
    -------
    Comparison
        ``table``: one row per model, sorted by AIC (best first): ``model``,
        ``success``, ``error`` (a failed fit), ``error_argument`` (the keyword
        its error is about, or empty), ``nparams`` (free parameters
        the data determine, offsets included: those AIC and BIC count),
        ``ndata``, ``chi_square``, ``reduced_chi_square`` (dimensionless),
        ``aic``, ``bic``, ``delta_aic``, ``delta_bic`` (from the best model),
        ``cpu_seconds`` (CPU time of the fit, ``time.process_time``, s),
        ``curve_cpu_seconds`` (CPU time of one evaluation of the model's hat
        curve at the data points, s), ``residual_rms`` (nm), ``goodness_p``
        (p-value of the goodness-of-fit test, see
        :mod:`supercoil.dna.fitting.diagnostics`), every fitted parameter
        and its ``_stderr`` (NaN for models without it), ``warnings``;
        ``attrs["units"]`` and ``attrs["provenance"]``; the definitions are
        those of lmfit (module docstring). ``results``: the
        :class:`FitResult` of each model that was fitted, by row label.

    Raises
    ------
    ValueError
        No model, or the same model (class, options and parameter values)
        given twice.

    Warns
    -----
    The warnings of each fit, prefixed by the row label.
    """
    if return_results is not None:
        return_results = check_flag(return_results, "return_results")
        warnings.warn("compare_models(return_results=...) is deprecated: the Comparison it "
                      "returns holds the table (.table) and the fits (.results)",
                      DeprecationWarning, stacklevel=2)
    models = _model_list(models)
    if not models:
        raise ValueError("compare_models needs at least one model")
    options = FitOptions(DEFAULTS.vary, fixed, bounds, start, sigma, fit_turns_offset,
                         fit_extension_offset, thermal, max_nfev, tol, DEFAULTS.model,
                         interaction)
    rows, units, results, errors = [], {}, {}, {}
    for spec, label in zip(models, model_labels(models), strict=True):
        name = get_model(spec).name
        names = (vary.get(label, vary.get(name, DEFAULT_VARY)) if isinstance(vary, dict)
                 else vary)
        names = [names] if isinstance(names, str) else list(names)
        result, error = None, None
        try:
            with warnings.catch_warnings(record=True):  # re-issued below with the model name
                result = _fit_one(data, dna, spec, names, not isinstance(vary, dict), options)
        except SupercoilError as exc:
            error = errors[label] = exc
        if result is not None:
            results[label] = result
            emit([(_category(m, result), m) for m in result.warnings],
                 prefix=f"model {label}: ")
        row, u = _row(label, result, error)
        rows.append(row)
        units.update(u)
    rows.sort(key=lambda r: r.get("aic", np.inf))
    cols, all_units = _assemble(rows, units)
    prov = provenance(dna, models=[r["model"] for r in rows],
                      vary={k: list(v) for k, v in vary.items()} if isinstance(vary, dict)
                      else list(vary),
                      thermal=thermal, interaction=_interaction_name(interaction),
                      criteria="lmfit: aic = N ln(chi2/N) + 2 k, bic = N ln(chi2/N) + ln(N) k",
                      cost="time.process_time of each fit and of one hat-curve evaluation")
    comparison = Comparison(make_table(cols, all_units, prov),
                            {r["model"]: results[r["model"]] for r in rows
                             if r["model"] in results}, errors)
    if return_results is None:
        return comparison
    return (comparison.table, comparison.results) if return_results else comparison.table


def _deprecated_frame_use(what):
    warnings.warn(f"using the result of compare_models as a DataFrame ({what}) is deprecated: "
                  "use its .table", DeprecationWarning, stacklevel=3)


@dataclasses.dataclass(frozen=True, eq=False)
class Comparison:
    """The result of :func:`compare_models`: the ranked table and every model's fit.

    Attributes
    ----------
    table : pandas.DataFrame
        One row per model, best AIC first (columns in :func:`compare_models`),
        ``attrs["units"]`` and ``attrs["provenance"]``.
    results : dict of str -> FitResult
        The fit of each model that converged, by row label, in the table's order.
    errors : dict of str -> SupercoilError
        The error of each model whose fit failed, by row label (its ``argument`` names
        the keyword it is about; the table's ``error`` and ``error_argument`` columns
        hold its text and that name).

    For old call sites the DataFrame's attributes and items (``comparison["aic"]``,
    ``comparison.iloc[0]``) still work, with a DeprecationWarning.
    """

    table: pd.DataFrame
    results: dict
    errors: dict = dataclasses.field(default_factory=dict)

    @property
    def best(self) -> str | None:
        """The label of the model with the lowest AIC (None when every fit failed)."""
        ok = self.table[self.table["success"]]
        return None if ok.empty else str(ok["model"].iloc[0])

    def report(self, error_text=None) -> str:
        """The ranked table as text (AIC, BIC, CPU cost), then each model's fit report.

        ``error_text``: None writes a failed row's ``error`` text; a callable is given the
        row's exception (:attr:`errors`) and returns its text (the command line passes its
        wording, the flag of the exception's ``argument`` first).
        """
        lines = ["[[Model comparison]] ranked by AIC (lmfit's definitions: aic = N ln(chi2/N) "
                 "+ 2k, bic = N ln(chi2/N) + ln(N) k; lower is better; CPU seconds per fit "
                 "and per hat-curve evaluation)",
                 f"    {'model':<16}{'k':>4}{'chi-square':>14}{'AIC':>12}{'dAIC':>10}"
                 f"{'BIC':>12}{'dBIC':>10}{'fit CPU s':>11}{'curve CPU s':>13}"]
        for _, row in self.table.iterrows():
            if not row["success"]:
                exc = self.errors.get(row["model"])
                text = row["error"] if error_text is None or exc is None else error_text(exc)
                lines.append(f"    {row['model']:<16}  FAILED: {text}")
                continue
            lines.append(f"    {row['model']:<16}{row['nparams']:>4}{row['chi_square']:>14.6g}"
                         f"{row['aic']:>12.2f}{row['delta_aic']:>10.2f}{row['bic']:>12.2f}"
                         f"{row['delta_bic']:>10.2f}{row['cpu_seconds']:>11.3g}"
                         f"{row['curve_cpu_seconds']:>13.3g}")
        for name, result in self.results.items():
            lines += ["", f"==== model {name} ====", result.report()]
        return "\n".join(lines)

    def plot(self, fig=None, n_curve=300):
        """Data, every model's fit and residuals (:func:`plot_comparison`); the Figure."""
        from supercoil.dna.fitting.plot import plot_comparison

        return plot_comparison(self.results, fig=fig, n_curve=n_curve)

    def __repr__(self):
        rows = ", ".join(f"{m} (dAIC {d:.3g})" for m, d, ok in zip(
            self.table["model"], self.table["delta_aic"], self.table["success"], strict=True)
            if ok)
        return f"<Comparison of {len(self.table)} models: {rows or 'every fit failed'}>"

    def _repr_html_(self):
        return self.table._repr_html_()

    # ---- the DataFrame the function returned before (old call sites) ----
    def __getattr__(self, name):
        if name.startswith("__") or name in ("table", "results"):
            raise AttributeError(name)
        value = getattr(self.table, name)
        _deprecated_frame_use(f".{name}")
        return value

    def __getitem__(self, key):
        _deprecated_frame_use("[...]")
        return self.table[key]

    def __len__(self):
        return len(self.table)


def _interaction_name(interaction):
    """The provenance entry of ``interaction``: its registry name (a name or an instance)."""
    from supercoil.dna.interactions.base import Interaction

    return str(interaction.name if isinstance(interaction, Interaction) else interaction)


def _model_list(models):
    """``models`` as a list: one name or model, or a sequence of them; TypeError otherwise."""
    from supercoil.dna.models.base import DNAModel

    if isinstance(models, str | DNAModel):
        return [models]
    try:
        return list(models)
    except TypeError:
        raise TypeError("models must be a model name, a DNAModel or a sequence of them, got "
                        f"{type(models).__name__}") from None


def model_labels(models):
    """One distinct label per model: its name, with its non-default options and parameters.

    ``["marko2007", Marko2007(end_loop=True)]`` gives ``["marko2007",
    "marko2007(end_loop=True)"]``: the rows of :func:`compare_models` and the
    keys of its results stay apart (on main both were ``"marko2007"`` and the
    dict kept one of the two results).

    Raises
    ------
    ValueError
        Two entries are the same model (same class, options and parameter
        values): the fit would be repeated under one label.
    """
    resolved = [get_model(spec) for spec in models]
    labels = []
    for i, m in enumerate(resolved):
        for j in range(i):
            if resolved[j] == m:
                raise ValueError(f"models[{j}] and models[{i}] are the same model ({m.name!r}"
                                 f"{_details(m, '.6g') or ''}): give each model once")
        labels.append(m.name + _details(m, ".6g"))
    for i, m in enumerate(resolved):  # equal to 6 digits but not equal: every digit
        if labels.count(labels[i]) > 1:
            labels[i] = m.name + _details(m, ".17g")
    return labels


def _details(m, fmt):
    """``"(option=..., parameter=...)"`` for what differs from the defaults, else ``""``."""
    defaults = m.option_defaults()
    parts = [f"{k}={v}" for k, v in m.options().items() if v != defaults[k]]
    for k, q in m.quantities().items():
        if m.values[k] != m.parameters[k].default:
            parts.append(f"{k}={format(q, fmt + '~P')}")
    return f"({', '.join(parts)})" if parts else ""


def _category(message, result):
    for cat, msg in result.warning_records:
        if msg == message:
            return cat
    return "FitWarning"
