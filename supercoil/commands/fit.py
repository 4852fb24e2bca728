"""``supercoil fit DATA.csv``: fit hat curves to magnetic-tweezers rotation curves.

Example::

    supercoil fit data.csv --vary twist_persistence radius --out DIR

``DATA.csv`` is a long table read by :func:`supercoil.read_tweezers_csv`
(``force [pN]``, ``turns``, ``extension [um]``, optional ``molecule``,
``sigma [nm]``, ``torque [pN nm]`` and ``torque_sigma [pN nm]``; with a torque
column extension and torque are fitted jointly, docs/theory/fitting.md#joint-torque-fit).
With one molecule (or ``--global``: all molecules share the
physical parameters, each keeps its own offsets) the command writes

* ``DIR/fit_report.txt``: the fit report (parameter table with units);
* ``DIR/fit_parameters.csv``: the estimates and standard errors (one row);
* ``DIR/fit_points.csv``: data, best fit and residual per point;
* ``DIR/fit.png``: data, fit and residuals per force.

With several molecules (and no ``--global``) each molecule is fitted alone
(:func:`supercoil.fit_many`, ``--jobs N`` processes) and the command writes
``fit_molecules.csv`` (one row per molecule; failed fits are reported there
and on stderr, they do not stop the batch), ``fit_report.txt`` and
``fit_molecules.png``; progress goes to stderr (a bar on a terminal, one line
per molecule in a log; ``--no-progress``: none). The exit status
is 1 when a molecule's fit failed or left a parameter not determined (column
``determined``), else 0. Error messages name the command's flags
(``--no-turns-offset``, ``--fix``, ...).
"""

from __future__ import annotations

import argparse
import sys
import warnings


def _assignment(text):
    name, sep, value = text.partition("=")
    if not sep or not name.strip() or not value.strip():
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE, got {text!r}")
    return name.strip(), value.strip()


def _parse_quantity(text, what):
    """One finite number with its unit; ArgumentTypeError naming ``what`` (the flag) else.

    pint reads ``[1,2]nm`` as 12 nm and ``nan`` as a number: both are refused here
    (a bad ``--fix`` value exits 2 naming the flag, no traceback).
    """
    import math

    from supercoil.units import ureg

    if any(c in text for c in "[],;"):
        raise argparse.ArgumentTypeError(f"cannot read {what} {text!r}: give one number with "
                                         "its unit, e.g. 2nm")
    try:
        q = ureg.Quantity(text)
    except Exception as exc:  # pint raises several parser errors
        raise argparse.ArgumentTypeError(f"cannot read {what} {text!r}: {exc}") from None
    m = q.magnitude
    if not (isinstance(m, int | float) and math.isfinite(m)):
        raise argparse.ArgumentTypeError(f"cannot read {what} {text!r}: the value must be "
                                         "one finite real number (with its unit)")
    return q


