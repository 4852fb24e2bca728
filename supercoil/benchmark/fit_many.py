"""Benchmarks of :func:`supercoil.fit_many`: the client's cost per molecule and the throughput.

* :func:`client_cost`: the time the calling process spends per molecule at
  2,000 molecules (target: under 2 ms). The executor runs no fits: it
  pickles each task (what a process pool or a dask client does in the calling
  process) and hands back one real fit's row, relabelled, so what is timed is
  the table check, the validation of the settings, the split by molecule,
  building and pickling the tasks, collecting and re-issuing the rows and the
  result table.
* :func:`client_cpu`: the calling process's CPU time per molecule (all its
  threads: the executor's feeder thread, dask's event loop) of real runs on a
  ``ProcessPoolExecutor(2)`` and a dask ``LocalCluster`` of 2 processes, and
  their molecules per second.
* :func:`throughput`: molecules fitted per second per core on the 20-molecule
  synthetic set (:func:`~supercoil.simulate_rotation_curves`), serial, with a
  ``ProcessPoolExecutor(2)`` and with a dask ``LocalCluster`` of 2 worker
  processes (pools started and warmed before the clock starts).

Run ``python -m supercoil.benchmark.fit_many`` to print both tables.
"""

from __future__ import annotations

import pickle
import time
import warnings
from concurrent.futures import Future

import numpy as np
import pandas as pd

from supercoil.tables import make_table, provenance

__all__ = ["client_cost", "client_cpu", "physical_throughput", "synthetic_molecules",
           "throughput"]

FORCES_PN = (0.3, 0.5, 0.7)


def synthetic_molecules(n_molecules, points_per_force=110, seed=1, tile=False):
    """``n_molecules`` rotation curves (seed DNA set, 5 nm noise), labels ``m1``, ``m2``...

    ``tile=True`` repeats one simulated molecule (cheap for thousands).
    """
    import supercoil as sc
    from supercoil.dna.fitting import simulate_rotation_curves

    dna = sc.load_parameters("dna")
    forces = np.array(FORCES_PN) * sc.ureg.pN
    if not tile:
        return dna, simulate_rotation_curves(dna, forces, points_per_force=points_per_force,
                                             molecules=n_molecules, seed=seed)
    one = simulate_rotation_curves(dna, forces, points_per_force=points_per_force, seed=seed)
    n = len(one)
    df = pd.DataFrame({"molecule": np.repeat([f"m{i + 1}" for i in range(n_molecules)], n)})
    for col in ("force", "turns", "extension"):
        df[col] = np.tile(one[col].to_numpy(), n_molecules)
    df.attrs = {"units": dict(one.attrs["units"], molecule=""),
                "provenance": dict(one.attrs["provenance"])}
    return dna, df


class _PicklingExecutor:
    """Pickles every task like a pool would; returns one real fit's row, relabelled."""

    def __init__(self):
        self.canned = None
        self.bytes = 0
        self.tasks = 0

    def submit(self, fn, task, *args):
        self.bytes += len(pickle.dumps((fn, task, *args), protocol=pickle.HIGHEST_PROTOCOL))
        self.tasks += 1
        if self.canned is None:
            self.canned = fn(task)  # one real fit
        row, records = self.canned
        fut = Future()
        fut.set_result((dict(row, molecule=task.label, ndata=int(task.data.n)), records))
        return fut


def client_cost(n_molecules=2000, points_per_force=110, repeat=3):
    """The calling process's seconds per molecule of :func:`fit_many` (best of ``repeat``).

    Returns a one-row table: molecules, points per molecule, client ms per
    molecule, pickled kB per task.
    """
    import supercoil as sc

    dna, df = synthetic_molecules(n_molecules, points_per_force, tile=True)
    best, ex = np.inf, None
    for _ in range(repeat):
        ex = _PicklingExecutor()
        t0 = time.perf_counter()
        table = sc.fit_many(df, dna, executor=ex, progress=False)
        best = min(best, time.perf_counter() - t0)
    assert len(table) == n_molecules and ex.tasks == n_molecules
    cols = {"molecules": [n_molecules], "points_per_molecule": [len(df) // n_molecules],
            "client_time_per_molecule": [best / n_molecules * 1e3],
            "pickled_per_task": [ex.bytes / ex.tasks / 1e3]}
    units = {"molecules": "", "points_per_molecule": "", "client_time_per_molecule": "ms",
             "pickled_per_task": "kB"}
    return make_table(cols, units, provenance(None, target="client_time_per_molecule < 2 ms",
                                              repeat=repeat))


def _runners(workers, dask):
    """``(name, context manager giving an executor)`` of the parallel runners."""
    from concurrent.futures import ProcessPoolExecutor

    out = [(f"ProcessPoolExecutor({workers})", lambda: ProcessPoolExecutor(workers))]
    if dask:
        from contextlib import contextmanager

        @contextmanager
        def dask_client():
            from distributed import Client, LocalCluster

            with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                              dashboard_address=None) as cluster, Client(cluster) as client:
                yield client

        out.append((f"dask LocalCluster({workers})", dask_client))
    return out


