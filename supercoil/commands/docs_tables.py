"""The tables behind the README's generated blocks, and their Markdown.

Each ``*_table`` function turns what a script wrote (a convention table read by
:func:`supercoil.read_csv`) into the small table a block shows (again a convention
table: it is kept as ``docs/generated/data/NAME.csv``); each ``*_markdown`` function
renders one as a Markdown table. :data:`RENDERERS` maps a block name to its renderer;
``tests/test_readme_numbers.py`` re-renders the kept tables and compares.
"""

from __future__ import annotations

import numpy as np

from supercoil.tables import make_table, provenance


def markdown_table(headers, rows) -> str:
    """A GitHub Markdown table: ``headers`` (strings) over ``rows`` (lists of strings)."""
    lines = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(headers)]
    lines += ["| " + " | ".join(str(c).replace("|", "\\|") for c in r) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def _g(x, digits=4):
    return f"{float(x):.{digits}g}"


# ---- validation: `supercoil validate` -> quantity, model, rows, min-max |relative error| ----


def validation_summary(table):
    """Per (quantity, model): the number of compared rows and the range of |relative error|
    (and of |relative error| in the trap's torque units, where a set gives a torque scale)."""
    ok = table.dropna(subset=["relative_error"])
    cols = {"quantity": [], "model": [], "rows": [], "min_abs_relative_error": [],
            "max_abs_relative_error": [], "min_abs_relative_error_trap_torque": [],
            "max_abs_relative_error_trap_torque": []}
    for (q, model), g in ok.groupby(["quantity", "model"], sort=False):
        err = g["relative_error"].abs()
        trap = g["relative_error_trap_torque"].abs().dropna()
        values = (q, model, len(g), err.min(), err.max(),
                  trap.min() if len(trap) else float("nan"),
                  trap.max() if len(trap) else float("nan"))
        for key, value in zip(cols, values, strict=True):
            cols[key].append(value)
    units = dict.fromkeys(cols, "")
    return make_table(cols, units, provenance(None, source="supercoil validate",
                                              **_source(table)))


def validation_markdown(summary) -> str:
    def span(lo, hi):
        return "-" if not np.isfinite(lo) else f"{lo:.3f} - {hi:.3f}"

    rows = [[r.quantity, f"`{r.model}`", int(r.rows),
             span(r.min_abs_relative_error, r.max_abs_relative_error),
             span(r.min_abs_relative_error_trap_torque, r.max_abs_relative_error_trap_torque)]
            for r in summary.itertuples(index=False)]
    return markdown_table(["quantity", "model", "rows", "abs. relative error (min - max)",
                           "same, prediction / torque scale"], rows)


# ---- main job: `supercoil hat` buckling.csv per model -------------------------------------------


def main_job_table(by_model):
    """Long table (model, force, N_b, buckling torque, slope) from each model's buckling.csv."""
    cols = {"model": [], "force": [], "buckling_turns": [], "buckling_torque": [],
            "post_buckling_slope": []}
    for model, t in by_model.items():
        for r in t.itertuples(index=False):
            for key, value in zip(cols, (model, r.force, r.buckling_turns, r.buckling_torque,
                                         r.post_buckling_slope), strict=True):
                cols[key].append(value)
    first = next(iter(by_model.values()))
    units = {"model": "", **{k: first.attrs["units"][k] for k in list(cols)[1:]}}
    prov = first.attrs.get("provenance", {})
    return make_table(cols, units, provenance(
        None, source="supercoil hat --params dna --model MODEL (buckling.csv)",
        parameters_of_the_run=prov.get("parameters", {}), thermal=prov.get("thermal")))


def main_job_markdown(table) -> str:
    u = table.attrs["units"]
    rows = [[f"`{r.model}`", _g(r.force), _g(r.buckling_turns), _g(r.buckling_torque),
             _g(r.post_buckling_slope)] for r in table.itertuples(index=False)]
    return markdown_table(["model", f"force [{u['force']}]", "buckling turns N_b",
                           f"buckling torque [{u['buckling_torque']}]",
                           f"post-buckling slope dz/dN [{u['post_buckling_slope']}]"], rows)


# ---- fit example: examples/fit_tweezers_data.py fit_parameters.csv ------------------------------


def fit_example_table(fit_parameters):
    """One row per fitted parameter (value, standard error, unit), then the fit's statistics."""
    row = fit_parameters.iloc[0]
    units = fit_parameters.attrs["units"]
    names = [c for c in fit_parameters.columns if f"{c}_stderr" in fit_parameters.columns]
    stats = ("residual_rms", "ndata")  # (the reduced chi-square of a fit without sigma is 1
    # by construction: the noise estimate residual_rms is the fit-quality number)
    cols = {"parameter": [*names, *stats],
            "value": [float(row[n]) for n in (*names, *stats)],
            "stderr": [*(float(row[f"{n}_stderr"]) for n in names), *[np.nan] * len(stats)],
            "unit": [units[n] for n in (*names, *stats)]}
    return make_table(cols, dict.fromkeys(cols, ""), provenance(
        None, source="examples/fit_tweezers_data.py (fit_parameters.csv)",
        **_source(fit_parameters)))


def fit_example_markdown(table) -> str:
    rows = []
    for r in table.itertuples(index=False):
        err = "" if not np.isfinite(r.stderr) else _g(r.stderr, 2)
        unit = r.unit if isinstance(r.unit, str) else ""  # "" reads back as NaN
        rows.append([f"`{r.parameter}`", _g(r.value, 5), err, unit])
    return markdown_table(["parameter", "fitted value", "standard error", "unit"], rows)


# ---- models: the registry itself -------------------------------------------------------------


def _default_in_unit(p):
    """A ModelParameter's SI default expressed in its own display unit."""
    from supercoil.units import ureg

    if not p.unit:
        return p.default
    factor = ureg.Quantity(1.0, p.unit).to_base_units().magnitude
    return p.default / factor


def models_markdown() -> str:
    """Every model the package registers: name, summary, own parameters with units, defaults.

    Models registered by user code (``register_model`` from outside the package) are not
    the package's and are left out.
    """
    from supercoil.dna.models import available_models, get_model

    rows = []
    for name in available_models():
        m = get_model(name)
        if not type(m).__module__.startswith("supercoil."):
            continue
        params = "; ".join(
            f"`{p.name}` = {_g(_default_in_unit(p))}{' ' + p.unit if p.unit else ''} "
            f"({p.description})" for p in m.parameters.values()) or "none"
        interaction = "yes" if m.uses_interaction else "no"
        rows.append([f"`{name}`", m.summary, interaction, params])
    return markdown_table(["model", "summary", "takes an interaction", "own parameters "
                           "(default)"], rows)


# ---- family: `supercoil bench` family_precision.csv -> one row per construction ---------------


def family_table(fam):
    """The work-precision rows of the model family (``family_precision.csv``), cheapest first."""
    fam = fam.assign(construction=[m + (f"/{i}" if isinstance(i, str) and i else "")
                                   for m, i in zip(fam["model"], fam["interaction"],
                                                   strict=True)])
    fam = fam.sort_values("hat_seconds", kind="stable", na_position="last")
    keys = ("construction", "hat_seconds", "fit_seconds", "extension_error", "positive_error",
            "torque_error", "fit_rms", "status")
    cols = {k: list(fam[k]) for k in keys}
    units = {"construction": "", "hat_seconds": "s", "fit_seconds": "s",
             "extension_error": "nm", "positive_error": "nm", "torque_error": "pN nm",
             "fit_rms": "nm", "status": ""}
    prov = fam.attrs.get("provenance", {})
    return make_table(cols, units, provenance(None, source="supercoil bench",
                                              reference=prov.get("reference"),
                                              forces_pN=prov.get("forces_pN"),
                                              **_source(fam)))


def family_markdown(table) -> str:
    def num(x, scale=1.0, digits=3):
        return "-" if not np.isfinite(float(x)) else f"{float(x) * scale:.{digits}g}"

    rows = [[f"`{r.construction}`", num(r.hat_seconds, 1e3), num(r.fit_seconds),
             num(r.extension_error), num(r.positive_error), num(r.torque_error), num(r.fit_rms),
             r.status]
            for r in table.itertuples(index=False)]
    ref = table.attrs.get("provenance", {}).get("reference")
    ref = "/".join(str(x) for x in ref if x) if isinstance(ref, list | tuple) else str(ref)
    return (markdown_table(["construction", "hat curve CPU (ms)", "fit CPU (s)",
                            "RMS extension difference (nm)", "same, N >= 0 (nm)",
                            "RMS torque difference (pN nm)",
                            "fit residual RMS (nm)", "status"], rows)
            + f"\nReference: `{ref}` (its own row: difference 0). Differences at the same "
            "physical parameters, no fit; the fit is to curves simulated by the reference "
            "(5 nm noise).\n")


def _source(table):
    prov = table.attrs.get("provenance", {})
    return {"supercoil_version_of_the_run": prov.get("supercoil_version")}


#: block name -> renderer of its kept table (``models`` renders the registry: no table)
RENDERERS = {"validation": validation_markdown, "main-job": main_job_markdown,
             "fit-example": fit_example_markdown, "family": family_markdown}
