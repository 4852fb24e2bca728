"""Headline measurements of the fits: one global fit, and many molecules.

* :func:`fit_cost`: CPU time of the public ``sc.fit_hat_curves`` on the problem
  of ``examples/fit_tweezers_data.py`` (3 forces x 110 points, twist
  persistence and radius varied, both offsets fitted), the number of kernel
  calls per fit (``supercoil.core.dna.li_zhao.hat_curve_points`` wrapped with a
  counter for one fit; the fit's own ``nfev`` beside it) and the CPU cost of one
  such kernel call on the arguments the fit passed, timed interleaved with the
  fit, both with BLAS limited to one thread (``threadpoolctl``), and the fit
  again with the default BLAS threads. The lower bound of a fit is calls x
  kernel cost. The re-timed calls carry the fit's memoised equilibrium
  solver, so they solve no plectoneme equilibrium: ``kernel_in_fit`` is the
  kernel CPU the fit itself pays, its equilibrium solves included.
* :func:`fit_many_cost`: the parent's CPU time per molecule of the public
  ``sc.fit_many``: with a real ``ProcessPoolExecutor(2)`` (the parent prepares,
  pickles, submits, collects and builds the table while the workers fit), and
  with a replaying executor whose ``submit()`` returns an already finished
  future holding one recorded worker result (the parent's own cost with no
  worker at all, affordable at 2,000 molecules); and the wall-time speed-up of
  ``ProcessPoolExecutor(2)`` over the serial call (medians of interleaved
  repeats; the pool's start-up and shutdown timed; every run with cold kernel
  tables).
"""

from __future__ import annotations

import contextlib
import copy
import tempfile
import time
from concurrent.futures import Future, ProcessPoolExecutor
from pathlib import Path

import numpy as np

from supercoil.benchmark.cpu import cpu_once, interleaved_cpu

FORCES_PN = (0.3, 0.5, 0.7)
POINTS_PER_FORCE = 110
VARY = ("twist_persistence", "radius")


def fit_problem(molecules=None, seed=20261121):
    """``(data, seed_set)``: the synthetic data of ``examples/fit_tweezers_data.py``.

    True parameters C_t = 95 nm, r_0 = 2.0 nm (the seed set has 86 nm and
    1.75 nm), turns offset 0.4 turn, extension offset 30 nm, 5 nm noise.
    ``molecules``: that many molecules (a ``molecule`` column) instead of one.
    """
    import supercoil as sc

    u = sc.ureg
    seed_set = sc.load_parameters("dna")
    true = seed_set.replace(twist_persistence=95 * u.nm, radius=2.0 * u.nm)
    extra = {} if molecules is None else {"molecules": molecules}
    data = sc.simulate_rotation_curves(true, np.array(FORCES_PN) * u.pN,
                                       points_per_force=POINTS_PER_FORCE, noise=5 * u.nm,
                                       turns_offset=0.4, extension_offset=30 * u.nm,
                                       seed=seed, **extra)
    return data, seed_set


class _KernelCounter:
    """Replaces ``supercoil.core.dna.li_zhao.hat_curve_points`` by a counting wrapper."""

    def __init__(self):
        from supercoil.core.dna import li_zhao

        self.module, self.original, self.calls = li_zhao, li_zhao.hat_curve_points, []

    def __enter__(self):
        def counted(*args, **kwargs):
            self.calls.append((copy.deepcopy(args), dict(kwargs)))
            return self.original(*args, **kwargs)

        self.module.hat_curve_points = counted
        return self

    def __exit__(self, *exc):
        self.module.hat_curve_points = self.original


class _KernelTimer:
    """Sums the CPU time spent inside ``hat_curve_points`` (no copies, only a clock)."""

    def __init__(self):
        from supercoil.core.dna import li_zhao

        self.module, self.original, self.cpu = li_zhao, li_zhao.hat_curve_points, 0.0

    def __enter__(self):
        def timed(*args, **kwargs):
            t0 = time.process_time()
            try:
                return self.original(*args, **kwargs)
            finally:
                self.cpu += time.process_time() - t0

        self.module.hat_curve_points = timed
        return self

    def __exit__(self, *exc):
        self.module.hat_curve_points = self.original


def clear_kernel_caches():
    """Clear the process-wide memo tables of the DNA kernels (``functools.lru_cache``).

    ``supercoil.core.dna.plectoneme.reduced_branch_table`` keeps the tabulated
    plectoneme branch of each ``B/(kT r0)`` across fits: a fit repeated on the
    same data finds every table it needs, a new molecule's fit (new radii)
    builds its own. Clearing them before each fit measures the latter.
    """
    from supercoil.core.dna import electrostatics, plectoneme

    for module in (plectoneme, electrostatics):
        for obj in vars(module).values():
            if not isinstance(obj, type) and callable(getattr(obj, "cache_clear", None)):
                obj.cache_clear()


