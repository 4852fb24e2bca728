"""``supercoil validate --out DIR``: the DNA models against published measurements."""

from __future__ import annotations


def register(sub):
    p = sub.add_parser(
        "validate", help="compare the DNA models with published measurements",
        description="Evaluate li-zhao (seed set, hard core), free-energy (150 mM set, screened) "
        "and marko2007 (150 mM set) at the conditions of every shipped published value "
        "(documentation: theory page Validation against published measurements); write "
        "validation.csv and validation.png.")
    p.add_argument("--out", default="results", help="output folder (default: results)")
    p.set_defaults(func=run)


def run(args) -> int:
    from pathlib import Path

    import matplotlib

    matplotlib.use("Agg")
    from supercoil.tables import write_csv
    from supercoil.validation import plot_validation, validate

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    table = validate()
    write_csv(table, out / "validation.csv")
    plot_validation(table, out / "validation.png")
    ok = table.dropna(subset=["relative_error"])
    for (q, model), g in ok.groupby(["quantity", "model"], sort=False):
        err = g["relative_error"].abs()
        print(f"{q:30s} {model:12s} |rel. error| {err.min():.3f}-{err.max():.3f} "
              f"({len(g)} rows)")
    print(f"wrote {out / 'validation.csv'} and {out / 'validation.png'}")
    return 0
