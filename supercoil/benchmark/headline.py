"""The headline table: every speed and memory target with its measured value.

:func:`measure` runs the measurements of :mod:`~supercoil.benchmark.targets_dna`,
:mod:`~supercoil.benchmark.targets_fit`, :mod:`~supercoil.benchmark.process` and
:mod:`~supercoil.benchmark.dna_models` (sizes in :data:`FULL` or, for
``--quick``, :data:`QUICK`; for ``--smoke``, :data:`SMOKE`); :func:`target_rows`
turns them into one row per target: ``measurement`` (naming exactly what is timed:
a public call such as ``sc.hat_curve`` or a kernel such as
``supercoil.core.dna.li_zhao.hat_curve_points``, and the size), ``value``,
``unit``, ``target``, ``met`` and ``note``. Times are CPU times
(``time.process_time``, medians of interleaved samples) except the ones a
subprocess or a process pool makes wall time by nature (import, CLI, pool
speed-up), which say so. The targets are benchmarks, never test assertions.

:func:`markdown` renders the table (with the machine and its load average);
``supercoil docs figures`` copies it into the README.
"""

from __future__ import annotations

import os

import numpy as np

#: sizes of the full run (``supercoil bench``)
FULL = {"hat_n": 10**6, "hat_mem": (10**6, 10**7), "eq_n": 1000, "eq_mem": 10**7,
        "loader_rows": 10**5, "fit_samples": 9, "pooled": 200, "replayed": (200, 2000),
        "pool_repeats": 3,
        "import_repeat": 5, "cli_repeat": 3, "model_forces": 1000,
        "model_sizes": (1_000, 100_000), "samples": 9, "physical": 200, "physical_repeats": 5,
        "fit_samples_models": 9,
        "coiled_points": 200_000}
#: sizes of ``supercoil bench --quick`` (seconds; the names of the rows give the sizes)
QUICK = {"hat_n": 10**5, "hat_mem": (10**4, 10**5), "eq_n": 1000, "eq_mem": 10**5,
         "loader_rows": 5_000, "fit_samples": 2, "pooled": 4, "replayed": (4, 20),
         "pool_repeats": 1,
         "import_repeat": 0, "cli_repeat": 0, "model_forces": 100, "model_sizes": (1_000,),
         "samples": 2, "physical": 40, "physical_repeats": 1, "fit_samples_models": 1,
         "coiled_points": 20_000}
#: sizes of ``supercoil bench --smoke``: every row measured once at the smallest sizes
#: that still exercise it (the hat curve above glibc's 1 MB mmap threshold, two molecules
#: on the pool), the test suite's run; its values say nothing about speed
SMOKE = {"hat_n": 2 * 10**5, "hat_mem": (10**4, 2 * 10**5), "eq_n": 100, "eq_mem": 10**4,
         "loader_rows": 1_000, "fit_samples": 1, "pooled": 2, "replayed": (2, 4),
         "pool_repeats": 1,
         "import_repeat": 0, "cli_repeat": 0, "model_forces": 20, "model_sizes": (100,),
         "samples": 1, "physical": 10, "physical_repeats": 1, "fit_samples_models": 1,
         "coiled_points": 20_000}
MODELS = ("li-zhao", "free-energy", "marko2007")