def kernel_cpu_in_fit(fit, samples=9):
    """Median over ``samples`` calls of ``fit()`` of the CPU time spent inside the kernel.

    Unlike the re-timed calls of :func:`fit_cost`'s ``lower_bound`` (whose
    equilibrium solver is the fit's own memoised one, so every re-timed call
    finds its plectoneme equilibrium already solved), this counts the
    equilibria the fit really solves: the kernel cost the fit itself pays.
    """
    sums = []
    for _ in range(samples):
        with _KernelTimer() as timer:
            fit()
        sums.append(timer.cpu)
    return float(np.median(sums))


def fit_cost(samples=9):
    """CPU time per fit, kernel calls per fit and the kernel-cost lower bound.

    Returns
    -------
    dict
        ``fit`` (CPU s per fit, median, BLAS on one thread when ``blas_limited``),
        ``fit_default_threads`` (the same with the default BLAS threads: on a
        multi-core machine the idle BLAS threads' spinning adds CPU time),
        ``kernel_calls`` (counted in one fit),
        ``nfev`` (the fit result's, or NaN if it has none), ``call_sizes``
        (text: how many calls of each size), ``lower_bound`` (the sum over the
        calls of the CPU cost of a kernel call of that size, timed on the
        arguments the fit passed; the fit's memoised equilibrium solver comes
        with them, so these re-timed calls solve no plectoneme equilibrium) and
        ``ratio`` (fit / lower_bound); ``kernel_in_fit`` (CPU s inside the
        kernel during one fit, its equilibrium solves included:
        :func:`kernel_cpu_in_fit`) and ``ratio_in_fit`` (fit / kernel_in_fit);
        ``fit_cold``, ``kernel_in_fit_cold`` and ``ratio_in_fit_cold``: the same
        with the kernels' process-wide tables cleared before every fit
        (:func:`clear_kernel_caches`; the cost of a new molecule's fit, the
        repeated fit above reuses the tables of the earlier repetitions).
    """
    import supercoil as sc

    data, seed_set = fit_problem()
    vary = list(VARY)
    sc.fit_hat_curves(data, seed_set, vary=vary)  # warm-up
    with _KernelCounter() as counter:
        result = sc.fit_hat_curves(data, seed_set, vary=vary)
    if not counter.calls:
        raise RuntimeError("the fit made no call of supercoil.core.dna.li_zhao.hat_curve_points")
    kernel = counter.original
    groups = {}  # one representative call per call size, and how many calls had that size
    for args, kwargs in counter.calls:
        n = int(np.size(args[0]))
        groups.setdefault(n, [args, kwargs, 0])[2] += 1
    funcs = {"fit": lambda: sc.fit_hat_curves(data, seed_set, vary=vary)}
    for n, (args, kwargs, _) in groups.items():
        funcs[n] = lambda args=args, kwargs=kwargs: kernel(*args, **kwargs)

    def cold():  # what a new molecule costs: no kernel table of an earlier fit
        clear_kernel_caches()
        return funcs["fit"]()

    limit, limited = blas_single_thread()
    with limit:  # the fit and its kernel calls on one BLAS thread
        t = interleaved_cpu(funcs, samples=samples)
        in_fit = kernel_cpu_in_fit(funcs["fit"], samples=samples)
        t_cold = interleaved_cpu({"cold": cold}, samples=samples)["cold"]
        in_fit_cold = kernel_cpu_in_fit(cold, samples=samples)
    # the same fit with the process's default BLAS threads (idle threads spin on CPU time)
    default = interleaved_cpu({"fit": funcs["fit"]}, samples=samples)["fit"]
    lower = sum(count * t[n] for n, (_, _, count) in groups.items())
    sizes = ", ".join(f"{count} x {n} points" for n, (_, _, count) in groups.items())
    return {"fit": t["fit"], "fit_default_threads": default, "blas_limited": limited,
            "kernel_calls": len(counter.calls),
            "nfev": float(getattr(result, "nfev", float("nan"))), "call_sizes": sizes,
            "lower_bound": lower, "ratio": t["fit"] / lower,
            "kernel_in_fit": in_fit, "ratio_in_fit": t["fit"] / in_fit,
            "fit_cold": t_cold, "kernel_in_fit_cold": in_fit_cold,
            "ratio_in_fit_cold": t_cold / in_fit_cold}


def blas_single_thread():
    """``(context manager, limited)``: BLAS/OpenMP pools limited to one thread if possible.

    Uses ``threadpoolctl`` when it is installed (``limited`` True); otherwise a
    no-op context (``limited`` False) and the numbers include the BLAS threads.
    """
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover - threadpoolctl is optional
        return contextlib.nullcontext(), False
    return threadpool_limits(1), True


class ReplayExecutor:
    """An executor whose ``submit()`` returns a finished future with a recorded result.

    The first ``submit`` runs the function (call it once before timing); every
    later one returns a copy of that result without running anything, so that
    only the caller's own work is timed.
    """

    def __init__(self):
        self.result = None

    def submit(self, fn, *args, **kwargs):
        if self.result is None:
            self.result = fn(*args, **kwargs)
        fut = Future()
        fut.set_result(copy.copy(self.result))
        return fut


