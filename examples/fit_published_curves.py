"""Fit the published rotation curves of real DNA (Qian et al. 2024, Figure S5) with every model.

The source data of Qian et al., "Chromatin buffers torsional stress during
transcription", bioRxiv 2024.10.15.618270 (2024) (repository
WangLabCornell/Qian_et_al, file ``Source Data/Figure S5.xlsx``; GPL, so not
shipped) hold averaged extension and torque against turns of naked DNA (about
6.48 kb) at 0.3, 0.5, 0.75, 1, 1.5 and 2 pN. This script reads the user's copy
(the path on the command line, or the environment variable SUPERCOIL_QIAN_S5),
measures the consistency of its two channels (``supercoil.maxwell_check``),
and fits each model (marko2007 with its plectoneme twist stiffness P free, and
the other registered models or those of ``--models``) to extension and torque
jointly, all six forces, both sides, one parameter set (contour length, A and
C free, the turns offset free, the extension offset held at 0: the trap
measures absolute extensions), each without and with the torque scale free
(model torque = torque_scale x measured torque; docs/theory/fitting.md).

    python examples/fit_published_curves.py [PATH] --out DIR [--quick] [--models a,b]
        [--points N] [--turns-min X]

Without a path it stops with a message (exit 0); with ``--quick`` and no path it
fits a small synthetic workbook of the same layout (marko2007 curves whose
measured torque is the model torque / 0.8), so the test suite runs it.

Writes published_fits.csv (per model and variant: residual RMS per channel, A,
C, length, P, turns offset, torque scale with their errors, C / torque scale (the
twist stiffness in the measured torque's units) with its propagated error, AIC, BIC),
published_maxwell.csv (the per-force slopes and plateau torques),
published_fits.txt (the reports) and published_fits.png.
"""

from __future__ import annotations

import sys
import warnings

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import supercoil as sc
from supercoil.datasets.published import (
    ENV_VAR,
    SYNTHETIC_LENGTH_NM,
    published_curves_path,
    read_published_curves,
    write_synthetic_workbook,
)
from supercoil.dna.fitting import compare_models
from supercoil.dna.fitting.report import twist_in_trap_units
from supercoil.dna.models import get_model
from supercoil.example_cli import example_parser

#: model parameters fitted per model (others: every parameter the model declares)
MODEL_VARY = {"marko2007": ["plectoneme_twist_persistence"]}
DNA_VARY = ["length", "bending_persistence", "twist_persistence"]
LENGTH_NM = SYNTHETIC_LENGTH_NM  # about 6.48 kb x 0.338 nm/bp (the paper's construct, text)


def synthetic_workbook(out):
    """A small workbook of the Figure S5 layout: marko2007 curves, torque measured / 0.8."""
    return write_synthetic_workbook(out / "synthetic_figure_s5.xlsx", points_per_force=60)


def fit_all(data, dna, models, quick, start=None):
    """compare_models without and with the torque scale; (table rows, results by label)."""
    rows, results = [], {}
    for scale in (False, True):
        vary = {m: DNA_VARY + MODEL_VARY.get(m, list(get_model(m).parameters))
                + (["torque_scale"] if scale else []) for m in models}
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            comparison = compare_models(data, dna, models, vary=vary,
                                        fit_extension_offset=False,
                                        max_nfev=200 if quick else None, start=start)
        table, res = comparison.table, comparison.results
        for rec in table.to_dict("records"):
            label = rec["model"] + (" + torque_scale" if scale else "")
            rows.append((label, rec, res.get(rec["model"]), len(caught)))
            if rec["model"] in res:
                results[label] = res[rec["model"]]
    return rows, results


def _pm(rec, name):
    return rec.get(name, np.nan), rec.get(f"{name}_stderr", np.nan)


