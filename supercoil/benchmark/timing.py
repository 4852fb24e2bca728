"""Wall-clock timing by the rules of the SciML DiffEqDevTools benchmarks.

One discarded warm-up call, then the minimum over ``repeat`` samples, each
sample timing ``number`` calls (chosen so that a sample lasts at least
``min_sample`` seconds). Errors are computed by the caller outside the timed
code. A call that raises is a failure: :func:`best_time` returns NaN and the
charts leave the point out.
"""

from __future__ import annotations

import platform
import time

import numpy as np


def _calls_per_sample(func, min_sample, max_number):
    number = 1
    while True:
        t0 = time.perf_counter()
        for _ in range(number):
            func()
        dt = time.perf_counter() - t0
        if dt >= min_sample or number >= max_number:
            return number, dt / number
        number = min(max_number, max(number * 2, int(number * min_sample / max(dt, 1e-9))))


def _sample(func, number):
    t0 = time.perf_counter()
    for _ in range(number):
        func()
    return (time.perf_counter() - t0) / number


def best_time(func, repeat: int = 5, min_sample: float = 2e-3, max_number: int = 10**6):
    """Minimum wall time per call of ``func()`` in seconds (NaN if it raises).

    Parameters
    ----------
    func : callable
        Called with no arguments.
    repeat : int
        Number of samples; the minimum is reported.
    min_sample : float
        Each sample repeats ``func`` until it lasts at least this long (s).
    """
    try:
        func()  # warm-up, discarded
    except Exception:
        return float("nan")
    number, first = _calls_per_sample(func, min_sample, max_number)
    samples = [first] + [_sample(func, number) for _ in range(repeat - 1)]
    return float(np.min(samples))


def paired_best_times(func_a, func_b, repeat: int = 7, min_sample: float = 2e-3,
                      max_number: int = 10**6, warm: bool = True):
    """Minimum times of two calls measured in interleaved samples (a, b, a, b, ...).

    Interleaving exposes both to the same machine state, so the difference of
    the two minima (e.g. a public call minus the float kernel it wraps) is not
    dominated by drift between two separate runs. ``warm=False`` skips the
    discarded warm-up calls (for calls of seconds, which a first call does not slow).
    """
    if warm:
        func_a()  # warm-ups, discarded
        func_b()
    na, ta = _calls_per_sample(func_a, min_sample, max_number)
    nb, tb = _calls_per_sample(func_b, min_sample, max_number)
    a, b = [ta], [tb]
    for _ in range(repeat - 1):
        a.append(_sample(func_a, na))
        b.append(_sample(func_b, nb))
    return float(np.min(a)), float(np.min(b))


def machine_description() -> str:
    """One line naming the machine the numbers were measured on."""
    import os

    import numpy
    import scipy

    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return (
        f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"numpy {numpy.__version__}, scipy {scipy.__version__}"
    )
