"""Large inputs: the loader's time against plain pandas, and peak memory per element.

Two measurements of large inputs, wired into
:func:`supercoil.benchmark.suite.run`:

* :func:`loader_timing`: :func:`supercoil.read_tweezers_csv` on a generated
  rotation-curve file of ``n_rows`` rows against ``pandas.read_csv`` of the
  same file (target: at most 2x plain pandas);
* :func:`plectoneme_memory`: the peak memory that
  :func:`supercoil.plectoneme_equilibrium` allocates beyond its own output
  (the eleven float64 fields and the force array), per force, measured with
  :mod:`tracemalloc` (numpy reports its buffers to it; target: <= 64 bytes per
  force).

Run from the command line as ``python -m supercoil.benchmark.memory``.
"""

from __future__ import annotations

import tempfile
import time
import tracemalloc
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = ["loader_timing", "plectoneme_memory", "rod_scene_cost", "run", "write_rotation_csv"]


def write_rotation_csv(path, n_rows, seed=0):
    """Write a rotation-curve CSV of ``n_rows`` rows (molecule, force, turns, extension)."""
    rng = np.random.default_rng(seed)
    n_mol = max(1, n_rows // 1000)
    df = pd.DataFrame({
        "molecule": np.char.add("m", (np.arange(n_rows) % n_mol).astype(str)),
        "force [pN]": np.round(rng.uniform(0.2, 4.0, n_rows), 4),
        "turns": np.round(rng.uniform(-30, 30, n_rows), 3),
        "extension [um]": np.round(rng.uniform(0.0, 0.6, n_rows), 5),
    })
    with open(path, "w") as fh:
        fh.write('# instrument: "benchmark"\n')
        df.to_csv(fh, index=False)
    return Path(path)


def loader_timing(n_rows=10**6, repeat=3, directory=None):
    """Best-of-``repeat`` wall times (s) of the loader and of plain pandas on one file.

    Returns
    -------
    dict
        ``rows``, ``supercoil_s``, ``pandas_s`` and ``ratio`` (supercoil / pandas).
    """
    import supercoil as sc

    with tempfile.TemporaryDirectory(dir=directory) as tmp:
        path = write_rotation_csv(Path(tmp) / "rotation.csv", n_rows)

        def best(func):
            times = []
            for _ in range(repeat):
                t0 = time.perf_counter()
                func()
                times.append(time.perf_counter() - t0)
            return min(times)

        t_pd = best(lambda: pd.read_csv(path, comment="#", skipinitialspace=True))
        t_sc = best(lambda: sc.read_tweezers_csv(path))
    return {"rows": n_rows, "supercoil_s": t_sc, "pandas_s": t_pd, "ratio": t_sc / t_pd}


def plectoneme_memory(n_forces=10**6):
    """Peak bytes per force that ``plectoneme_equilibrium`` allocates beyond its output.

    The forces span 0.2-20 pN. The output (11 float64 arrays of ``n_forces``)
    and the input force array are subtracted from the traced peak.

    Returns
    -------
    dict
        ``forces``, ``peak_bytes``, ``output_bytes`` and ``bytes_per_force``
        (peak minus input and output, divided by the number of forces).
    """
    import supercoil as sc

    dna = sc.load_parameters("dna")
    sc.plectoneme_equilibrium(dna, np.linspace(0.2, 20, 100) * sc.ureg.pN)  # warm caches
    tracemalloc.start()
    try:
        force = np.linspace(0.2, 20.0, n_forces) * sc.ureg.pN
        tracemalloc.reset_peak()
        base, _ = tracemalloc.get_traced_memory()
        eq = sc.plectoneme_equilibrium(dna, force)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    output = 11 * 8 * n_forces
    extra = peak - base - output
    del eq
    return {"forces": n_forces, "peak_bytes": peak - base, "output_bytes": output,
            "bytes_per_force": extra / n_forces}


def rod_scene_cost(scene, n_turns=10**7):
    """Wall time (s) and peak bytes per element beyond the output of a rod scene.

    ``scene`` is ``"smooth"`` (:func:`supercoil.smooth_helix` at 10 cm of slack) or
    ``"spinning"`` (:func:`supercoil.twist_spinning` at 2 N), on ``n_turns`` turns from 1
    to 40 of the silicone-rubber rod (target: within 5x of
    :func:`supercoil.hat_curve` at the same size and <= 64 bytes per element). The
    output is what the record holds when the call returns (traced with :mod:`tracemalloc`).
    """
    import supercoil as sc

    rod = sc.load_parameters("silicone_rubber_rod")
    u = sc.ureg
    call = {"smooth": lambda N: sc.smooth_helix(rod, N, 10 * u.cm),
            "spinning": lambda N: sc.twist_spinning(rod, N, 2 * u.N)}[scene]
    call(np.linspace(1, 40, 100))  # warm the imports and caches
    turns = np.linspace(1, 40, n_turns)
    t0 = time.perf_counter()
    res = call(turns)
    seconds = time.perf_counter() - t0
    del res
    tracemalloc.start()
    try:
        base, _ = tracemalloc.get_traced_memory()
        res = call(turns)
        current, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    del res
    return {"scene": scene, "elements": n_turns, "seconds": seconds,
            "output_bytes": current - base, "bytes_per_element": (peak - current) / n_turns}


def run(sizes=(10**6,), log=print):
    """Both measurements at each size; a table in the package convention."""
    from supercoil.tables import make_table, provenance

    rows = []
    for n in sizes:
        lt = loader_timing(n)
        log(f"loader {n:.0e} rows: {lt['supercoil_s']:.3f} s, pandas {lt['pandas_s']:.3f} s "
            f"(ratio {lt['ratio']:.2f})")
        pm = plectoneme_memory(n)
        log(f"plectoneme_equilibrium {n:.0e} forces: {pm['bytes_per_force']:.1f} bytes/force "
            "beyond the output")
        rows.append({"elements": n, "loader_s": lt["supercoil_s"], "pandas_s": lt["pandas_s"],
                     "loader_ratio": lt["ratio"], "bytes_per_force": pm["bytes_per_force"]})
    cols = {k: [r[k] for r in rows] for k in rows[0]}
    units = {"elements": "", "loader_s": "s", "pandas_s": "s", "loader_ratio": "",
             "bytes_per_force": "B"}
    return make_table(cols, units, provenance(scene="large inputs"))


if __name__ == "__main__":  # pragma: no cover - manual measurement
    import sys

    run(tuple(int(float(a)) for a in sys.argv[1:]) or (10**6,))
