"""``supercoil bench --out DIR``: work-precision charts, stability map, headline numbers."""

from __future__ import annotations

import sys


def register(sub):
    p = sub.add_parser(
        "bench",
        help="benchmarks: work-precision charts, stability map, speed and memory targets",
        description="Runs every benchmark (under 5 minutes on 2 cores) and writes the "
        "charts (PNG), the measurements (CSV) and the headline table of every speed and "
        "memory target with its measured value (headline.csv, headline.md).",
    )
    p.add_argument("--out", default="bench", help="output folder (default: bench)")
    p.add_argument("--quick", action="store_true",
                   help="fewer tolerances and smaller sizes (the row names give the sizes)")
    p.add_argument("--smoke", action="store_true",
                   help="the smallest sizes that still write every chart and table (a check "
                   "that the benchmarks run, used by the test suite; not a measurement)")
    p.set_defaults(func=run)


def run(args) -> int:
    from supercoil.benchmark import suite

    suite.run(args.out, quick=args.quick, smoke=args.smoke,
              log=lambda msg: print(msg, file=sys.stderr))
    return 0