def client_cpu(n_molecules=2000, workers=2, dask=True):
    """CPU seconds of the calling process per molecule in real parallel runs (warmed pools).

    Returns a table: runner, molecules, client CPU per molecule (ms), wall
    seconds, molecules per second.
    """
    import supercoil as sc

    dna, df = synthetic_molecules(n_molecules, tile=True)
    warm = df[df["molecule"].isin(["m1", "m2"])].reset_index(drop=True)
    warm.attrs = dict(df.attrs)
    rows = []
    for name, make in _runners(workers, dask):
        with make() as ex:
            sc.fit_many(warm, dna, executor=ex, progress=False)
            cpu, wall = time.process_time(), time.perf_counter()
            table = sc.fit_many(df, dna, executor=ex, progress=False)
            cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
        if not table["success"].all():
            raise RuntimeError(f"benchmark fits failed: {table['error'].iloc[0]}")
        rows.append((name, cpu / n_molecules * 1e3, wall, n_molecules / wall))
    cols = {"runner": [r[0] for r in rows], "molecules": [n_molecules] * len(rows),
            "client_cpu_per_molecule": [r[1] for r in rows], "seconds": [r[2] for r in rows],
            "molecules_per_second": [r[3] for r in rows]}
    units = {"runner": "", "molecules": "", "client_cpu_per_molecule": "ms", "seconds": "s",
             "molecules_per_second": "1/s"}
    return make_table(cols, units, provenance(None, target="client_cpu_per_molecule < 2 ms"))


def _time_fits(df, dna, executor):
    import supercoil as sc

    t0 = time.perf_counter()
    table = sc.fit_many(df, dna, executor=executor, progress=False)
    seconds = time.perf_counter() - t0
    if not table["success"].all():
        raise RuntimeError(f"benchmark fits failed: {table['error'].tolist()}")
    return seconds