def measure(quick=False, log=print, size=None):
    """Run every headline measurement; a dict of result dicts by group.

    ``size`` ("full", "quick" or "smoke") overrides ``quick``.
    """
    from supercoil.benchmark import fit_models, process, targets_dna, targets_fit

    size = size or ("quick" if quick else "full")
    quick = size != "full"
    s = {"full": FULL, "quick": QUICK, "smoke": SMOKE}[size]
    r = {"load_start": os.getloadavg()[0]}
    log("headline: hat curve and plectoneme equilibrium (CPU, interleaved) ...")
    # quick: no compiled kernel (its compilation in each child would dominate the run)
    r["hat"] = process.hat_throughput_regimes(s["hat_n"], samples=s["samples"],
                                              compiled=not quick)
    r["hat_n"] = s["hat_n"]
    r["hat_mem"] = {n: targets_dna.hat_memory(n) for n in s["hat_mem"]}
    r["hat_mem_models"] = {m: targets_dna.hat_memory(s["hat_mem"][0], model=m)
                           for m in ("free-energy", "marko2007")}
    r["eq"] = targets_dna.equilibrium_cost(s["eq_n"], samples=s["samples"])
    r["eq"]["n"] = s["eq_n"]
    log("headline: peak memory (tracemalloc) ...")
    r["eq_mem"] = targets_dna.equilibrium_memory(s["eq_mem"])
    r["eq_mem"]["n"] = s["eq_mem"]
    log("headline: tweezers loader against pandas ...")
    r["loader"] = targets_dna.loader_cost(s["loader_rows"], samples=3 if quick else 5)
    r["loader"]["n"] = s["loader_rows"]
    log("headline: fit and fit_many ...")
    r["fit"] = targets_fit.fit_cost(samples=s["fit_samples"])
    r["many"] = process.fit_many_cost_child(s["pooled"], s["replayed"], min(s["replayed"]),
                                            s["pool_repeats"])
    r["many"].update(pooled=s["pooled"], replayed=s["replayed"], read_back=min(s["replayed"]))
    log("headline: fit_many with the physical model, serial and on a pool ...")
    r["physical"] = process.physical_throughput_child(s["physical"], s["physical_repeats"])
    log("headline: fits of the physical models against the paper's ...")
    r["fit_models"] = fit_models.fit_model_cost(samples=s["fit_samples_models"])
    log("headline: import time and the CLI main job (fresh interpreters) ...")
    r["cli"] = process.cli_hat_phases(repeat=s["cli_repeat"])
    if s["import_repeat"] > 0:
        r["import"] = process.import_time(repeat=s["import_repeat"])
    else:  # quick: the import phase of the CLI run (import supercoil.cli)
        r["import"] = {"import": r["cli"]["import"], "import_cpu": float("nan"),
                       "startup": float("nan")}
    log("headline: DNA models side by side ...")
    r["models"] = process.model_cost_regimes(n_forces=s["model_forces"],
                                             sizes=list(s["model_sizes"]), repeat=s["samples"],
                                             models=list(MODELS),
                                             coiled=[40.0, s["coiled_points"]])
    r["load_end"] = os.getloadavg()[0]
    return r


def target_row(measurement, value, unit, target, met, note=""):
    """One headline row (a dict of the table's columns)."""
    return {"measurement": measurement, "value": float(value), "unit": unit,
            "target": target, "met": bool(met), "note": note}


_row = target_row


def _faults(h):
    """Page faults per call of the public call, the 9 columns and the pass (if counted)."""
    if h.get("public_faults") is None:
        return ""
    return (f"; minor page faults per call: public {h['public_faults']:.0f}, the 9 columns "
            f"{h['columns_write_faults']:.0f}, the sqrt pass {h['sqrt_pass_faults']:.0f} "
            "(fresh memory the kernel zeroes)")


def _memory_row(call, n, mem, target):
    """A row of peak traced memory over the memory of the result of ``call`` at ``n`` values."""
    return _row(f"public {call}, {n:.0e} turns values: peak traced memory / memory of its "
                "result", mem["peak_to_result"], "x", target, mem["peak_to_result"] <= 1.5,
                f"peak {mem['peak_per_element']:.3g} B per element, result "
                f"{mem['result'] / n:.3g} B per element (tracemalloc)")


#: the allocator regimes of the hat-curve rows (supercoil.benchmark.process.MALLOC_REGIMES)
REGIMES = {"reused": "memory reused from the previous call",
           "fresh": "fresh memory: every large array newly mapped, the pass's too"}


