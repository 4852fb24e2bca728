"""Regenerate the sample data sets shipped in :mod:`supercoil.datasets`.

    python -m supercoil.datasets.make [--out DIR]

writes every data set of :data:`RECIPES` (default: into this package's folder,
which is what the repository ships). Each data set is made by
:func:`supercoil.simulate_rotation_curves` with a fixed seed; the true
parameters, the offsets, the noise and the seed are written into the CSV's
``#`` provenance lines, so a file documents how it was made and the test suite
checks that regenerating it gives the same numbers.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

#: name -> recipe. Units: forces in pN, lengths in nm, offsets in turns and nm.
RECIPES = {
    "rotation_curves": {
        "description": (
            "Synthetic magnetic-tweezers rotation curves (extension versus turns) of two "
            "molecules at 0.3, 0.5 and 0.7 pN, 110 points per force and molecule, from the "
            "li-zhao thermal hat curve of the seed DNA set with twist_persistence = 95 nm and "
            "radius = 2.0 nm (not the seed values 86 nm and 1.75 nm), per-molecule turns "
            "offsets 0.4 and -0.3 turn and extension offsets 30 and 10 nm, and 5 nm "
            "Gaussian extension noise (seed 20261201)"
        ),
        "parameter_set": "dna",
        "replace": {"twist_persistence": 95.0, "radius": 2.0},  # nm
        "forces": [0.3, 0.5, 0.7],  # pN
        "points_per_force": 110,
        "molecules": ["m1", "m2"],
        "turns_offset": [0.4, -0.3],  # turn
        "extension_offset": [30.0, 10.0],  # nm
        "noise": 5.0,  # nm
        "seed": 20261201,
    },
}


def make_table(name):
    """The data set ``name`` as a table (the convention of ``read_tweezers_csv``)."""
    import supercoil as sc
    from supercoil.dna.fitting.fit import simulate_rotation_curves

    recipe = RECIPES[name]
    u = sc.ureg
    dna = sc.load_parameters(recipe["parameter_set"])
    dna = dna.replace(**{k: v * u.nm for k, v in recipe["replace"].items()})
    table = simulate_rotation_curves(
        dna, np.asarray(recipe["forces"]) * u.pN,
        points_per_force=recipe["points_per_force"],
        noise=recipe["noise"] * u.nm,
        turns_offset=recipe["turns_offset"],
        extension_offset=np.asarray(recipe["extension_offset"]) * u.nm,
        molecules=recipe["molecules"],
        seed=recipe["seed"],
    )
    table.attrs["provenance"] = {
        **table.attrs.get("provenance", {}),
        "dataset": name,
        "description": recipe["description"],
        "generator": "python -m supercoil.datasets.make",
        "recipe": {k: v for k, v in recipe.items() if k != "description"},
    }
    return table


def write(name, out_dir=None) -> Path:
    """Write the data set ``name`` as ``<out_dir>/<name>.csv`` and return the path."""
    from supercoil.tables import write_csv

    out = Path(out_dir) if out_dir is not None else Path(__file__).resolve().parent
    out.mkdir(parents=True, exist_ok=True)
    return write_csv(make_table(name), out / f"{name}.csv")


def main(argv=None):
    """Command-line entry: write every data set."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=None, help="output folder (default: the package)")
    args = parser.parse_args(argv)
    for name in RECIPES:
        print(write(name, args.out))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
