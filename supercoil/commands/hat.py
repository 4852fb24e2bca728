"""``supercoil hat``: DNA hat curves (extension and torque versus turns) at fixed forces.

Example::

    supercoil hat --params dna --force 0.4pN --force 1.2pN --turns=-20:20:0.1 --out DIR

writes ``DIR/hat_curve.csv`` (units in the headers, provenance in ``#`` lines),
``DIR/buckling.csv`` (buckling turns, buckling torque and post-buckling slope per
force; docs/theory/models.md#buckling) and ``DIR/hat_curve.png``. Forces and lengths
are read with their units by :data:`supercoil.ureg`; ``--turns -20:20:0.1`` and
``--turns=-20:20:0.1`` are the same.

With no option (the main job), the seed DNA set is computed at 0.4, 1.2 and 3.0 pN
(the paper's DNA figure): from -40 to 40 turns at 0.4 pN, and from 0 to 40 turns at
the forces above 0.8 pN, where real DNA melts under negative supercoiling
(docs/theory/limits.md) and the model, which ignores melting, would have to warn.
Warnings of a run the user asked for are printed once each, in plain words.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from supercoil import display
from supercoil.core.dna.interface import DENATURATION_FORCE

DEFAULT_FORCES = ("0.4pN", "1.2pN", "3.0pN")
#: default turns at forces up to DENATURATION_PN, and above it (positive turns only: real
#: DNA melts under negative supercoiling there and the model ignores it, so the default
#: job computes no point that it would have to warn about)
DEFAULT_TURNS = "-40:40:0.1"
DEFAULT_TURNS_HIGH_FORCE = "0:40:0.1"
DENATURATION_PN = display.to_display(DENATURATION_FORCE, "force")  # 0.8 pN
#: what to do when the denaturation warning is shown (the user asked for those points)
DENATURATION_HINT = "give --turns=0:40 to compute positive turns only"


def _quantity(kind, unit_name, allow_zero=False):
    """An argparse type: a pint quantity of dimension ``unit_name``; lengths positive."""

    def parse(text):
        import pint

        from supercoil.units import U, magnitude, ureg

        try:
            q = ureg.Quantity(text)
        except Exception as exc:  # pint raises several parser errors
            raise argparse.ArgumentTypeError(f"cannot read {kind} {text!r}: {exc}") from None
        try:
            value = magnitude(q, getattr(U, unit_name), kind)
        except pint.DimensionalityError:
            raise argparse.ArgumentTypeError(
                f"{kind} {text!r} is not a {kind} (give a unit, e.g. "
                f"{'0.4pN' if kind == 'force' else '750nm'})"
            ) from None
        if kind == "length" and not (np.isfinite(value) and (value > 0 or
                                                             (allow_zero and value == 0))):
            raise argparse.ArgumentTypeError(
                f"length {text!r} must be {'>= 0' if allow_zero else 'positive'} and finite")
        return q

    return parse


def parse_turns(text):
    """``start:stop:step`` (both ends included), ``start:stop`` (step 0.1), or ``a,b,c``."""
    from supercoil.commands._common import parse_range

    return parse_range(text, "--turns")


def register(sub):
    p = sub.add_parser(
        "hat",
        help="DNA hat curves: extension and torque versus turns at fixed forces",
        description="Hat curves of a DNA molecule in a magnetic tweezers (documentation: "
        "theory page Models): "
        "by default the paper's construction (li-zhao: Marko-Siggia plectoneme equilibrium, "
        "Moroz-Nelson tail corrections); --model selects any registered model.",
    )
    p.add_argument("--params", default="dna", help="DNA parameter set name or TOML path "
                   "(default: dna)")
    p.add_argument("--force", action="append", type=_quantity("force", "N"),
                   help="a force with its unit, e.g. 0.4pN; repeat for several "
                   f"(default: {', '.join(DEFAULT_FORCES)})")
    p.add_argument("--turns", type=parse_turns, default=None,
                   help="turns as start:stop:step, start:stop (step 0.1) or a,b,c; "
                   "--turns -20:20:0.1 and --turns=-20:20:0.1 are the same (default: "
                   f"{DEFAULT_TURNS} at forces <= {DENATURATION_PN:g} pN, "
                   f"{DEFAULT_TURNS_HIGH_FORCE} above, where real DNA melts under negative "
                   "turns)")
    p.add_argument("--length", type=_quantity("length", "m"), default=None,
                   help="override the contour length L, e.g. 750nm")
    p.add_argument("--short-tail", type=_quantity("length", "m", allow_zero=True), default=None,
                   help="tail length below which points are flagged short_tail "
                   "(default: 3 bending persistence lengths; 0: flag none)")
    p.add_argument("--athermal", action="store_true",
                   help="no Moroz-Nelson corrections (C_eff = C, zeta = 1)")
    p.add_argument("--model", default="li-zhao", metavar="NAME",
                   help="DNA model (default li-zhao, the paper's); any registered model, "
                   "see supercoil.available_models()")
    p.add_argument("--end-loop", action="store_true",
                   help="add the plectoneme end loop (documentation: theory page The plectoneme "
                   "end loop; models "
                   "free-energy and marko2007)")
    p.add_argument("--interaction", default="hard-core", metavar="NAME",
                   help="inter-strand interaction of the plectoneme: hard-core (the paper's "
                   "Marko-Siggia w, default), screened (Debye-Hueckel with salt; needs a "
                   "parameter set with 'salt', e.g. --params dna_150mM_nacl) or any "
                   "registered interaction; models without a plectoneme take none")
    p.add_argument("--out", default="hat_out", help="output folder (default: %(default)s)")
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


def model_with_options(command, name, end_loop):
    """``(model, None)``: the model ``name`` with its command-line options; or ``(None, error)``."""
    from supercoil.dna.models import get_model

    if not end_loop:
        return get_model(name), None
    if "end_loop" not in get_model(name).options():
        with_loop = [m for m in _models_with_end_loop()]
        return None, (f"supercoil {command}: error: --end-loop: model {name!r} has no end loop "
                      f"(models with one: {', '.join(with_loop)})")
    return get_model(name, end_loop=True), None


def _models_with_end_loop():
    from supercoil.dna.models import available_models, get_model

    return [m for m in available_models() if "end_loop" in get_model(m).options()]


def _interaction_arg(args):
    """The interaction for a model: None (the default) when the model has no plectoneme."""
    from supercoil.dna.models import get_model

    if not get_model(args.model).uses_interaction:
        if args.interaction != "hard-core":
            return args.interaction  # let the library name the conflict (ModelError)
        return None
    return args.interaction


def _curves(dna, force, turns, thermal, short_tail, mi):
    """The hat-curve table; ``turns=None``: the default turns per force (see DEFAULT_TURNS)."""
    import pandas as pd

    from supercoil.dna.hat import hat_curve

    if turns is not None:
        return hat_curve(dna, force, turns, thermal=thermal, short_tail_length=short_tail,
                         **mi)
    low = force.m_as("N") <= DENATURATION_FORCE  # the library's own test, in SI
    parts = [hat_curve(dna, force[mask], parse_turns(grid), thermal=thermal,
                       short_tail_length=short_tail, **mi)
             for mask, grid in ((low, DEFAULT_TURNS), (~low, DEFAULT_TURNS_HIGH_FORCE))
             if mask.any()]
    df = pd.concat(parts, ignore_index=True).sort_values(["force", "turns"], kind="stable")
    df = df.reset_index(drop=True)
    df.attrs = {"units": dict(parts[0].attrs["units"]),
                "provenance": dict(parts[0].attrs["provenance"])}
    df.attrs["provenance"]["turns"] = (f"{DEFAULT_TURNS} at forces <= {DENATURATION_PN:g} pN, "
                                       f"{DEFAULT_TURNS_HIGH_FORCE} above (the default)")
    return df


def _buckling_table(dna, force, thermal, mi, provenance_dict):
    """Buckling turns, buckling torque and post-buckling slope per force (a convention table).

    The torque is the model's torque at buckling (``DNAModel.buckling``;
    docs/theory/models.md#buckling): for li-zhao the plectoneme torque.
    """
    from supercoil.dna.hat import buckling_turns, post_buckling_slope, resolve
    from supercoil.tables import make_table

    nb = buckling_turns(dna, force, thermal=thermal, **mi).m_as("turn")
    slope = post_buckling_slope(dna, force, thermal=thermal, **mi).m_as("nm/turn")
    si, f, thermal, m, inter = resolve(dna, force, thermal, mi["model"], mi["interaction"])
    torque = display.to_display(m.buckling(f, si, thermal, inter).torque, "torque")
    return make_table({"force": force.m_as("pN"), "buckling_turns": nb,
                       "buckling_torque": torque, "post_buckling_slope": slope},
                      {"force": "pN", "buckling_turns": "turn", "buckling_torque": "pN nm",
                       "post_buckling_slope": "nm/turn"}, provenance_dict)


def _print_warnings(messages):
    """Each warning once, in plain words, with what to do about the denaturation one."""
    from supercoil.commands._common import flag_text

    for text in messages:
        hint = f"; {DENATURATION_HINT}" if "denatur" in text else ""
        print(f"supercoil hat: note: {flag_text(text)}{hint}", file=sys.stderr)


def run(args) -> int:
    from pathlib import Path

    from supercoil.commands._common import plain_warnings
    from supercoil.dna.material import DNA
    from supercoil.exceptions import ParameterError
    from supercoil.parameters import load_parameters
    from supercoil.tables import write_csv
    from supercoil.units import ureg

    problem = check_names("hat", [args.model], args.interaction)
    model, problem = (None, problem) if problem else model_with_options("hat", args.model,
                                                                          args.end_loop)
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
    thermal = not args.athermal
    mi = {"model": model, "interaction": _interaction_arg(args)}

    def compute():
        df = _curves(dna, force, args.turns, thermal, args.short_tail, mi)
        return df, _buckling_table(dna, force, thermal, mi, df.attrs["provenance"])

    (df, buckling), messages = plain_warnings(compute)
    _print_warnings(messages)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    csv = write_csv(df, out / "hat_curve.csv")
    write_csv(buckling, out / "buckling.csv")
    print(f"wrote {csv} ({len(df)} rows; model {args.model}) and {out / 'buckling.csv'}")
    if not args.no_plot:
        from supercoil.dna.plot import plot_hat_curves

        plot_hat_curves(df, out / "hat_curve.png", pyplot=False)  # Agg canvas, no pyplot
        print(f"wrote {out / 'hat_curve.png'}")
    print(f"{'force [pN]':>10} {'N_b':>8} {'buckling torque [pN nm]':>24} "
          f"{'dz/dN [nm/turn]':>16}")
    for row in buckling.itertuples(index=False):
        print(f"{row.force:10.4g} {row.buckling_turns:8.4g} {row.buckling_torque:24.4g} "
              f"{row.post_buckling_slope:16.4g}")
    return 0