def register(sub):
    p = sub.add_parser(
        "fit",
        help="fit hat curves to magnetic-tweezers rotation curves (CSV)",
        description="Fit a DNA hat-curve model (documentation: theory page Fitting) to "
        "extension-versus-turns "
        "data at several forces: shared physical parameters, per-molecule turns and extension "
        "offsets, least squares with uncertainties. Repeat --model to compare models (AIC, "
        "BIC).",
    )
    p.add_argument("data", help="CSV: force [pN], turns, extension [um], optional molecule, "
                   "sigma [nm], torque [pN nm], torque_sigma [pN nm]")
    p.add_argument("--params", default="dna", help="DNA parameter set (start values and fixed "
                   "values; default: dna)")
    p.add_argument("--vary", nargs="+", default=["twist_persistence", "radius"],
                   metavar="NAME", help="parameters to fit: DNA fields (length, "
                   "bending_persistence, twist_persistence, radius) and the parameters the "
                   "model and the interaction declare (default: twist_persistence radius)")
    p.add_argument("--fix", action="append", type=_assignment, default=[], metavar="NAME=VALUE",
                   help="hold a parameter fixed, e.g. --fix length=760nm or --fix turns_offset=0")
    p.add_argument("--start", action="append", type=_assignment, default=[],
                   metavar="NAME=VALUE", help="start value, e.g. --start twist_persistence=100nm")
    p.add_argument("--bound", action="append", type=_assignment, default=[],
                   metavar="NAME=LO:HI", help="bounds with units, e.g. --bound radius=1nm:3nm "
                   "(leave a side empty for none: radius=:3nm)")
    p.add_argument("--sigma", default=None, help="extension standard error, e.g. 5nm "
                   "(default: the data's sigma column, else unit weights)")
    p.add_argument("--no-turns-offset", action="store_true", help="do not fit the turns offset")
    p.add_argument("--no-extension-offset", action="store_true",
                   help="do not fit the extension offset")
    p.add_argument("--athermal", action="store_true",
                   help="athermal hat curve (C_eff = C, zeta = 1)")
    p.add_argument("--model", action="append", default=None, metavar="NAME",
                   help="DNA model (default li-zhao); repeat to fit several models to the same "
                   "data and compare them (writes fit_comparison.csv and .png)")
    p.add_argument("--interaction", default="hard-core", metavar="NAME",
                   help="plectoneme interaction (default hard-core)")
    p.add_argument("--end-loop", action="store_true",
                   help="add the plectoneme end loop to every --model (documentation: theory page "
                   "The plectoneme end loop; "
                   "models free-energy and marko2007)")
    p.add_argument("--drop-incomplete", action="store_true",
                   help="drop rows with empty cells (listed in a warning) instead of failing")
    p.add_argument("--global", dest="global_fit", action="store_true",
                   help="one fit for all molecules (shared physical parameters)")
    p.add_argument("--jobs", type=int, default=1,
                   help="worker processes for per-molecule fits (default 1)")
    p.add_argument("--out", default="fit_out", help="output folder (default: fit_out)")
    p.add_argument("--no-plot", action="store_true", help="do not write the figure")
    p.add_argument("--no-progress", action="store_true",
                   help="no progress bar or lines on stderr (several molecules)")
    p.set_defaults(func=run)


def _bounds(items):
    out = {}
    for name, value in items:
        lo, sep, hi = value.partition(":")
        if not sep:
            raise argparse.ArgumentTypeError(f"--bound {name}={value}: expected LO:HI")
        out[name] = (
            _parse_quantity(lo, f"--bound {name} (lower)") if lo.strip() else None,
            _parse_quantity(hi, f"--bound {name} (upper)") if hi.strip() else None,
        )
    return out


def _models(args):
    """``(models, None)``: the --model instances (each once, with --end-loop); or ``(_, error)``."""
    from supercoil.commands.hat import check_names, model_with_options

    names = list(dict.fromkeys(args.model or ["li-zhao"]))
    problem = check_names("fit", names, args.interaction)
    models = []
    for name in names if not problem else []:
        model, problem = model_with_options("fit", name, args.end_loop)
        if problem:
            break
        models.append(model)
    return models, problem


