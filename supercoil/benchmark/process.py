"""Headline measurements in fresh interpreters: import time and the CLI main job.

* :func:`import_time`: wall time of ``import supercoil`` inside a fresh
  ``python`` process (timed by the child around the import statement, so the
  interpreter's own start-up is left out and reported separately), median of
  ``repeat`` processes;
* :func:`cli_hat_phases`: the CLI main job ``supercoil hat --params dna --out
  DIR`` (``python -m supercoil.cli``): its whole wall time as a subprocess
  (median), and in a second fresh interpreter the same job split into
  ``startup`` (interpreter start-up and exit: the wall time of the process
  minus the time inside the script), ``import`` (``import supercoil.cli``), ``compute``
  (argument parsing to the end of the last CSV written: parameters, hat
  curve, buckling table, CSVs), ``plot`` (from there to the end of
  ``plot_hat_curves``: matplotlib import, figure, PNG) and ``rest`` (the printed
  table). The split wraps ``supercoil.tables.write_csv`` and
  ``plot_hat_curves`` (in ``supercoil.dna.plot`` and ``supercoil.dna.hat``: the
  command imports them at run time) with clocks; if a hook does not fire, the
  measurement fails with that message. Modules that ``import supercoil`` loads
  lazily are loaded (and counted) in the phase that first needs them.

The children import this checkout of supercoil (its parent folder first on
``PYTHONPATH``) with ``MPLBACKEND=Agg``.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

_IMPORT = """
import time
t0, c0 = time.perf_counter(), time.process_time()
import supercoil
print(time.perf_counter() - t0, time.process_time() - c0)
"""

_PHASES = """
import json, sys, time
t_start = time.perf_counter()
import supercoil.cli as cli
t_import = time.perf_counter()
import importlib
import supercoil.tables as tables
marks = {}
def clocked(func, mark):
    def wrapper(*a, **k):
        out = func(*a, **k)
        marks[mark] = time.perf_counter()
        return out
    return wrapper
tables.write_csv = clocked(tables.write_csv, "csv")
for name in ("supercoil.dna.plot", "supercoil.dna.hat"):  # wherever the command imports it from
    module = importlib.import_module(name)
    if hasattr(module, "plot_hat_curves"):
        module.plot_hat_curves = clocked(module.plot_hat_curves, "plot")
import contextlib, io
with contextlib.redirect_stdout(io.StringIO()):
    code = cli.main(["hat", "--params", "dna", "--out", sys.argv[1]])
t_end = time.perf_counter()
if "csv" not in marks or "plot" not in marks:
    sys.exit(f"the timing hooks did not fire (marks: {sorted(marks)}): "
             "supercoil hat no longer calls supercoil.tables.write_csv and plot_hat_curves")
print(json.dumps({"code": code, "import": t_import - t_start,
                  "compute": marks["csv"] - t_import, "plot": marks["plot"] - marks["csv"],
                  "rest": t_end - marks["plot"], "inside": t_end - t_start}))
"""


def _env():
    root = str(Path(__file__).resolve().parents[2])
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([root] + [p for p in [env.get("PYTHONPATH")] if p])
    env["MPLBACKEND"] = "Agg"
    return env


def _children_cpu():
    import resource

    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return ru.ru_utime + ru.ru_stime


def _run(args, env, timeout=120):
    """``(stdout, wall seconds, CPU seconds)`` of ``python *args`` in a child process."""
    c0, t0 = _children_cpu(), time.perf_counter()
    proc = subprocess.run([sys.executable, *args], env=env, capture_output=True, text=True,
                          check=False, timeout=timeout)
    wall, cpu = time.perf_counter() - t0, _children_cpu() - c0
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(args)} failed ({proc.returncode}): {proc.stderr[-500:]}")
    return proc.stdout, wall, cpu


def import_time(repeat=5):
    """Median in-process wall seconds of ``import supercoil``; interpreter start-up beside.

    Returns
    -------
    dict
        ``import`` (s, median), ``samples`` (list), ``import_cpu`` (CPU s of the
        import, median) and ``startup`` (median wall of ``python -c pass``, s).
    """
    env = _env()
    samples, cpus, startups = [], [], []
    for _ in range(repeat):  # interleaved: start-up, import, start-up, import, ...
        startups.append(_run(["-c", "pass"], env)[1])
        wall, cpu = _run(["-c", _IMPORT], env)[0].split()[-2:]
        samples.append(float(wall))
        cpus.append(float(cpu))
    return {"import": float(np.median(samples)), "samples": samples,
            "import_cpu": float(np.median(cpus)), "startup": float(np.median(startups))}


def cli_hat_phases(repeat=3):
    """Wall seconds of ``supercoil hat --params dna --out DIR``, whole and by phase.

    Returns
    -------
    dict
        ``wall`` (median of ``repeat`` subprocess runs of ``python -m
        supercoil.cli hat --params dna --out DIR``; with ``repeat=0`` the wall
        time of the hooked run), ``cpu`` (CPU s of the same processes, median),
        and from one hooked run
        ``startup``, ``import``, ``compute``, ``plot``, ``rest`` (s).
    """
    env = _env()
    with tempfile.TemporaryDirectory() as tmp:
        runs = [_run(["-m", "supercoil.cli", "hat", "--params", "dna", "--out", tmp], env)
                for _ in range(repeat)]
        out, wall, cpu = _run(["-c", _PHASES, tmp], env)
        walls, cpus = [r[1] for r in runs] or [wall], [r[2] for r in runs] or [cpu]
        if not (Path(tmp) / "hat_curve.png").is_file():
            raise RuntimeError("supercoil hat wrote no hat_curve.png")
    phases = json.loads(out.strip().splitlines()[-1])
    if phases["code"] != 0:
        raise RuntimeError(f"supercoil hat returned {phases['code']}")
    return {"wall": float(np.median(walls)), "cpu": float(np.median(cpus)),
            "startup": wall - phases["inside"],
            **{k: phases[k] for k in ("import", "compute", "plot", "rest")}}


#: glibc's malloc settings (environment variables read at start-up) of the two memory
#: regimes of :func:`hat_throughput_regimes`: every large array from memory freed by the
#: previous call (mmap threshold at its 32 MB maximum, no trimming), or every large
#: array a fresh mapping (mmap threshold 1 MB: 8 MB arrays are mapped and unmapped, the
#: block-sized temporaries of the kernels, 256 kB, stay on the heap).
MALLOC_REGIMES = {
    "reused": {"MALLOC_MMAP_THRESHOLD_": str(32 << 20), "MALLOC_TRIM_THRESHOLD_": str(1 << 40)},
    "fresh": {"MALLOC_MMAP_THRESHOLD_": str(1 << 20)},
}

_HAT = """
import json, sys
from supercoil.benchmark.targets_dna import hat_throughput
print(json.dumps(hat_throughput(int(sys.argv[1]), samples=int(sys.argv[2]),
                                compiled=sys.argv[3] == "1")))
