"""``supercoil hat``: DNA hat curves (extension and torque versus turns) at fixed forces.

Example::

    supercoil hat --params dna --force 0.4pN --force 1.2pN --turns=-20:20:0.1 --out DIR

writes ``DIR/hat_curve.csv`` (units in the headers, provenance in ``#`` lines)
and ``DIR/hat_curve.png``. Forces and lengths are read with their units by
:data:`supercoil.ureg`. With no option, the seed DNA set at 0.4, 1.2 and
3.0 pN (the paper's DNA figure) is computed.
"""

from __future__ import annotations

import argparse
import sys
import warnings

import numpy as np

DEFAULT_FORCES = ("0.4pN", "1.2pN", "3.0pN")
DEFAULT_TURNS = "-40:40:0.1"


def _quantity(kind, unit_name):
    def parse(text):
        import pint

        from supercoil.units import U, magnitude, ureg

        try:
            q = ureg.Quantity(text)
        except Exception as exc:  # pint raises several parser errors
            raise argparse.ArgumentTypeError(f"cannot read {kind} {text!r}: {exc}") from None
        try:
            magnitude(q, getattr(U, unit_name), kind)
        except pint.DimensionalityError:
            raise argparse.ArgumentTypeError(
                f"{kind} {text!r} is not a {kind} (give a unit, e.g. "
                f"{'0.4pN' if kind == 'force' else '750nm'})"
            ) from None
        return q

    return parse


def parse_turns(text):
    """``start:stop:step`` (both ends included), ``start:stop`` (step 0.1), or ``a,b,c``."""
    try:
        if ":" in text:
            parts = [float(p) for p in text.split(":")]
            if len(parts) == 2:
                parts.append(0.1)
            if len(parts) != 3:
                raise ValueError
            start, stop, step = parts
            if not (step > 0 and stop >= start and np.isfinite([start, stop, step]).all()):
                raise ValueError
            n = int(np.floor((stop - start) / step + 1e-9)) + 1
            return start + step * np.arange(n)
        values = np.array([float(p) for p in text.split(",")])
        if not np.isfinite(values).all():
            raise ValueError
        return values
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"turns {text!r}: expected start:stop:step with step > 0 and stop >= start, "
            "or a comma-separated list"
        ) from None


def register(sub):
    p = sub.add_parser(
        "hat",
        help="DNA hat curves: extension and torque versus turns at fixed forces",
        description="Hat curves of a DNA molecule in a magnetic tweezers (MODEL.md section 6): "
        "Marko-Siggia plectoneme equilibrium, Moroz-Nelson tail corrections.",
    )
    p.add_argument("--params", default="dna", help="DNA parameter set name or TOML path "
                   "(default: dna)")
    p.add_argument("--force", action="append", type=_quantity("force", "N"),
                   help="a force with its unit, e.g. 0.4pN; repeat for several "
                   f"(default: {', '.join(DEFAULT_FORCES)})")
    p.add_argument("--turns", type=parse_turns, default=None,
                   help=f"turns as start:stop:step (default {DEFAULT_TURNS}); "
                   "write --turns=-20:20:0.1 for a negative start")
    p.add_argument("--length", type=_quantity("length", "m"), default=None,
                   help="override the contour length L, e.g. 750nm")
    p.add_argument("--short-tail", type=_quantity("length", "m"), default=None,
                   help="tail length below which points are flagged short_tail "
                   "(default: 3 bending persistence lengths)")
    p.add_argument("--interaction", default="hard-core",
                   help="inter-strand interaction of the plectoneme: hard-core (the paper's "
                   "Marko-Siggia w, default) or screened (Debye-Hueckel with salt; needs a "
                   "parameter set with 'salt', e.g. --params dna_150mM_nacl)")
    p.add_argument("--athermal", action="store_true",
                   help="no Moroz-Nelson corrections (C_eff = C, zeta = 1)")
    p.add_argument("--out", default="hat_out", help="output folder (default: hat_out)")
    p.add_argument("--no-plot", action="store_true", help="write only the CSV")
    p.set_defaults(func=run)


def run(args) -> int:
    from pathlib import Path

    from supercoil.dna.hat import buckling_turns, hat_curve, plot_hat_curves, post_buckling_slope
    from supercoil.dna.material import DNA
    from supercoil.dna.plectoneme import plectoneme_equilibrium
    from supercoil.exceptions import ParameterError
    from supercoil.parameters import load_parameters
    from supercoil.tables import write_csv
    from supercoil.units import ureg

    dna = load_parameters(args.params)
    if not isinstance(dna, DNA):
        raise ParameterError(f"parameter set {args.params!r} is not a DNA set")
    if args.length is not None:
        dna = dna.replace(length=args.length)
    forces = args.force or [ureg.Quantity(f) for f in DEFAULT_FORCES]
    force = ureg.Quantity(np.array([f.m_as("pN") for f in forces]), "pN")
    turns = args.turns if args.turns is not None else parse_turns(DEFAULT_TURNS)
    thermal = not args.athermal
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        inter = args.interaction
        df = hat_curve(dna, force, turns, thermal=thermal, short_tail_length=args.short_tail,
                       interaction=inter)
        nb = buckling_turns(dna, force, thermal=thermal, interaction=inter).magnitude
        slope = post_buckling_slope(dna, force, thermal=thermal, interaction=inter).magnitude
    for w in caught:
        print(f"supercoil hat: warning: {w.message}", file=sys.stderr)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    csv = write_csv(df, out / "hat_curve.csv")
    print(f"wrote {csv} ({len(df)} rows)")
    if not args.no_plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig = plot_hat_curves(df, out / "hat_curve.png")
        plt.close(fig)
        print(f"wrote {out / 'hat_curve.png'}")
    print(f"{'force [pN]':>10} {'N_b':>8} {'plectoneme torque [pN nm]':>26} "
          f"{'dz/dN [nm/turn]':>16}")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # already reported above
        torque_p = plectoneme_equilibrium(dna, force, interaction=inter).torque.m_as("pN nm")
    for f, n, m, s in zip(force.magnitude, nb, torque_p, slope, strict=True):
        print(f"{f:10.4g} {n:8.4g} {m:26.4g} {s:16.4g}")
    return 0
