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
        description="Hat curves of a DNA molecule in a magnetic tweezers (docs/theory/models.md): "
        "by default the paper's construction (li-zhao: Marko-Siggia plectoneme equilibrium, "
        "Moroz-Nelson tail corrections); --model selects any registered model.",
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
    p.add_argument("--athermal", action="store_true",
                   help="no Moroz-Nelson corrections (C_eff = C, zeta = 1)")
    p.add_argument("--model", default="li-zhao", metavar="NAME",
                   help="DNA model (default li-zhao, the paper's); any registered model, "
                   "see supercoil.available_models()")
    p.add_argument("--interaction", default="hard-core", metavar="NAME",
                   help="inter-strand interaction of the plectoneme: hard-core (the paper's "
                   "Marko-Siggia w, default), screened (Debye-Hueckel with salt; needs a "
                   "parameter set with 'salt', e.g. --params dna_150mM_nacl) or any "
                   "registered interaction; models without a plectoneme take none")
    p.add_argument("--out", default="hat_out", help="output folder (default: hat_out)")
    p.add_argument("--no-plot", action="store_true", help="write only the CSV")
    p.set_defaults(func=run)


def check_names(command, models, interaction):
    """``None``, or an error message for a model or interaction name not registered now.

    Checked at run time (not argparse ``choices``), so models registered after
    import, e.g. by a plug-in, are accepted.
    """
    from supercoil.dna.interactions import available_interactions
    from supercoil.dna.models import available_models

    for name in models:
        if name not in available_models():
            return (f"supercoil {command}: error: --model {name!r} is not a registered model; "
                    f"available: {', '.join(available_models())}")
    if interaction is not None and interaction not in available_interactions():
        return (f"supercoil {command}: error: --interaction {interaction!r} is not a registered "
                f"interaction; available: {', '.join(available_interactions())}")
    return None


def _interaction_arg(args):
    """The interaction for a model: None (the default) when the model has no plectoneme."""
    from supercoil.dna.models import get_model

    if not get_model(args.model).uses_interaction:
        if args.interaction != "hard-core":
            return args.interaction  # let the library name the conflict (ModelError)
        return None
    return args.interaction


def run(args) -> int:
    from pathlib import Path

    from supercoil.dna.hat import buckling_turns, hat_curve, plot_hat_curves, post_buckling_slope
    from supercoil.dna.material import DNA
    from supercoil.dna.plectoneme import plectoneme_equilibrium
    from supercoil.exceptions import ParameterError
    from supercoil.parameters import load_parameters
    from supercoil.tables import write_csv
    from supercoil.units import ureg

    problem = check_names("hat", [args.model], args.interaction)
    if problem:
        print(problem, file=sys.stderr)
        return 2
    dna = load_parameters(args.params)
    if not isinstance(dna, DNA):
        raise ParameterError(f"parameter set {args.params!r} is not a DNA set")
    if args.length is not None:
        dna = dna.replace(length=args.length)
    forces = args.force or [ureg.Quantity(f) for f in DEFAULT_FORCES]
    force = ureg.Quantity(np.array([f.m_as("pN") for f in forces]), "pN")
    turns = args.turns if args.turns is not None else parse_turns(DEFAULT_TURNS)
    thermal = not args.athermal
    mi = {"model": args.model, "interaction": _interaction_arg(args)}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        df = hat_curve(dna, force, turns, thermal=thermal, short_tail_length=args.short_tail,
                       **mi)
        nb = buckling_turns(dna, force, thermal=thermal, **mi).magnitude
        slope = post_buckling_slope(dna, force, thermal=thermal, **mi).magnitude
    for w in caught:
        print(f"supercoil hat: warning: {w.message}", file=sys.stderr)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    csv = write_csv(df, out / "hat_curve.csv")
    print(f"wrote {csv} ({len(df)} rows; model {args.model})")
    if not args.no_plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig = plot_hat_curves(df, out / "hat_curve.png")
        plt.close(fig)
        print(f"wrote {out / 'hat_curve.png'}")
    print(f"{'force [pN]':>10} {'N_b':>8} {'plectoneme torque [pN nm]':>26} "
          f"{'dz/dN [nm/turn]':>16}")
    torque_p = np.full(len(nb), np.nan)
    if mi["interaction"] is not None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # already reported above
            torque_p = plectoneme_equilibrium(dna, force, interaction=mi["interaction"]
                                              ).torque.m_as("pN nm")
    for f, n, m, s in zip(force.magnitude, nb, torque_p, slope, strict=True):
        torque = f"{m:26.4g}" if np.isfinite(m) else f"{'- (no plectoneme helix)':>26}"
        print(f"{f:10.4g} {n:8.4g} {torque} {s:16.4g}")
    return 0
