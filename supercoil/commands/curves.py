"""``supercoil curves RECORDING``: rotation curves from a raw magnetic-tweezers recording.

Example::

    supercoil curves "Tracking Data 2025-12-01 00-00-00.000000.h5" --reference 20 \\
        --calibration force_calibration.csv --settle 1s [--errors pooled] --out DIR

``RECORDING`` is a MagScope tracking file (or its acquisition folder; the motor
logs ``ZaberNmsMotor.txt``/``ZaberLsqMotor.txt`` beside it) or a CALISTO
recording (HDF5, or the headerless text bead file with ``--motor FILE``);
``--format`` picks the reader when the guess (MagScope for a folder or an HDF5
file with a ``/tracking`` group, else CALISTO) is wrong. ``--calibration``
is a CSV with columns ``height [mm]`` and ``force [pN]``, or MagScope's
``force_calibrant.txt`` (magnet height -> force; there is no default calibration).
The command writes

* ``DIR/rotation_curves.csv``: ``molecule, force [pN], turns, extension [nm],
  sigma [nm]``, the table :func:`supercoil.read_tweezers_csv` reads and
  ``supercoil fit`` fits;
* ``DIR/plateaus.csv``: the detected plateaus;
* ``DIR/recording.png``: bead z, magnet turns and height versus time with the
  kept plateau frames shaded.

Method: docs/theory/recordings.md.
"""

from __future__ import annotations

import argparse
import sys
import warnings

__all__ = ["add_parser", "register", "run"]


def _time(text):
    """``--settle``: a time with its unit, finite and >= 0 (argparse exits 2 otherwise)."""
    import math

    from ..units import U, magnitude, ureg

    try:
        q = ureg.Quantity(text)
        seconds = magnitude(q, U.s, "settle")
    except Exception as exc:  # pint parse or dimensionality error
        raise argparse.ArgumentTypeError(f"cannot read --settle {text!r} as a time (e.g. 1s): "
                                         f"{exc}") from None
    if not (isinstance(seconds, float | int) and math.isfinite(seconds) and seconds >= 0):
        raise argparse.ArgumentTypeError(f"{text!r}: the settling time must be one "
                                         "finite time >= 0 (e.g. 1s)")
    return q


def add_parser(sub):
    """Add the ``curves`` subcommand to ``sub`` (an argparse subparsers object)."""
    p = sub.add_parser(
        "curves",
        help="rotation curves from a raw tweezers recording (MagScope, CALISTO)",
        description="Find the plateaus of constant magnet rotation and height, drop the "
        "settling frames, subtract the reference beads (drift), average, and give each "
        "plateau mean its blocking standard error (Flyvbjerg & Petersen 1989).",
    )
    p.add_argument("recording", help="MagScope tracking file or folder, CALISTO .h5 or .txt")
    p.add_argument("--format", choices=("magscope", "calisto"), default=None,
                   help="the recording's format (default: guessed)")
    p.add_argument("--settle", type=_time, default="1s",
                   help="settling time dropped after every magnet move (default 1s)")
    p.add_argument("--reference", nargs="+", default=None, metavar="BEAD",
                   help="reference bead(s) (default: those the file marks, e.g. CALISTO R<i>)")
    p.add_argument("--calibration", default=None, metavar="FILE",
                   help="CSV 'height [mm], force [pN]', or MagScope's force_calibrant.txt "
                   "(position [mm], force [pN]): magnet height -> force")
    p.add_argument("--motor", default=None, metavar="FILE",
                   help="CALISTO text: the motor file (frame, time, position, rotation)")
    p.add_argument("--rotation-log", default="ZaberNmsMotor.txt",
                   help="MagScope: motor log of the rotation in turns (default ZaberNmsMotor.txt)")
    p.add_argument("--height-log", default="ZaberLsqMotor.txt",
                   help="MagScope: motor log of the height in mm (default ZaberLsqMotor.txt)")
    p.add_argument("--errors", choices=("pooled", "plateau"), default="pooled",
                   help="sigma of each plateau mean: its standard deviation with the "
                   "inefficiency pooled per bead and magnet height (default), or its own "
                   "blocking error")
    p.add_argument("--no-check-settled", action="store_true",
                   help="keep plateaus whose two halves differ (not settled) instead of failing")
    p.add_argument("--out", default="curves_out", help="output folder (default: curves_out)")
    p.add_argument("--no-plot", action="store_true", help="do not write the figure")
    p.set_defaults(func=run)
    return p


#: the name the command line (supercoil.cli) calls
register = add_parser


def _guess_format(path):
    from pathlib import Path

    path = Path(path)
    if path.is_dir() or path.name.startswith("Tracking Data"):
        return "magscope"
    if path.suffix.lower() in (".h5", ".hdf5") and path.exists():
        from ..traces.trace import require_h5py

        h5py = require_h5py(path)
        try:
            with h5py.File(path, "r") as fh:
                return "magscope" if "tracking" in fh else "calisto"
        except OSError:
            return "calisto"  # the reader names the problem
    return "calisto"


def _read(args):
    from .. import traces

    fmt = args.format or _guess_format(args.recording)
    refs = args.reference or ()
    if fmt == "magscope":
        return traces.read_magscope(args.recording, rotation_log=args.rotation_log,
                                    height_log=args.height_log, reference_beads=refs)
    return traces.read_calisto(args.recording, args.motor,
                               reference_beads=args.reference)


def _calibration(path):
    """The ``--calibration`` table (None without one); its errors name the flag."""
    from .. import traces
    from ..exceptions import DataError, SupercoilError

    if path is None:
        return None
    try:  # a CSV table or MagScope's own force_calibrant.txt
        return traces.read_calibration(path)
    except SupercoilError as exc:
        raise DataError(str(exc), argument="calibration") from exc


def run(args) -> int:
    from pathlib import Path

    from .. import traces
    from ..tables import write_csv

    out = Path(args.out)
    settle = args.settle if not isinstance(args.settle, str) else _time(args.settle)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        trace = _read(args)
        calibration = _calibration(args.calibration)
        plateaus = traces.find_plateaus(trace, settle)
        curves = traces.rotation_curves(trace, settle, calibration=calibration,
                                        errors=args.errors,
                                        check_settled=not args.no_check_settled)
    from ._common import flag_text

    for w in caught:  # keyword hints (calibration=, check_settled=False) as flags
        print(f"supercoil curves: warning: {flag_text(str(w.message))}", file=sys.stderr)
    out.mkdir(parents=True, exist_ok=True)
    csv = write_csv(curves, out / "rotation_curves.csv")
    write_csv(plateaus, out / "plateaus.csv")
    n_mol = curves["molecule"].nunique()
    print(f"{len(plateaus)} plateaus ({plateaus.attrs['moves']} moves skipped), {n_mol} "
          f"molecule(s), {len(curves)} points; reference beads: "
          f"{trace.attrs['reference_beads'] if args.reference is None else args.reference}")
    print(f"wrote {csv}, {out / 'plateaus.csv'}")
    if not args.no_plot:
        import matplotlib

        matplotlib.use("Agg")
        traces.plot_plateaus(trace, plateaus, path=out / "recording.png")
        print(f"wrote {out / 'recording.png'}")
    return 0