def run(args) -> int:
    from pathlib import Path

    from supercoil.commands._common import warning_text
    from supercoil.dna.fitting import fit_hat_curves
    from supercoil.dna.material import DNA
    from supercoil.dna.tweezers import read_tweezers_csv
    from supercoil.exceptions import ParameterError
    from supercoil.parameters import load_parameters
    from supercoil.tables import write_csv

    try:
        fixed = {k: _parse_quantity(v, f"--fix {k}") for k, v in args.fix}
        start = {k: _parse_quantity(v, f"--start {k}") for k, v in args.start}
        bounds = _bounds(args.bound)
        sigma = _parse_quantity(args.sigma, "--sigma") if args.sigma else None
        if args.jobs < 1:
            raise argparse.ArgumentTypeError(f"--jobs must be at least 1, got {args.jobs}")
    except argparse.ArgumentTypeError as exc:
        print(f"supercoil fit: error: {exc}", file=sys.stderr)
        return 2

    models, problem = _models(args)
    if problem:
        print(problem, file=sys.stderr)
        return 2
    dna = load_parameters(args.params)
    if not isinstance(dna, DNA):
        raise ParameterError(f"parameter set {args.params!r} is not a DNA set")
    out = Path(args.out)
    options = {
        "sigma": sigma,
        "fit_turns_offset": not args.no_turns_offset,
        "fit_extension_offset": not args.no_extension_offset,
        "thermal": not args.athermal,
        "interaction": args.interaction,
    }
    if len(models) > 1:
        return _run_compare(args, models, dna, fixed, bounds, dict(options, start=start), out)
    options["model"] = models[0]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        data = read_tweezers_csv(args.data, drop_incomplete=args.drop_incomplete)
        molecules = data["molecule"].astype(str).unique() if "molecule" in data.columns else []
        many = len(molecules) > 1 and not args.global_fit
        # errors name their argument (``exc.argument``): the command prints its flag
        if many:
            table = _run_many(args, data, dna, fixed, bounds, start, options)
        else:
            result = fit_hat_curves(data, dna, vary=args.vary, fixed=fixed, bounds=bounds,
                                    start=start, **options)
    for w in caught:
        print(warning_text("fit", w.message), file=sys.stderr)
    out.mkdir(parents=True, exist_ok=True)
    if many:
        csv = write_csv(table, out / "fit_molecules.csv")
        report = _many_report(table, args)
        (out / "fit_report.txt").write_text(report + "\n")
        print(report)
        print(f"wrote {csv}")
        if not args.no_plot:
            _plot_many(table, args.vary, out / "fit_molecules.png")
            print(f"wrote {out / 'fit_molecules.png'}")
        return 0 if (table["success"] & table["determined"]).all() else 1
    return _write_single(result, out, args)


def _write_single(result, out, args):
    from supercoil.tables import write_csv

    report = result.report()
    (out / "fit_report.txt").write_text(report + "\n")
    print(report)
    write_csv(result.to_frame(), out / "fit_parameters.csv")
    write_csv(result.points_frame(), out / "fit_points.csv")
    print(f"wrote {out / 'fit_report.txt'}, {out / 'fit_parameters.csv'}, "
          f"{out / 'fit_points.csv'}")
    if not args.no_plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig = result.plot()
        fig.savefig(out / "fit.png", dpi=120)
        plt.close(fig)
        print(f"wrote {out / 'fit.png'}")
    return 0


def _run_compare(args, models, dna, fixed, bounds, options, out):
    """``--model a --model b``: one data set, every model; table, report and figure."""
    from supercoil.commands._common import warning_text
    from supercoil.dna.fitting import compare_models
    from supercoil.dna.fitting.plot import plot_comparison
    from supercoil.dna.tweezers import read_tweezers_csv
    from supercoil.exceptions import FitError
    from supercoil.tables import write_csv

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        data = read_tweezers_csv(args.data, drop_incomplete=args.drop_incomplete)
        if "molecule" in data.columns and data["molecule"].nunique() > 1 and not args.global_fit:
            raise FitError("several --model compare models on one data set: give --global "
                           "(shared parameters, per-molecule offsets) or one molecule")
        comparison = compare_models(data, dna, models, vary=args.vary, fixed=fixed,
                                    bounds=bounds, **options)
    table, results = comparison.table, comparison.results
    for w in caught:
        print(warning_text("fit", w.message), file=sys.stderr)
    out.mkdir(parents=True, exist_ok=True)
    csv = write_csv(table, out / "fit_comparison.csv")
    from supercoil.commands._common import flagged_error

    report = comparison.report(error_text=flagged_error)
    (out / "fit_report.txt").write_text(report + "\n")
    print(report)
    print(f"wrote {csv}, {out / 'fit_report.txt'}")
    if not args.no_plot and results:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig = plot_comparison(results)
        fig.savefig(out / "fit_comparison.png", dpi=120)
        plt.close(fig)
        print(f"wrote {out / 'fit_comparison.png'}")
    return 0 if table["success"].all() else 1


def _run_many(args, data, dna, fixed, bounds, start, options):
    from supercoil.dna.fitting import fit_many
    from supercoil.dna.fitting.progress import Progress

    n = data["molecule"].astype(str).nunique()
    # a tqdm bar on a terminal, one line per molecule in a log (no carriage returns piling up)
    bar = Progress(False if args.no_progress else "log", n, prefix="supercoil fit: ")
    kwargs = dict(vary=args.vary, fixed=fixed, bounds=bounds, start=start,
                  progress=lambda done, total, molecule: bar.update(molecule), **options)
    try:
        if args.jobs > 1:
            from concurrent.futures import ProcessPoolExecutor

            with ProcessPoolExecutor(max_workers=args.jobs) as pool:
                return fit_many(data, dna, executor=pool, **kwargs)
        return fit_many(data, dna, **kwargs)
    finally:
        bar.close()