def throughput(n_molecules=20, workers=2, dask=True):
    """Molecules per second per core: serial, process pool and dask LocalCluster.

    Returns a table with one row per runner: runner, cores, seconds,
    molecules per second, molecules per second per core.
    """
    dna, df = synthetic_molecules(n_molecules)
    warm = df[df["molecule"].isin(["m1", "m2"])].reset_index(drop=True)
    warm.attrs = dict(df.attrs)
    rows = [("serial", 1, _time_fits(df, dna, None))]
    for name, make in _runners(workers, dask):
        with make() as ex:
            _time_fits(warm, dna, ex)  # start the workers, import the package there
            rows.append((name, workers, _time_fits(df, dna, ex)))
    cols = {"runner": [r[0] for r in rows], "cores": [r[1] for r in rows],
            "seconds": [r[2] for r in rows],
            "molecules_per_second": [n_molecules / r[2] for r in rows],
            "molecules_per_second_per_core": [n_molecules / r[2] / r[1] for r in rows]}
    units = {"runner": "", "cores": "", "seconds": "s", "molecules_per_second": "1/s",
             "molecules_per_second_per_core": "1/s"}
    return make_table(cols, units, provenance(None, molecules=n_molecules,
                                              points_per_molecule=len(df) // n_molecules))


def _children_cpu():
    import resource

    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return ru.ru_utime + ru.ru_stime


def physical_throughput(n_molecules=200, workers=2, model="free-energy",
                        interaction="hard-core", repeats=1):
    """Serial against ``ProcessPoolExecutor(workers)`` fits of the physical model.

    The molecules of :func:`supercoil.benchmark.targets_fit.fit_problem` (3 forces x 110
    points, C_t and r_0 varied), fitted with ``model`` / ``interaction``; each run starts
    with the kernels' memo tables cleared (a forked worker would inherit the serial
    run's), the pool run from the pool's creation to its shutdown (workers forked at the
    first submit, as a user pays it). One fit of two molecules first imports what the
    fits import lazily (else the first serial run pays it and the pool's forks do not).
    ``repeats`` serial and pool runs alternate; each quantity is the median over them (on
    a shared 2-core machine one run's CPU time per molecule moves by up to 40 %). The
    ratios are paired: each pool run against the serial run just before it, then the
    median over the pairs (a drift of the machine's speed between runs cancels within a
    pair; measured on 8 pairs of 200 molecules here, the per-core ratio of single pairs
    spread over 0.79-1.07 while the workers' page faults and system time stayed below
    1 % of their CPU).

    Returns
    -------
    dict
        ``serial_wall``, ``pool_wall`` (s); ``serial_rate`` and ``pool_rate_per_core``
        (molecules per second per core: the pool's over ``workers``); ``per_core_ratio``
        (pool per core / serial); ``serial_cpu`` and ``pool_cpu`` (s per molecule: the
        pool's the workers' and the parent's together) and ``cpu_ratio`` (pool CPU per
        molecule over serial: the pool's overhead whatever the machine's load);
        ``pool_cores`` (the workers' CPU over the pool's wall time: the cores they got);
        ``repeats``. ``per_core_ratio`` and ``cpu_ratio`` are medians of the pairs'
        ratios, with their smallest and largest in ``per_core_ratio_range`` and
        ``cpu_ratio_range``.
    """
    from concurrent.futures import ProcessPoolExecutor

    import supercoil as sc
    from supercoil.benchmark.targets_fit import VARY, clear_kernel_caches, fit_problem

    data, seed_set = fit_problem(molecules=n_molecules)
    kw = {"vary": list(VARY), "model": model, "interaction": interaction, "progress": False}

    def fit(executor=None, df=data):
        clear_kernel_caches()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            table = sc.fit_many(df, seed_set, executor=executor, **kw)
        if not table["success"].all():
            raise RuntimeError(f"benchmark fits failed: {table['error'].dropna().iloc[0]}")

    warm = data[data["molecule"].isin(data["molecule"].unique()[:2])].reset_index(drop=True)
    warm.attrs = dict(data.attrs)
    fit(df=warm)
    runs = {k: [] for k in ("serial_cpu", "serial_wall", "pool_cpu", "pool_wall",
                            "workers_cpu")}
    for _ in range(max(int(repeats), 1)):
        c0, w0 = time.process_time(), time.perf_counter()
        fit()
        runs["serial_cpu"].append(time.process_time() - c0)
        runs["serial_wall"].append(time.perf_counter() - w0)
        k0, c0, w0 = _children_cpu(), time.process_time(), time.perf_counter()
        with ProcessPoolExecutor(workers) as pool:
            fit(pool)
        runs["pool_wall"].append(time.perf_counter() - w0)
        runs["workers_cpu"].append(_children_cpu() - k0)
        runs["pool_cpu"].append(runs["workers_cpu"][-1] + time.process_time() - c0)
    med = {k: float(np.median(v)) for k, v in runs.items()}
    pairs = {k: np.asarray(v, dtype=float) for k, v in runs.items()}
    per_core_pairs = pairs["serial_wall"] / pairs["pool_wall"] / workers
    cpu_pairs = pairs["pool_cpu"] / pairs["serial_cpu"]
    return {"molecules": n_molecules, "workers": workers, "repeats": len(runs["pool_wall"]),
            "serial_wall": med["serial_wall"], "pool_wall": med["pool_wall"],
            "serial_rate": n_molecules / med["serial_wall"],
            "pool_rate_per_core": n_molecules / med["pool_wall"] / workers,
            "per_core_ratio": float(np.median(per_core_pairs)),
            "per_core_ratio_range": [float(per_core_pairs.min()), float(per_core_pairs.max())],
            "serial_cpu": med["serial_cpu"] / n_molecules,
            "pool_cpu": med["pool_cpu"] / n_molecules,
            "cpu_ratio": float(np.median(cpu_pairs)),
            "cpu_ratio_range": [float(cpu_pairs.min()), float(cpu_pairs.max())],
            "pool_cores": med["workers_cpu"] / med["pool_wall"]}


def main():  # pragma: no cover - a command-line benchmark
    from supercoil.benchmark.timing import machine_description

    print(machine_description())
    with pd.option_context("display.width", 120):
        print(client_cost())
        print(client_cpu())
        print(throughput())


if __name__ == "__main__":  # pragma: no cover
    main()