"""


def hat_throughput_regimes(n, samples=9, compiled=True):
    """:func:`~supercoil.benchmark.targets_dna.hat_throughput` in a child per memory regime.

    The time of a call that returns fresh arrays depends on whether the allocator
    hands it memory freed by the previous call (no page faults) or new pages (a
    fault per page; fresh memory can cost several times mapped memory, as the
    bench output's two rows show). In one process either can happen, by the heap's layout; each
    child fixes one (:data:`MALLOC_REGIMES`, glibc; elsewhere the two are alike),
    and the numpy pass of the reference is measured under the same regime.

    Returns
    -------
    dict
        ``{"reused": {...}, "fresh": {...}}``: the dicts of ``hat_throughput``.
    """
    out = {}
    for regime, malloc in MALLOC_REGIMES.items():
        env = {**_env(), **malloc}
        text, _, _ = _run(["-c", _HAT, str(n), str(samples), "1" if compiled else "0"], env)
        out[regime] = json.loads(text.strip().splitlines()[-1])
    return out


_MODELS = """
import json, sys
from supercoil.benchmark.dna_models import model_cost
kw = json.loads(sys.argv[1])
kw["sizes"], kw["models"] = tuple(kw["sizes"]), tuple(kw["models"])
kw["coiled"] = tuple(kw["coiled"]) if kw["coiled"] else None
print(json.dumps(model_cost(**kw)))
"""


def model_cost_regimes(**kw):
    """:func:`~supercoil.benchmark.dna_models.model_cost` in a child per memory regime.

    The models' ratio moves with the allocator as the hat curve's does: li-zhao's
    ten-odd fresh output arrays per call fault page by page, the free-energy kernel
    fills kept workspaces, so fresh mappings slow li-zhao several times more than
    free-energy (the bench's rows give both). Each regime's rows carry it in a
    ``regime`` column (:data:`MALLOC_REGIMES`).

    Returns
    -------
    dict
        The rows of ``model_cost`` (dict of lists) of both regimes, with ``regime``.
    """
    rows = None
    for regime, malloc in MALLOC_REGIMES.items():
        text, _, _ = _run(["-c", _MODELS, json.dumps(kw)], {**_env(), **malloc}, timeout=600)
        part = json.loads(text.strip().splitlines()[-1])
        part["regime"] = [regime] * len(part["model"])
        rows = part if rows is None else {k: rows[k] + part[k] for k in rows}
    return rows


_FIT_MANY = """
import json, sys
from supercoil.benchmark.targets_fit import fit_many_cost
replayed = tuple(int(x) for x in sys.argv[2].split(","))
r = fit_many_cost(pooled=int(sys.argv[1]), replayed=replayed, read_back=int(sys.argv[3]),
                  repeats=int(sys.argv[4]))
print(json.dumps({k: (v if not hasattr(v, "tolist") else v.tolist()) for k, v in r.items()}))
"""


def fit_many_cost_child(pooled, replayed, read_back, repeats):
    """:func:`~supercoil.benchmark.targets_fit.fit_many_cost` in a fresh interpreter.

    A process pool forks its workers from the calling process: after the other
    benchmarks that process holds a large heap of Python objects, whose pages
    the workers copy as they touch them (reference counts), which a user's
    fitting script does not. Measured in a fresh child, as such a script runs.
    """
    args = [str(pooled), ",".join(str(n) for n in replayed), str(read_back), str(repeats)]
    text, _, _ = _run(["-c", _FIT_MANY, *args], _env(), timeout=900)
    return json.loads(text.strip().splitlines()[-1])


_PHYSICAL = """
import json, sys
from supercoil.benchmark.fit_many import physical_throughput
print(json.dumps(physical_throughput(int(sys.argv[1]), repeats=int(sys.argv[2]))))
"""


def physical_throughput_child(n_molecules, repeats=1):
    """:func:`~supercoil.benchmark.fit_many.physical_throughput` in a fresh interpreter
    (as :func:`fit_many_cost_child`: the pool forks from a small process)."""
    text, _, _ = _run(["-c", _PHYSICAL, str(n_molecules), str(repeats)], _env(), timeout=900)
    return json.loads(text.strip().splitlines()[-1])