def _hat_rows(h, n, per_point, regime):
    """The hat-curve rows (public, against its columns, kernel; numpy and compiled) of one
    memory regime."""
    when = f"[{REGIMES[regime]}]"
    ref = f"one numpy pass np.sqrt(turns) over the same array ({h['sqrt_pass'] * 1e3:.3g} ms)"
    rows = [
        _row(f"public sc.hat_curve, {n:.0e} turns values at 1.2 pN (numpy path, the default) "
             f"{when}: CPU per call / {ref}", h["public_ratio"], "x", "<= 10x",
             h["public_ratio"] <= 10,
             f"{h['public'] * 1e3:.3g} ms; returns a 9-column DataFrame of {per_point:.3g} B per "
             f"point; writing the table's 9 fresh columns alone costs "
             f"{h['columns_write_ratio']:.3g}x; / np.multiply(turns, 2.0) "
             f"({h['numpy_pass'] * 1e3:.3g} ms): {h['public_mul_ratio']:.3g}x" + _faults(h)),
        _row(f"public sc.hat_curve table of {n:.0e} turns values at 1.2 pN {when}: CPU per "
             "call / writing its 9 columns alone (7 fresh float64 and 2 one-byte arrays, "
             f"{h['columns_write'] * 1e3:.3g} ms)", h["public"] / h["columns_write"], "x",
             "<= 2x", h["public"] / h["columns_write"] <= 2,
             f"the kernel alone {h['kernel'] / h['columns_write']:.3g}x (its forces written "
             "out; the public call passes one force broadcast)"),
        _row(f"kernel supercoil.core.dna.li_zhao.hat_curve_points, {n:.0e} points (numpy path) "
             f"{when}: CPU per call / the same sqrt pass", h["kernel_ratio"], "x", "<= 5x",
             h["kernel_ratio"] <= 5,
             f"{h['kernel'] * 1e3:.3g} ms; / the multiply pass {h['kernel_mul_ratio']:.3g}x"),
    ]
    if "kernel_fast_ratio" in h:
        rows += [
            _row(f"compiled kernel hat_curve_points(fast=True) (numba, supercoil[fast]), "
                 f"{n:.0e} points {when} / the same sqrt pass", h["kernel_fast_ratio"], "x",
                 "<= 5x", h["kernel_fast_ratio"] <= 5,
                 f"{h['kernel_fast'] * 1e3:.3g} ms; / the multiply pass "
                 f"{h['kernel_fast_mul_ratio']:.3g}x"),
            _row(f"public sc.hat_curve on the compiled kernel (SUPERCOIL_FAST=1), {n:.0e} turns "
                 f"values {when} / the same sqrt pass", h["public_fast_ratio"], "x", "<= 10x",
                 h["public_fast_ratio"] <= 10,
                 f"{h['public_fast'] * 1e3:.3g} ms; / the multiply pass "
                 f"{h['public_fast_mul_ratio']:.3g}x"),
        ]
    return rows


def _dna_rows(r):
    n = r["hat_n"]
    per_point = r["hat_mem"].get(n, {}).get("result", float("nan")) / n
    rows = [row for regime, h in r["hat"].items() for row in _hat_rows(h, n, per_point, regime)]
    rows += [_memory_row("sc.hat_curve", m, mem, "<= 1.5x (at 1e7)")
             for m, mem in r["hat_mem"].items()]
    m = r["hat_mem"] and next(iter(r["hat_mem"]))
    rows += [_memory_row(f"sc.hat_curve(model={model!r})", m, mem,
                         "<= 1.5x (at 1e7, for the default model)")
             for model, mem in r.get("hat_mem_models", {}).items()]
    eq, em = r["eq"], r["eq_mem"]
    rows += [
        _row(f"public sc.plectoneme_equilibrium, {eq['n']} forces: CPU per force",
             eq["public_per_force"] * 1e6, "us", "<= 2 us", eq["public_per_force"] <= 2e-6,
             f"kernel supercoil.core.dna.plectoneme.equilibrium "
             f"{eq['kernel_per_force'] * 1e6:.3g} us"),
        _row(f"public sc.plectoneme_equilibrium, {em['n']:.0e} forces: peak traced memory "
             "beyond its output, per force", em["beyond_output_per_force"], "B", "<= 64 B",
             em["beyond_output_per_force"] <= 64,
             f"output {em['output'] / em['n']:.3g} B per force, peak "
             f"{em['peak'] / em['n']:.3g} B per force"),
    ]
    ld = r["loader"]
    rows += [
        _row(f"public sc.read_tweezers_csv, {ld['n']:.0e} rows: CPU / pandas.read_csv(path, "
             "comment='#', skipinitialspace=True)", ld["ratio"], "x", "<= 2x",
             ld["ratio"] <= 2, f"{ld['loader'] * 1e3:.3g} ms vs {ld['pandas'] * 1e3:.3g} ms"),
        _row(f"public sc.read_tweezers_csv, {ld['n']:.0e} rows: peak traced memory beyond "
             "its output, per row", ld["beyond_output_per_row"], "B", "<= 64 B",
             ld["beyond_output_per_row"] <= 64,
             f"output {ld['output'] / ld['n']:.3g} B per row (4 columns)"),
    ]
    return rows