def table_of(rows):
    cols = {k: [] for k in ("fit", "success", "extension_rms", "torque_rms", "A", "A_err", "C",
                            "C_err", "length", "length_err", "P", "P_err", "turns_offset",
                            "turns_offset_err", "torque_scale", "torque_scale_err",
                            "C_over_torque_scale", "C_over_torque_scale_err", "aic",
                            "bic", "delta_aic", "delta_bic", "nparams", "error")}
    for label, rec, res, _ in rows:
        cols["fit"].append(label)
        cols["success"].append(bool(rec["success"]))
        ch = res.channels if res is not None else {}
        cols["extension_rms"].append(ch["extension"]["residual_rms"].m_as("nm") if ch
                                     else np.nan)
        cols["torque_rms"].append(ch["torque"]["residual_rms"].m_as("pN*nm") if ch
                                  else np.nan)
        for key, name in (("A", "bending_persistence"), ("C", "twist_persistence"),
                          ("length", "length"), ("P", "plectoneme_twist_persistence"),
                          ("turns_offset", "turns_offset"), ("torque_scale", "torque_scale")):
            v, e = _pm(rec, name)
            if key == "torque_scale" and not np.isfinite(v):
                v, e = 1.0, 0.0  # held at 1
            cols[key].append(v)
            cols[f"{key}_err"].append(e)
        trap = twist_in_trap_units(res) if res is not None else None
        cols["C_over_torque_scale"].append(np.nan if trap is None else trap[0])
        cols["C_over_torque_scale_err"].append(np.nan if trap is None else trap[1])
        cols["aic"].append(rec.get("aic", np.nan))
        cols["bic"].append(rec.get("bic", np.nan))
        cols["nparams"].append(int(rec.get("nparams", 0)))
        cols["error"].append(rec.get("error", ""))
    for crit in ("aic", "bic"):
        v = np.array(cols[crit], dtype=float)
        best = np.nanmin(v) if np.isfinite(v).any() else np.nan
        cols[f"delta_{crit}"] = list(v - best)
    units = {k: "" for k in cols}
    units.update(extension_rms="nm", torque_rms="pN nm", A="nm", A_err="nm", C="nm",
                 C_err="nm", C_over_torque_scale="nm", C_over_torque_scale_err="nm",
                 length="nm", length_err="nm", P="nm", P_err="nm",
                 turns_offset="turn", turns_offset_err="turn")
    return sc.tables.make_table(cols, units, sc.tables.provenance(
        source="supercoil.datasets.published (the user's copy of the source data)",
        note="errors from the per-channel noise estimates (independent residuals assumed); "
             "AIC/BIC as supercoil.compare_models (one term per channel)"))


def main(argv=None):
    parser = example_parser(__doc__, "published_fits")
    parser.add_argument("path", nargs="?", default=None,
                        help=f"the Figure S5 workbook (default: ${ENV_VAR})")
    parser.add_argument("--models", default=None,
                        help="comma-separated models (default: every registered model; "
                             "--quick: marko2007)")
    parser.add_argument("--points", type=int, default=None,
                        help="points per force (bin means; default 100, --quick 25)")
    parser.add_argument("--turns-min", type=float, default=None,
                        help="drop the turns below this (e.g. -3: the melting side); the turns "
             "offset then starts at the torque's zero (maxwell_check's centre)")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    path = published_curves_path(args.path)
    if path is None:
        if not args.quick:
            print(f"skipped: no workbook given. Pass the path of 'Source Data/Figure S5.xlsx' "
                  f"(github.com/WangLabCornell/Qian_et_al; GPL, not shipped) or set "
                  f"{ENV_VAR}.")
            return 0
        path = synthetic_workbook(args.out)
        print(f"--quick without a workbook: fitting the synthetic {path.name}")
    models = (args.models.split(",") if args.models else
              ["marko2007"] if args.quick else sc.available_models())
    points = args.points or (25 if args.quick else 100)
    data = read_published_curves(path, points_per_force=points,
                                 turns_range=None if args.turns_min is None
                                 else (args.turns_min, None))
    check = sc.maxwell_check(data)
    print("\n".join(check.lines()))
    sc.write_csv(check.to_table(), args.out / "published_maxwell.csv")
    u = sc.ureg
    dna = sc.load_parameters("dna").replace(length=LENGTH_NM * u.nm)
    start = None
    if args.turns_min is not None:  # one-sided curves: start at the torque's zero
        centre = float(np.nanmedian(check.to_table()["centre"]))
        start = {"turns_offset": centre}
        print(f"one-sided curves: turns offset started at the torque's zero, {centre:.3g}")
    rows, results = fit_all(data, dna, models, args.quick, start)
    table = table_of(rows)
    sc.write_csv(table, args.out / "published_fits.csv")
    show = ["fit", "extension_rms", "torque_rms", "A", "C", "length", "P", "turns_offset",
            "torque_scale", "torque_scale_err", "delta_aic", "delta_bic"]
    with np.printoptions(precision=4):
        print(table[show].to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    with open(args.out / "published_fits.txt", "w") as fh:
        for label, res in results.items():
            fh.write(f"==== {label}\n{res.report()}\n\n")
    best = table[table["success"]].sort_values("aic")
    if len(best):
        fig = results[best["fit"].iloc[0]].plot()
        fig.suptitle(f"{best['fit'].iloc[0]} (best AIC) on {path.name}", fontsize="medium")
        fig.savefig(args.out / "published_fits.png", dpi=110)
        plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
