"""``supercoil rod``: the double helix of a twisted rod, written as CSV and a plot.

Examples::

    supercoil rod --params silicone_rubber_rod --turns 40 --out OUT
        rough rod, k = 0 (twist 40 turns, then slack): profile over s
    supercoil rod --params silicone_rubber_rod --turns 40 --surface smooth --out OUT
        smooth rod: the uniform helix over a sweep of slack 0 .. 0.98 L
    supercoil rod --params silicone_rubber_rod --turns 40 --surface smooth \
        --slack "10 cm" "20 cm" --out OUT
        smooth rod at the given slacks

Quantities are parsed with :data:`supercoil.ureg` ("10 cm", "0.1 m", "80 pi rad").
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np


def register(sub):
    p = sub.add_parser(
        "rod",
        help="double helix of a twisted elastic rod (smooth or rough surface)",
        description="Double helix of a rod twisted by N turns and slacked "
        "(documentation: theory pages Smooth and Rough). "
        "Writes the table as CSV (units in the headers) and a PNG plot into --out.",
    )
    p.add_argument("--params", default="silicone_rubber_rod",
                   help="parameter set name or TOML path (default: silicone_rubber_rod)")
    p.add_argument("--turns", required=True,
                   help="turns N (plain number, or a quantity such as '80 pi rad'); "
                   "negative turns twist the other way: --turns -40 or --turns=-40")
    p.add_argument("--surface", choices=("rough", "smooth"), default="rough",
                   help="rough: frozen non-uniform helix, k = 0 (default); smooth: uniform helix")
    p.add_argument("--slack", nargs="+", default=None,
                   help="smooth: slack value(s) S, e.g. '10 cm' (default: sweep 0 .. 0.98 L); "
                   "rough: stop the helix at this slack")
    p.add_argument("--method", choices=("auto", "closed_form", "ode"), default="auto",
                   help="rough: solver (default auto = closed form for k = 0)")
    p.add_argument("--curvature-tolerance", type=float, default=0.01,
                   help="rough: tolerance on |e - 1| for the curvature-error flag (default 0.01)")
    p.add_argument("--points", type=int, default=801,
                   help="grid size (default 801; rough: >= 2, smooth sweep: >= 1)")
    p.add_argument("--out", type=Path, required=True, help="output folder")
    p.set_defaults(func=run)


def _quantity(text, what):
    import pint

    from supercoil.units import ureg

    try:
        return ureg.Quantity(text)
    except (pint.errors.UndefinedUnitError, pint.errors.DefinitionSyntaxError, ValueError,
            TypeError, AttributeError) as exc:
        raise SystemExit(f"supercoil rod: error: cannot read {what} {text!r}: {exc}") from None


def _turns(text) -> float:
    """``--turns`` as a float number of turns; errors name the flag (exit status 2)."""
    import pint

    from supercoil.units import as_turns

    try:
        value = float(as_turns(_quantity(text, "--turns"), "--turns"))
        if not np.isfinite(value):
            raise ValueError(f"turns must be finite, got {value}")
        return value
    except (pint.DimensionalityError, ValueError, TypeError) as exc:
        text_ = str(exc)
        raise ValueError(text_ if "--turns" in text_ else f"--turns {text!r}: {text_}") from None


def run(args) -> int:
    import pint

    from supercoil.parameters import load_parameters

    rod = load_parameters(args.params)
    if not hasattr(rod, "bending_rigidity") or not hasattr(rod.si, "friction_coefficient"):
        print(f"supercoil rod: error: parameter set {args.params!r} is not an ElasticRod",
              file=sys.stderr)
        return 2
    try:
        turns = _turns(args.turns)
        slack = None
        if args.slack is not None:
            slack = [_quantity(t, "--slack") for t in args.slack]
        args.out.mkdir(parents=True, exist_ok=True)
        if args.surface == "smooth":
            return _smooth(rod, turns, slack, args)
        return _rough(rod, turns, slack, args)
    except (pint.DimensionalityError, ValueError, TypeError) as exc:
        # named errors (NoHelixError, ...) are ValueErrors too; the message names the input
        print(f"supercoil rod: error: {exc}", file=sys.stderr)
        return 2


def _stack(quantities):
    from supercoil.units import U, magnitude, quantity

    return quantity(np.array([magnitude(q, U.m, "--slack") for q in quantities]), U.m)


def _smooth(rod, turns, slack, args) -> int:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from supercoil.rod.smooth import smooth_helix
    from supercoil.tables import write_csv
    from supercoil.units import U, quantity

    if slack is None:
        S = quantity(np.linspace(0.0, 0.98 * rod.si.length, args.points), U.m)
    else:
        S = _stack(slack)
    h = smooth_helix(rod, turns, S)
    table = h.to_table()
    csv = write_csv(table, args.out / "rod_smooth.csv")
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    x = table["slack"] / 10
    style = "-" if len(table) > 1 else "o"
    ax[0].plot(x, table["pitch"], style)
    ax[0].set_ylabel("pitch P [mm]")
    ax[1].plot(x, table["tension"], style)
    ax[1].set_ylabel("tension T [N]")
    for a in ax:
        a.set_xlabel("slack S [cm]")
    fig.suptitle(f"smooth rod {args.params}, N = {turns:g}: uniform helix")
    fig.tight_layout()
    png = args.out / "rod_smooth.png"
    fig.savefig(png, dpi=110)
    plt.close(fig)
    if len(table) <= 5:
        for _, row in table.iterrows():
            print(f"S = {row['slack']:.6g} mm: alpha = {row['alpha']:.6g} rad, pitch = "
                  f"{row['pitch']:.6g} mm, tension = {row['tension']:.6g} N, Tw = "
                  f"{row['twist']:.6g}, Wr = {row['writhe']:.6g}")
    print(f"wrote {csv} and {png}")
    return 0


def _rough(rod, turns, slack, args) -> int:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from supercoil.rod.rough import rough_helix
    from supercoil.tables import write_csv
    from supercoil.units import U

    slack_max = None
    if slack is not None:
        if len(slack) != 1:
            print("supercoil rod: error: --surface rough takes one --slack (where to stop)",
                  file=sys.stderr)
            return 2
        slack_max = slack[0]
    res = rough_helix(rod, turns, method=args.method, n_points=args.points,
                      curvature_tolerance=args.curvature_tolerance, slack_max=slack_max)
    p = res.profile
    csv = write_csv(p, args.out / "rod_profile.csv")
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    ax[0].plot(p["s"], p["pitch"])
    ax[0].set_ylabel("pitch P [mm]")
    ax[0].set_ylim(0, min(float(p["pitch"].max()), 6 * float(p["pitch"].iloc[0])))
    ax[1].semilogy(p["s"], p["friction_torque_required"], label="required C|d omega/ds|")
    if p["friction_torque_available"].notna().all():
        ax[1].semilogy(p["s"], p["friction_torque_available"], label="available dM_fmax/ds")
    ax[1].set_ylabel("friction torque per length [N]")
    ax[1].legend()
    for a in ax:
        a.set_xlabel("s [mm]")
        if res.curvature_error_onset is not None:
            a.axvline(res.curvature_error_onset.m_as(U.mm), color="gray", ls=":", lw=0.8)
    fig.suptitle(f"rough rod {args.params}, N = {turns:g}, k = 0 ({res.method}); "
                 f"dotted: |e - 1| > {args.curvature_tolerance:g}")
    fig.tight_layout()
    png = args.out / "rod_profile.png"
    fig.savefig(png, dpi=110)
    plt.close(fig)

    def fmt(q, none="None"):
        return none if q is None else f"{q.m_as(U.mm):.6g} mm"

    # s_max is the helix end (alpha -> 0, or the rod's end); s_end where the run stopped
    print(f"alpha0 = {res.alpha0.m_as(U.rad):.6g} rad, s_max = "
          f"{fmt(res.s_max, 'unknown (depends on the twisting beyond the stop)')}, "
          f"integrated to s_end = {fmt(res.s_end)} ({res.end}), "
          f"slip onset = {fmt(res.slip_onset)}, |e-1| > {args.curvature_tolerance:g} from "
          f"{fmt(res.curvature_error_onset)}")
    print(f"wrote {csv} and {png}")
    return 0