def _fit_rows(r):
    f, m = r["fit"], r["many"]
    n2, n1 = max(m["replayed"]), min(m["replayed"])
    rows = [
        _row("public sc.fit_hat_curves, 3 forces x 110 points (examples/fit_tweezers_data.py)"
             f": CPU per fit{', BLAS on 1 thread' if f['blas_limited'] else ''}",
             f["fit"] * 1e3, "ms", "about 10-15 ms", f["fit"] <= 15e-3,
             f"{f['kernel_calls']} kernel calls (nfev {f['nfev']:.0f}); with the default "
             f"BLAS threads {f['fit_default_threads'] * 1e3:.3g} ms CPU"),
        _row("public sc.fit_hat_curves: CPU per fit / (kernel calls x CPU of "
             "supercoil.core.dna.li_zhao.hat_curve_points on the fit's arguments), both on the "
             "same BLAS threads", f["ratio"],
             "x", "<= 2x", f["ratio"] <= 2,
             f"{f['call_sizes']}; lower bound {f['lower_bound'] * 1e3:.3g} ms"),
    ]
    if "ratio_in_fit" in f:
        rows += [
            _row("public sc.fit_hat_curves: CPU per fit / CPU of its kernel calls as the fit "
                 "pays them (with their equilibrium solves)", f["ratio_in_fit"], "x",
                 "<= 2x", f["ratio_in_fit"] <= 2,
                 f"kernel in the fit {f['kernel_in_fit'] * 1e3:.3g} ms; the bound above re-times"
                 " the calls with the fit's equilibria already cached"),
            _row("public sc.fit_hat_curves, a new molecule (kernel caches cleared): CPU per fit "
                 "/ its kernel calls", f["ratio_in_fit_cold"], "x", "<= 2x",
                 f["ratio_in_fit_cold"] <= 2,
                 f"fit {f['fit_cold'] * 1e3:.3g} ms, kernel {f['kernel_in_fit_cold'] * 1e3:.3g}"
                 " ms"),
        ]
    rows += [
        _row(f"public sc.fit_many, {n2} molecules: parent CPU per molecule, replaying "
             "executor (submit returns a finished future with one recorded result)",
             m[f"replay_parent_cpu_{n2}"] * 1e3, "ms", "<= 2 ms",
             m[f"replay_parent_cpu_{n2}"] <= 2e-3,
             f"{n1} molecules: {m[f'replay_parent_cpu_{n1}'] * 1e3:.3g} ms"),
        _row(f"public sc.fit_many, {m['read_back']} molecules read by sc.read_tweezers_csv: "
             "parent CPU per molecule, replaying executor", m["replay_read_back_cpu"] * 1e3,
             "ms", "<= 2 ms", m["replay_read_back_cpu"] <= 2e-3,
             "the same molecules as simulated tables cost "
             f"{m[f'replay_parent_cpu_{n1}'] * 1e3:.3g} ms" if m["read_back"] == n1 else ""),
        _row(f"public sc.fit_many, {m['pooled']} molecules on ProcessPoolExecutor(2): parent "
             "CPU per molecule while the workers fit", m["pool_parent_cpu"] * 1e3, "ms",
             "<= 2 ms", m["pool_parent_cpu"] <= 2e-3,
             f"every fit succeeded: {m['all_ok']}"),
        _row(f"public sc.fit_many, {m['pooled']} molecules: wall time serial / "
             "ProcessPoolExecutor(2)", m["speedup"], "x", ">= 1.8x", m["speedup"] >= 1.8,
             f"wall: serial {m['serial_wall']:.3g} s, pool {m['pool_wall']:.3g} s (medians of "
             f"{len(m['speedups'])} interleaved runs, the pool's start-up included); serial CPU "
             f"{m['serial_cpu'] * 1e3:.3g} ms per molecule; the workers got "
             f"{m['pool_workers_cpu'] / m['pool_wall']:.2g} cores (their CPU / pool wall); "
             f"load average {r['load_start']:.1f} on {os.cpu_count()} cores"),
    ]
    return rows


def _span(p, key):
    """``"a-b"`` of a paired ratio's smallest and largest pair (its value alone if absent)."""
    lo, hi = p.get(f"{key}_range", (p[key], p[key]))
    return f"{lo:.3g}-{hi:.3g}"


