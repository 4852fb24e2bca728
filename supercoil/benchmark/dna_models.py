"""Cost of the DNA models side by side: each registered model against li-zhao.

:func:`model_cost` measures, for each model, through the model interface at
the float level (``model.buckling`` and ``model.points``, hard-core
interaction, no units):

* ``per force``: the per-force constants (plectoneme equilibrium, and for
  free-energy the coexistence at the tail's effective pull, three equilibrium
  calls), vectorised over ``n_forces`` forces 0.3-10 pN, time per force;
* ``hat points``: hat-curve points per second at 1.2 pN for ``sizes`` turns
  values, on two ranges: up to full coiling of the free-energy model
  (stretched and plectoneme phases, where tweezers data lie) and the range
  +-25 turns of :func:`supercoil.benchmark.dna.hat_cost` (7 % of it fully
  coiled for free-energy, where each point needs the plectoneme state of its
  linking: the expensive part); and ``coiled = (turns, points)``, default +-40 turns
  at 2e5 points (42 % fully coiled).

Rows are a dict of lists (``measurement``, ``model``, ``points``, ``time``,
``per_item``, ``rate``, ``ratio_to_li_zhao``) for
:func:`supercoil.tables.make_table` with :data:`UNITS`. Wiring into
``supercoil bench`` (suite.run)::

    rows = dna_models.model_cost(n_forces=100 if quick else 1000,
                                 sizes=(1_000,) if quick else (1_000, 100_000))
    write_csv(make_table(rows, dna_models.UNITS, provenance(...)), out / "dna_model_cost.csv")
"""

from __future__ import annotations

import numpy as np

from supercoil import display

from .cpu import interleaved_cpu

MODELS = ("li-zhao", "free-energy")
#: units of the :func:`model_cost` columns, for ``make_table(rows, UNITS, ...)``
UNITS = {"measurement": "", "model": "", "points": "", "time": "s", "per_item": "s",
         "rate": "1/s", "ratio_to_li_zhao": ""}
#: the units of :func:`supercoil.benchmark.process.model_cost_regimes`' rows (its
#: ``regime`` column: the allocator's)
REGIME_UNITS = {**UNITS, "regime": ""}


def _calls(d, names):
    """Per-force and per-point calls of each model through the model interface."""
    from supercoil.dna.interactions import get_interaction
    from supercoil.dna.models import get_model

    inter = get_interaction("hard-core")
    per_force, points = {}, {}
    for name in names:
        m = get_model(name)
        per_force[name] = lambda F, m=m: m.buckling(F, d, True, inter)
        points[name] = lambda N, F, m=m: m.points(N, F, d, True, inter, None)
    return per_force, points