def _many_report(table, args):
    import numpy as np

    from supercoil.commands._common import flag_text

    units = table.attrs["units"]
    params = [c for c in table.columns
              if f"{c}_stderr" in table.columns]
    lines = [
        f"[[Per-molecule fits]] {len(table)} molecules, {int(table['success'].sum())} fitted, "
        f"{int((~table['success']).sum())} failed; varied: {', '.join(args.vary)}",
    ]
    # with unit weights the reduced chi-square is 1 by construction: show the noise
    # estimate (the residual RMS in nm, by which the errors are scaled)
    unit_weights = table.attrs.get("provenance", {}).get("weighting", "unit") == "unit"
    stat_head = "noise [nm]" if unit_weights else "red.chi2"
    head = f"    {'molecule':<12}{stat_head:>10}"
    for p in params:
        head += f"{p + ' [' + units[p] + ']':>30}"
    lines.append(head)
    for _, row in table.iterrows():
        if not row["success"]:
            lines.append(f"    {row['molecule']!s:<12}  FAILED: {flag_text(row['error'])}")
            continue
        stat = row["residual_rms"] if unit_weights else row["reduced_chi_square"]
        text = f"    {row['molecule']!s:<12}{stat:>10.4g}"
        for p in params:
            err = row[p + "_stderr"]
            cell = (f"{row[p]:.5g} (not determined)" if np.isinf(err)
                    else f"{row[p]:.5g} ± {err:.2g}")
            text += f"{cell:>30}"
        lines.append(text)
    undetermined = table[table["success"] & ~table["determined"]]
    if len(undetermined):
        lines.append("[[Not determined]] the data of these molecules do not determine some "
                     "parameters (stderr inf), e.g. a nicked molecule with a flat curve:")
        for _, row in undetermined.iterrows():
            bad = [p for p in params if np.isinf(row[p + "_stderr"])]
            lines.append(f"    {row['molecule']!s:<12}  {', '.join(bad)}")
    ok = table[table["success"]]
    if len(ok) > 1:
        lines.append("[[Across molecules]] mean ± standard deviation (molecules whose fit "
                     "determines the parameter)")
        for p in params:
            if p in args.vary:
                vals = ok[p][np.isfinite(ok[p + "_stderr"])]
                if len(vals) > 1:
                    lines.append(f"    {p:<24}{vals.mean():.5g} ± {vals.std(ddof=1):.2g} "
                                 f"{units[p]} ({len(vals)} molecules)")
    return "\n".join(lines)


def _plot_many(table, vary, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    units = table.attrs["units"]
    names = [v for v in vary if v in table.columns] or ["residual_rms"]
    fig, axes = plt.subplots(1, len(names), figsize=(4.5 * len(names), 3.6), squeeze=False,
                             layout="constrained")
    ok = table["success"].to_numpy()
    x = np.arange(len(table))
    for ax, name in zip(axes[0], names, strict=True):
        err = table.get(f"{name}_stderr")
        fin = ok if err is None else ok & np.isfinite(err.to_numpy())
        ax.errorbar(x[fin], table[name][fin], yerr=None if err is None else err[fin], fmt="o",
                    ms=4, capsize=2)
        if (ok & ~fin).any():  # not determined: value without an error bar
            ax.plot(x[ok & ~fin], table[name][ok & ~fin], "x", color="0.4",
                    label="not determined")
            ax.legend(fontsize="small")
        for xi in x[~ok]:
            ax.axvline(xi, color="r", alpha=0.3, lw=4)
        ax.set_xticks(x, table["molecule"].astype(str), rotation=90, fontsize="small")
        ax.set_xlabel("molecule (red: fit failed)")
        ax.set_ylabel(f"{name} [{units.get(name, '')}]")
    fig.savefig(path, dpi=120)
    plt.close(fig)