def _children_cpu():
    """CPU seconds (user + system) of the terminated and reaped child processes."""
    import resource

    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return ru.ru_utime + ru.ru_stime


def _pool_run(fit, workers):
    """``(table, parent CPU, wall, workers' CPU)`` of ``fit(executor)`` on a new pool.

    The pool is created, forked (at the first submit), used and shut down
    inside the timed region: its start-up is paid as a user pays it.
    """
    children = _children_cpu()

    def run():
        with ProcessPoolExecutor(max_workers=workers) as pool:
            return fit(pool)

    table, cpu, wall = cpu_once(run)
    # the workers' CPU time (they are reaped at shutdown): with the pool wall time it says
    # how many cores the workers actually got on a machine shared with other processes
    return table, cpu, wall, _children_cpu() - children


def fit_many_cost(pooled=200, replayed=(200, 2000), serial=True, workers=2, read_back=200,
                  repeats=3):
    """Parent CPU per molecule of ``sc.fit_many``, and the pool's speed-up.

    Parameters
    ----------
    pooled : int
        Molecules fitted for real, on ``ProcessPoolExecutor(workers)`` and
        (if ``serial``) serially in this process.
    replayed : tuple of int
        Molecule counts of the replaying-executor runs.
    read_back : int
        Molecules of one more replaying run on the data written with
        ``sc.write_csv`` and read back with ``sc.read_tweezers_csv`` (the
        table then carries the file line of every row in its attrs); 0: none.
    repeats : int
        Timed runs of each of pool and serial, interleaved (pool, serial,
        pool, ...); the medians are reported.

    The pool runs are timed from the creation of a new
    ``ProcessPoolExecutor(workers)`` to its shutdown (workers forked at the
    first submit, as a user pays it). Every real run, pool or serial, starts
    with the kernels' process-wide tables cleared (:func:`clear_kernel_caches`):
    forked workers would otherwise inherit the tables an earlier serial run built
    in this process, and a serial run those of the replayed fit.

    Returns
    -------
    dict
        ``pool_parent_cpu`` (s per molecule), ``pool_wall``,
        ``pool_workers_cpu`` (s, all workers together), ``serial_wall``,
        ``serial_cpu`` (s per molecule), ``speedup`` (median serial wall /
        median pool wall), ``speedups`` (of each interleaved pair),
        ``all_ok`` (every real fit succeeded), and ``replay_parent_cpu_<n>`` (s
        per molecule) for each ``n`` in ``replayed``, ``replay_read_back_cpu`` (s
        per molecule, if ``read_back``).
    """
    import supercoil as sc

    out = {}
    data, seed_set = fit_problem(molecules=max((pooled, *replayed)))
    mol = data["molecule"].astype(str).to_numpy()
    labels = list(dict.fromkeys(mol))

    def first(n):
        sub = data.loc[np.isin(mol, labels[:n])].reset_index(drop=True)
        sub.attrs = dict(data.attrs)
        return sub

    replay = ReplayExecutor()
    sc.fit_many(first(1), seed_set, vary=list(VARY), executor=replay)  # records one result
    for n in replayed:
        sub = first(n)
        _, cpu, _ = cpu_once(lambda sub=sub: sc.fit_many(sub, seed_set, vary=list(VARY),
                                                          executor=replay))
        out[f"replay_parent_cpu_{n}"] = cpu / n
    if read_back:  # the same molecules written as CSV and read by sc.read_tweezers_csv
        with tempfile.TemporaryDirectory() as tmp:
            back = sc.read_tweezers_csv(sc.write_csv(first(read_back), Path(tmp) / "m.csv"))
        _, cpu, _ = cpu_once(lambda: sc.fit_many(back, seed_set, vary=list(VARY),
                                                 executor=replay))
        out["replay_read_back_cpu"] = cpu / read_back
    sub = first(pooled)

    def fit(executor=None):
        clear_kernel_caches()  # each run starts cold: no kernel table of an earlier run
        return sc.fit_many(sub, seed_set, vary=list(VARY), executor=executor)

    runs = {"pool": [], "serial": []}
    for _ in range(max(1, repeats)):  # interleaved: pool, serial, pool, serial, ...
        table, cpu, wall, workers_cpu = _pool_run(fit, workers)
        runs["pool"].append((wall, cpu, workers_cpu, bool(table["success"].all())))
        if serial:
            table, cpu, wall = cpu_once(fit)
            runs["serial"].append((wall, cpu, 0.0, bool(table["success"].all())))
    pool = np.median(np.array(runs["pool"])[:, :3], axis=0)
    out.update(pool_parent_cpu=pool[1] / pooled, pool_wall=pool[0], pool_workers_cpu=pool[2],
               all_ok=all(r[3] for r in runs["pool"] + runs["serial"]))
    if serial:
        ser = np.median(np.array(runs["serial"])[:, :2], axis=0)
        out.update(serial_wall=ser[0], serial_cpu=ser[1] / pooled, speedup=ser[0] / pool[0],
                   speedups=[s[0] / p[0] for s, p in zip(runs["serial"], runs["pool"],
                                                           strict=True)])
    return out
