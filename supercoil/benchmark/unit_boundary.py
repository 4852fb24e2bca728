"""Cost of the unit boundary: a public call against the float kernel it wraps.

For each wrapped function and each input size (1, 1e2, 1e4, 1e6 elements) the
public call (quantities in, quantity out) and the float kernel (SI floats in,
floats out) are timed with :func:`~supercoil.benchmark.timing.best_time`; the
overhead is the difference. Inputs are given once in display units (nm, pN), where
the O(n) conversion multiply is part of what is measured, and once in SI
units, where the boundary only compares unit containers and wraps arrays
without copying.
"""

from __future__ import annotations

import numpy as np

from supercoil import display
from supercoil.benchmark.timing import paired_best_times

SIZES = (1, 100, 10_000, 1_000_000)


def _cases():
    """(name, public(n) -> callable, kernel(n) -> callable) for each wrapped function."""
    import supercoil as sc
    from supercoil.core import geometry as g

    u = sc.ureg

    def geom_public(n, si=False):
        a = np.linspace(0.1, 0.7, n) * u.rad
        R = np.full(n, 2e-9) * u.m if si else np.full(n, 2.0) * u.nm
        return lambda: sc.geometry.torsion(a, R)

    def geom_kernel(n):
        a = np.linspace(0.1, 0.7, n)
        R = np.full(n, 2e-9)
        return lambda: g.torsion(a, R)

    cases = [("geometry.torsion", geom_public, geom_kernel)]
    try:  # DNA plectoneme equilibrium
        from supercoil.core.dna import plectoneme as pk

        dna = sc.load_parameters("dna")
        d = dna.si

        def eq_public(n, si=False):
            f = np.linspace(0.3e-12, 5e-12, n) * u.N if si else np.linspace(0.3, 5.0, n) * u.pN
            return lambda: sc.plectoneme_equilibrium(dna, f)

        def eq_kernel(n):
            f = display.from_display(np.linspace(0.3, 5.0, n), "force")
            return lambda: pk.equilibrium(
                f, d.bending_rigidity, d.torsional_rigidity, d.kT, d.radius
            )

        cases.append(("plectoneme_equilibrium", eq_public, eq_kernel))

        from supercoil.core.dna.li_zhao import hat_curve_points

        def hat_public(n, si=False):
            f = 1.2e-12 * u.N if si else 1.2 * u.pN
            turns = np.linspace(0.0, 20.0, n)  # N >= 0: no denaturation warning at 1.2 pN
            return lambda: sc.hat_curve(dna, f, turns)

        def hat_kernel(n):
            turns = np.linspace(0.0, 20.0, n)
            force = np.full(n, 1.2e-12)
            return lambda: hat_curve_points(turns, force, d.length, d.bending_rigidity,
                                            d.torsional_rigidity, d.kT, d.radius)

        cases.append(("hat_curve (table)", hat_public, hat_kernel))
    except (ImportError, AttributeError):  # pragma: no cover - a build without the DNA layer
        pass
    return cases


def run(sizes=SIZES):
    """Measure the boundary overhead; returns a convention table.

    Public call and kernel are timed in interleaved samples
    (:func:`~supercoil.benchmark.timing.paired_best_times`); at 1e6 elements
    fewer samples are taken (a plectoneme solve of 1e6 forces is the slowest sample).
    """
    from supercoil.tables import make_table, provenance

    keys = ("function", "input_units", "elements", "public_time", "kernel_time", "overhead")
    rows = {k: [] for k in keys}
    for name, public, kernel in _cases():
        for n in sizes:
            repeat = 3 if n >= 1_000_000 else 7
            kern = kernel(n)
            for si in (False, True):
                tp, tk = paired_best_times(public(n, si), kern, repeat=repeat)
                rows["function"].append(name)
                rows["input_units"].append("SI" if si else "display")
                rows["elements"].append(n)
                rows["public_time"].append(tp * 1e6)
                rows["kernel_time"].append(tk * 1e6)
                rows["overhead"].append((tp - tk) * 1e6)
    units = {"function": "", "input_units": "", "elements": "", "public_time": "us",
             "kernel_time": "us", "overhead": "us"}
    return make_table(rows, units, provenance(None, benchmark="unit boundary"))


def plot(table, ax):
    """Public and kernel time per call against the number of elements."""
    for name, sub in table.groupby("function", sort=False):
        disp = sub[sub["input_units"] == "display"]
        si = sub[sub["input_units"] == "SI"]
        (line,) = ax.loglog(disp["elements"], disp["public_time"], "o-",
                            label=f"{name} (public, nm/pN inputs)")
        ax.loglog(si["elements"], si["public_time"], "^:", color=line.get_color(),
                  label=f"{name} (public, SI inputs)")
        ax.loglog(disp["elements"], disp["kernel_time"], "s--", color=line.get_color(),
                  label=f"{name} (float kernel)")
    ax.set(xlabel="elements per call", ylabel="time per call (us)",
           title="unit boundary: public call vs float kernel")
    ax.legend(fontsize=7)
