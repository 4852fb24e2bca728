"""CPU-time and peak-memory measurement for the headline targets.

* :func:`interleaved_cpu`: median CPU time (``time.process_time``) per call of
  several callables, sampled in interleaved rounds (a, b, c, a, b, c, ...), so
  that a ratio between them is measured under the same machine state;
* :func:`cpu_once`: CPU and wall time of one call (for long calls);
* :func:`peak_memory`: the peak bytes :mod:`tracemalloc` sees during one call
  (numpy reports its buffers to it), and the bytes the result still holds
  after the call (what the caller receives), both above the traced baseline.

CPU time of the process counts every thread of it (BLAS threads included) and
none of the other processes loading the machine, which is why it is preferred
to wall time here; a median of interleaved samples absorbs the remaining noise.
"""

from __future__ import annotations

import gc
import time
import tracemalloc

import numpy as np

__all__ = ["cpu_once", "interleaved_cpu", "page_faults", "peak_memory"]


def _calls_per_sample(func, min_sample):
    """Calls per sample so that one sample lasts at least ``min_sample`` CPU seconds."""
    number = 1
    while True:
        t0 = time.process_time()
        for _ in range(number):
            func()
        dt = time.process_time() - t0
        if dt >= min_sample or number >= 10**5:
            return number
        number = min(10**5, max(2 * number, int(1.2 * number * min_sample / max(dt, 1e-6))))


def page_faults(func, repeat=5):
    """Median minor page faults of one call of ``func`` (``getrusage``), its result dropped.

    What fresh memory costs: the first touch of new pages faults, and the kernel
    maps and zeroes them (each fault maps 128 kB, so writing fresh memory can cost a
    multiple of rewriting mapped memory; the bench output has the measured ratio);
    memory the allocator
    reuses from an earlier call faults no more. None where
    :mod:`resource` is missing (Windows).
    """
    try:
        import resource
    except ImportError:
        return None
    counts = []
    for _ in range(repeat):
        r0 = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
        func()
        counts.append(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - r0)
    return float(np.median(counts))


def interleaved_cpu(funcs, samples=15, min_sample=0.02):
    """Median CPU seconds per call of each callable, in interleaved samples.

    Parameters
    ----------
    funcs : dict of str to callable
        Called with no arguments; each is called once first (warm-up, discarded).
    samples : int
        Rounds of samples; each round takes one sample of every callable in turn.
    min_sample : float
        CPU seconds a sample lasts at least (several calls per sample for fast
        calls: the resolution of ``time.process_time`` depends on the OS).

    Returns
    -------
    dict of str to float
        Median CPU seconds per call.
    """
    for f in funcs.values():
        f()
    numbers = {k: _calls_per_sample(f, min_sample) for k, f in funcs.items()}
    times = {k: [] for k in funcs}
    for _ in range(samples):
        for k, f in funcs.items():
            n = numbers[k]
            t0 = time.process_time()
            for _ in range(n):
                f()
            times[k].append((time.process_time() - t0) / n)
    return {k: float(np.median(v)) for k, v in times.items()}


def cpu_once(func):
    """``(result, cpu_seconds, wall_seconds)`` of one call of ``func()``."""
    c0, w0 = time.process_time(), time.perf_counter()
    result = func()
    return result, time.process_time() - c0, time.perf_counter() - w0


def peak_memory(func):
    """Peak and retained traced bytes of one call of ``func()``, above the baseline.

    The inputs must be allocated before the call (they are part of the
    baseline). ``retained`` is what is still allocated once the call returned
    while its result is alive: the output itself.

    Returns
    -------
    dict
        ``peak`` (bytes), ``retained`` (bytes) and ``result`` (the return value,
        dropped by the caller).
    """
    gc.collect()
    started = tracemalloc.is_tracing()
    if not started:
        tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        base, _ = tracemalloc.get_traced_memory()
        result = func()
        current, peak = tracemalloc.get_traced_memory()
    finally:
        if not started:
            tracemalloc.stop()
    return {"peak": peak - base, "retained": current - base, "result": result}