def _physical_rows(r):
    """fit_many with the physical model (pool against serial) and the fits' CPU ratios."""
    p = r["physical"]
    rows = [
        _row(f"public sc.fit_many, {p['molecules']} molecules, model free-energy / hard-core, "
             f"ProcessPoolExecutor({p['workers']}): CPU per molecule, pool (workers and "
             "parent) / serial", p["cpu_ratio"], "x", "<= 1.11x (per-core throughput "
             "within 10 %)", p["cpu_ratio"] <= 1.0 / 0.9,
             f"serial {p['serial_cpu'] * 1e3:.3g} ms, pool {p['pool_cpu'] * 1e3:.3g} ms per "
             f"molecule (medians of {p.get('repeats', 1)} alternated runs; the ratio the "
             f"median of the pairs', which spread over {_span(p, 'cpu_ratio')}); chunks of "
             "molecules per submit (sc.fit_many)"),
        _row(f"public sc.fit_many, {p['molecules']} molecules, model free-energy / hard-core: "
             f"molecules per second per core, ProcessPoolExecutor({p['workers']}) (wall / "
             f"{p['workers']} cores) / serial (wall)", p["per_core_ratio"], "x", ">= 0.9x",
             p["per_core_ratio"] >= 0.9,
             f"wall: serial {p['serial_wall']:.3g} s ({p['serial_rate']:.3g} molecules/s), "
             f"pool {p['pool_wall']:.3g} s ({p['pool_rate_per_core']:.3g} molecules/s per "
             f"core); the ratio the median of {p.get('repeats', 1)} pairs' (each pool run "
             f"against the serial run before it), which spread over "
             f"{_span(p, 'per_core_ratio')}; the workers got {p['pool_cores']:.2g} cores "
             "(their CPU / pool wall): below 2 the machine's load, not the pool, sets this "
             "ratio"),
    ]
    m, ref = r["fit_models"], {}
    for i, meas in enumerate(m["measurement"]):
        if meas not in ref:  # the first construction of a problem is its reference
            ref[meas] = m["model"][i]
            continue
        ratio, j = m["ratio_to_li_zhao"][i], m["measurement"].index(meas)
        rows.append(_row(f"public sc.{meas}, {m['model'][i]} / {ref[meas]}: CPU per cold fit",
                         ratio, "x", "<= 3x", ratio <= 3,
                         f"{m['time'][i] * 1e3:.3g} ms per fit; residual RMS "
                         f"{m['residual_rms'][i]:.3g} nm, {ref[meas]} {m['residual_rms'][j]:.3g}"
                         " nm"))
    return rows


def _process_rows(r):
    im, c = r["import"], r["cli"]
    return [
        _row("import supercoil in a fresh interpreter: wall time of the import statement",
             im["import"], "s", "<= 0.4 s", im["import"] <= 0.4,
             "median of fresh processes" + (f"; CPU {im['import_cpu']:.2g} s; interpreter "
                                            f"start-up {im['startup']:.2g} s"
                                            if np.isfinite(im["startup"]) else
                                            " (quick: import supercoil.cli of the CLI run)")),
        _row("supercoil hat --params dna --out DIR (python -m supercoil.cli): wall time of the "
             "subprocess", c["wall"], "s", "<= 1.5 s", c["wall"] <= 1.5,
             f"CPU {c['cpu']:.2f} s; split (wall): import {c['import']:.2f} s, compute "
             f"{c['compute']:.2f} s, plot "
             f"{c['plot']:.2f} s, table {c['rest']:.2f} s, start-up and exit "
             f"{c['startup']:.2f} s"),
    ]


def _model_rows(r):
    rows = []
    m = r["models"]
    for i, (meas, model) in enumerate(zip(m["measurement"], m["model"], strict=True)):
        if model == MODELS[0]:
            continue
        ratio = m["ratio_to_li_zhao"][i]
        per = "CPU per force" if "per-force" in meas else "CPU per point"
        when = REGIMES[m["regime"][i]] if "regime" in m else ""
        path = ("" if meas.startswith("public") else
                " through model.buckling / model.points")
        rows.append(_row(f"model {model} / li-zhao{path}: {per}, {meas}, "
                         f"{m['points'][i]} values"
                         + (f" [{when}]" if when else ""), ratio, "x", "<= 3x",
                         ratio <= 3, f"{m['rate'][i]:.3g} per s"))
    return rows


def target_rows(r):
    """One row per target (list of dicts) from the results of :func:`measure`."""
    return _dna_rows(r) + _fit_rows(r) + _physical_rows(r) + _process_rows(r) + _model_rows(r)


def markdown(head, machine, load=None):
    """The headline table as markdown, with the machine (and the load average).

    Four columns (measurement, value, target, met); the note follows the
    measurement in parentheses. ``supercoil docs figures`` copies this text into
    ``docs/generated/headline.md`` and the README's ``headline`` block.
    """
    def cell(text):  # a "|" (as in |N| <= 25) would end the cell
        return str(text).replace("|", "\\|")

    lines = ["| measurement | value | target | met |", "|---|---|---|---|"]
    for _, row in head.iterrows():
        note = f" ({cell(row['note'])})" if row["note"] else ""
        lines.append(f"| {cell(row['measurement'])}{note} | {row['value']:.3g} {row['unit']} | "
                     f"{cell(row['target'])} | {'yes' if row['met'] else 'no'} |")
    lines.append("")
    where = f"Measured on: {machine}"
    if load is not None:
        where += f"; load average {load[0]:.1f} at the start, {load[1]:.1f} at the end"
    lines.append(where + ".")
    return "\n".join(lines) + "\n"