def model_cost(dna=None, n_forces=1000, sizes=(1_000, 100_000), force=1.2e-12, repeat=3,
               models=MODELS, coiled=(40.0, 200_000)):
    """CPU time per force and points per second of each model (dict of lists).

    ``models[0]`` is the reference of ``ratio_to_li_zhao`` (time over its time
    for the same measurement). The models of one measurement are timed in
    interleaved samples (CPU time, median of ``repeat`` samples,
    :func:`supercoil.benchmark.cpu.interleaved_cpu`), so their ratio is measured
    under the same machine load.
    """
    import supercoil as sc
    from supercoil.core.dna import free_energy as fe
    from supercoil.dna.interactions import get_interaction

    material = dna or sc.load_parameters("dna")
    d = material.si
    per_force, points = _calls(d, models)
    rows = {k: [] for k in ("measurement", "model", "points", "time", "per_item", "rate",
                            "ratio_to_li_zhao")}

    def add(measurement, model, n, t):
        rows["measurement"].append(measurement)
        rows["model"].append(model)
        rows["points"].append(n)
        rows["time"].append(t)
        rows["per_item"].append(t / n)
        rows["rate"].append(n / t)
        # the reference model's row of the same measurement, models.index(model) rows back
        base = rows["time"][-1 - models.index(model)]
        rows["ratio_to_li_zhao"].append(t / base)

    forces = np.geomspace(0.3e-12, 10e-12, n_forces)
    t = interleaved_cpu({m: lambda m=m: per_force[m](forces) for m in models}, samples=repeat)
    for model in models:
        add(f"per-force constants, {n_forces} forces 0.3-10 pN", model, n_forces, t[model])
    inter = get_interaction("hard-core")
    co = fe.coexistence(np.array([force]), d.length, d.bending_rigidity, d.torsional_rigidity,
                        d.kT, lambda T: inter.equilibrium(T, d))
    n_full = float(co.buckling_turns[0] + d.length * co.linking_rate[0] / (2 * np.pi))
    ranges = [(f"hat points to full coiling (|N| <= {n_full:.1f})", n_full, sizes),
              ("hat points, |N| <= 25", 25.0, sizes)]
    if coiled:  # far past full coiling: 40 % of the points fully coiled at 40 turns
        ranges.append((f"hat points past full coiling, |N| <= {coiled[0]:g}", coiled[0],
                       (coiled[1],)))
    for label, top, counts in ranges:
        for n in counts:
            N = np.linspace(-top, top, n)
            F = np.full(n, force)
            t = interleaved_cpu({m: lambda m=m, N=N, F=F: points[m](N, F) for m in models},
                                samples=repeat)
            for model in models:
                add(f"{label} at {display.text(force, 'force', 'g')}", model, n, t[model])
    if coiled:  # the same points as a user gets them: units, table and shared checks
        N = np.linspace(-coiled[0], coiled[0], coiled[1])
        t = interleaved_cpu({m: lambda m=m: _public(material, force, N, m) for m in models},
                            samples=repeat)
        for model in models:
            add(f"{PUBLIC} past full coiling, |N| <= {coiled[0]:g} at "
                f"{display.text(force, 'force', 'g')}", model, N.size, t[model])
    return rows


#: the label of :func:`model_cost`'s rows through the public ``sc.hat_curve``
PUBLIC = "public sc.hat_curve (units, table, shared checks), hat points"


def _public(material, force, turns, model):
    """``sc.hat_curve`` of ``material`` at ``force`` (N), its warnings dropped."""
    import warnings

    import supercoil as sc

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.SupercoilWarning)
        return sc.hat_curve(material, force * sc.ureg.N, turns, model=model)


def screened_equilibrium_cost(dna=None, n_forces=1000, repeat=3):
    """CPU time per force of the screened equilibrium: Newton (default) against the direct
    nested solve it replaced (``method="direct"``, the reference), forces 0.05-5 pN.

    Rows as :func:`model_cost` (``ratio_to_li_zhao`` here: time over the direct solve's).
    """
    import supercoil as sc
    from supercoil.core.dna import equilibrium as eq
    from supercoil.dna.interactions import Screened
    from supercoil.dna.interactions import screened as scm

    d = (dna or sc.load_parameters("dna_150mM_nacl")).si
    inter = Screened()
    _, lam, pref = inter.screening_functions(d)
    B = d.bending_rigidity
    f = scm.partials_function(B, d.kT, lam, pref, inter.values["confinement"])
    branch, contact = inter.branch(d), inter.contact_branch(d)
    forces = np.geomspace(0.05e-12, 5e-12, n_forces)
    methods = ("direct", "newton")
    t = interleaved_cpu({m: lambda m=m: eq.solve_equilibrium(forces, B, f, branch, contact,
                                                             method=m) for m in methods},
                        samples=repeat)
    rows = {k: [] for k in UNITS}
    for m in methods:
        for key, v in (("measurement", f"screened equilibrium, {n_forces} forces 0.05-5 pN"),
                       ("model", m), ("points", n_forces), ("time", t[m]),
                       ("per_item", t[m] / n_forces), ("rate", n_forces / t[m]),
                       ("ratio_to_li_zhao", t[m] / t["direct"])):
            rows[key].append(v)
    return rows
