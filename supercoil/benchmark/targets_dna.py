"""Headline measurements of the DNA layer: hat curve, plectoneme equilibrium, loader.

Each function returns a flat dict of SI numbers (seconds, bytes) and names in
its docstring exactly what it times:

* :func:`hat_throughput`: the public ``sc.hat_curve`` (a DataFrame of 9
  columns) and the kernel it calls,
  ``supercoil.core.dna.li_zhao.hat_curve_points`` (float arrays; ``diagnostics=False``,
  as the default model calls it), against one numpy
  pass over the same turns array: ``np.sqrt(turns)`` (the issue's reference,
  a new array) and the cheaper ``np.multiply(turns, 2.0)``; CPU time, median
  of interleaved samples; beside them the write of the table's 9 columns
  alone (``columns_write``) and, with numba installed, the compiled kernel
  (``kernel_fast``, ``hat_curve_points(..., fast=True)``) and the public call
  on it (``public_fast``, ``SUPERCOIL_FAST=1``);
* :func:`hat_memory`: peak traced memory of one public ``sc.hat_curve`` call
  against the memory its result holds;
* :func:`equilibrium_cost`: the public ``sc.plectoneme_equilibrium`` and the
  kernel ``supercoil.core.dna.plectoneme.equilibrium`` per force;
* :func:`equilibrium_memory`: peak traced memory of one public
  ``sc.plectoneme_equilibrium`` call beyond its output, per force;
* :func:`loader_cost`: ``sc.read_tweezers_csv`` against plain
  ``pandas.read_csv(path, comment="#", skipinitialspace=True)`` of the same
  file (:func:`supercoil.benchmark.memory.write_rotation_csv`; CPU,
  interleaved), and its peak memory beyond its output per row.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from supercoil.benchmark.cpu import interleaved_cpu, page_faults, peak_memory
from supercoil.benchmark.memory import write_rotation_csv

#: force of the hat-curve measurements (N) and their turns range (turns): N >= 0
#: at 1.2 pN, so that no denaturation warning is part of what is timed
HAT_FORCE = 1.2e-12
HAT_TURNS = (0.0, 25.0)


def _dna():
    import supercoil as sc

    return sc.load_parameters("dna")


def hat_throughput(n, samples=9, compiled=True):
    """CPU seconds per call at ``n`` turns values: public, kernel, one numpy pass.

    ``compiled=False`` leaves out the compiled kernel (no numba compilation).

    Returns
    -------
    dict
        ``public``, ``kernel`` (the numpy path), ``sqrt_pass``, ``numpy_pass``
        (the multiply), ``columns_write`` (:func:`_columns_write`) and, with
        numba installed, ``kernel_fast`` and ``public_fast`` (s per call); the
        ratios ``<name>_ratio`` to the sqrt pass and ``<name>_mul_ratio`` to the
        multiply pass; ``public_faults``, ``sqrt_pass_faults`` and
        ``columns_write_faults``: minor page faults per call (None without
        :mod:`resource`).
    """
    import supercoil as sc
    from supercoil.core.dna import li_zhao as hat_kernel
    from supercoil.core.dna import li_zhao_numba

    dna = _dna()
    d = dna.si
    turns = np.linspace(*HAT_TURNS, n)
    forces = np.full(n, HAT_FORCE)
    force_q = HAT_FORCE * sc.ureg.N
    args = (d.length, d.bending_rigidity, d.torsional_rigidity, d.kT, d.radius)
    funcs = {
        "public": lambda: sc.hat_curve(dna, force_q, turns),
        # the kernel as hat_curve's default model calls it: no zeta/bracket arrays kept
        "kernel": lambda: hat_kernel.hat_curve_points(turns, forces, *args, fast=False,
                                                      diagnostics=False),
        "sqrt_pass": lambda: np.sqrt(turns),
        "numpy_pass": lambda: np.multiply(turns, 2.0),
        "columns_write": lambda: _columns_write(turns),
    }
    if compiled and li_zhao_numba.available():  # the compiled kernel (supercoil[fast]): compiled
        # in the warm-up
        funcs["kernel_fast"] = lambda: hat_kernel.hat_curve_points(turns, forces, *args,
                                                                   fast=True,
                                                                   diagnostics=False)
        funcs["public_fast"] = lambda: _with_fast(lambda: sc.hat_curve(dna, force_q, turns))
    t = interleaved_cpu(funcs, samples=samples)
    for k in ("public", "kernel", "columns_write", "kernel_fast", "public_fast"):
        if k in t:
            t[f"{k}_ratio"] = t[k] / t["sqrt_pass"]
            t[f"{k}_mul_ratio"] = t[k] / t["numpy_pass"]
    for k in ("public", "sqrt_pass", "columns_write"):
        t[f"{k}_faults"] = page_faults(funcs[k])
    return t


def _with_fast(call):
    """``call()`` with ``SUPERCOIL_FAST=1`` (the public calls on the compiled kernel)."""
    import os

    from supercoil.core.dna import li_zhao_numba

    old = os.environ.get(li_zhao_numba.ENV)
    os.environ[li_zhao_numba.ENV] = "1"
    try:
        return call()
    finally:
        if old is None:
            del os.environ[li_zhao_numba.ENV]
        else:
            os.environ[li_zhao_numba.ENV] = old


def _columns_write(turns):
    """What writing the table's columns alone costs: 7 fresh float64 and 2 one-byte arrays.

    The floor of any ``hat_curve`` that returns them (``public``): each is one
    numpy pass over ``turns`` into a new array, all kept until the end of the call.
    """
    cols = [np.multiply(turns, 2.0) for _ in range(7)]
    cols += [np.greater(turns, 1.0), np.greater(turns, 2.0)]
    return cols


def hat_memory(n, model="li-zhao"):
    """Peak traced bytes of one public ``sc.hat_curve(..., model=model)`` at ``n`` turns values.

    Returns
    -------
    dict
        ``peak`` and ``result`` (bytes the returned DataFrame holds), per element
        ``peak_per_element`` and the ratio ``peak_to_result``.
    """
    import supercoil as sc

    dna = _dna()
    turns = np.linspace(*HAT_TURNS, n)
    force_q = HAT_FORCE * sc.ureg.N
    sc.hat_curve(dna, force_q, turns[:100], model=model)  # warm caches outside the trace
    m = peak_memory(lambda: sc.hat_curve(dna, force_q, turns, model=model))
    del m["result"]
    return {"peak": m["peak"], "result": m["retained"], "peak_per_element": m["peak"] / n,
            "peak_to_result": m["peak"] / m["retained"]}


def equilibrium_cost(n=1000, samples=15):
    """CPU seconds per force of the public equilibrium and its kernel at ``n`` forces."""
    import supercoil as sc
    from supercoil.core.dna import plectoneme as pl

    dna = _dna()
    d = dna.si
    f_si = np.linspace(0.2e-12, 10e-12, n)
    f_q = f_si * sc.ureg.N
    t = interleaved_cpu({
        "public": lambda: sc.plectoneme_equilibrium(dna, f_q),
        "kernel": lambda: pl.equilibrium(f_si, d.bending_rigidity, d.torsional_rigidity,
                                         d.kT, d.radius),
    }, samples=samples)
    return {"public_per_force": t["public"] / n, "kernel_per_force": t["kernel"] / n}


def equilibrium_memory(n):
    """Peak traced bytes of one public ``sc.plectoneme_equilibrium`` at ``n`` forces.

    The forces (0.2-10 pN, a quantity in N) are allocated before the call.
    ``beyond_output_per_force`` is (peak - retained output) / n.
    """
    import supercoil as sc

    dna = _dna()
    sc.plectoneme_equilibrium(dna, np.linspace(0.2, 10, 100) * sc.ureg.pN)  # warm caches
    f_q = np.linspace(0.2e-12, 10e-12, n) * sc.ureg.N
    m = peak_memory(lambda: sc.plectoneme_equilibrium(dna, f_q))
    del m["result"]
    return {"peak": m["peak"], "output": m["retained"],
            "beyond_output_per_force": (m["peak"] - m["retained"]) / n}


def loader_cost(n_rows, samples=5, directory=None):
    """``sc.read_tweezers_csv`` against plain pandas on one file of ``n_rows`` rows.

    Returns
    -------
    dict
        ``loader``, ``pandas`` (CPU s per read, median of interleaved samples),
        ``ratio``, ``peak``, ``output`` (bytes the returned DataFrame holds) and
        ``beyond_output_per_row`` ((peak - output) / rows, bytes).
    """
    import pandas as pd

    import supercoil as sc

    with tempfile.TemporaryDirectory(dir=directory) as tmp:
        path = write_rotation_csv(Path(tmp) / "rotation.csv", n_rows)
        t = interleaved_cpu({
            "loader": lambda: sc.read_tweezers_csv(path),
            "pandas": lambda: pd.read_csv(path, comment="#", skipinitialspace=True),
        }, samples=samples, min_sample=0.0)
        m = peak_memory(lambda: sc.read_tweezers_csv(path))
    del m["result"]
    return {"loader": t["loader"], "pandas": t["pandas"], "ratio": t["loader"] / t["pandas"],
            "peak": m["peak"], "output": m["retained"],
            "beyond_output_per_row": (m["peak"] - m["retained"]) / n_rows}
