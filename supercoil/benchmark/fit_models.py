"""CPU of a fit with the physical models against the paper's model, on the same data.

:func:`fit_model_cost` times public :func:`supercoil.fit_hat_curves` calls in
interleaved samples (:func:`supercoil.benchmark.cpu.interleaved_cpu`, CPU time, the
kernels' memo tables cleared before every fit: what a new molecule costs), on two
synthetic problems of the ``dna_150mM_nacl`` set (the screened interaction needs a
salt):

* ``3 forces x 110 points``: 0.5 / 1 / 2 pN, extension only, C_t = 95 nm true (86 nm
  start), simulated by ``li-zhao``: ``free-energy`` + ``screened`` against ``li-zhao`` +
  ``hard-core``;
* ``6 forces x 167 points``: 0.25-2 pN, extension and torque (5 nm, 1 pN nm noise),
  simulated by ``free-energy`` + ``screened`` (the stand-in for real curves, which are
  screened): ``free-energy`` + ``screened`` against its hard-core counterpart
  ``free-energy`` + ``hard-core``;
* ``6 forces x 167 points, extension and torque, A and C varied``: as the second
  problem with the bending persistence free too, as a fit of real curves has it: the
  screened branch table depends on B, so each new B builds one, where the C-free table
  of the second problem is built once per fit (the interaction's tables are cleared
  before each of these fits, :func:`supercoil.dna.interactions.screened.clear_tables`:
  else each sample would replay the first fit's B values from the cache);
* ``3 forces x 110 points, each on data it made``: as the first problem, but each
  construction fits curves simulated by itself. On the first problem's curves the
  screened model misfits (at 150 mM its plectoneme is wider than the hard-core one at
  the set's r0: residual RMS ~460 nm against the 5 nm noise), and the solver spends about
  three times the evaluations of the matched fit; this problem prices a fit whose model
  describes the data, the case of a user who chose the model for the data.

Rows as :func:`supercoil.benchmark.dna_models.model_cost` (``ratio_to_li_zhao`` here:
CPU over the first construction of the problem), with each fit's ``residual_rms`` (nm).
"""

from __future__ import annotations

import warnings

import numpy as np

from .cpu import interleaved_cpu
from .dna_models import UNITS as _MODEL_UNITS

__all__ = ["PROBLEMS", "UNITS", "fit_model_cost"]

#: the rows' units: those of the model-cost rows and the fits' residual RMS
UNITS = {**_MODEL_UNITS, "residual_rms": "nm"}

#: name -> (forces pN, points per force, with torque, simulating (model, interaction) or
#: None (each construction fits data simulated by itself), the two fitted constructions,
#: the reference first, the parameters varied)
PROBLEMS = {
    "3 forces x 110 points": ((0.5, 1.0, 2.0), 110, False, ("li-zhao", "hard-core"),
                              (("li-zhao", "hard-core"), ("free-energy", "screened")),
                              ("twist_persistence",)),
    "6 forces x 167 points, extension and torque": (
        (0.25, 0.5, 0.75, 1.0, 1.5, 2.0), 167, True, ("free-energy", "screened"),
        (("free-energy", "hard-core"), ("free-energy", "screened")), ("twist_persistence",)),
    "6 forces x 167 points, extension and torque, A and C varied": (
        (0.25, 0.5, 0.75, 1.0, 1.5, 2.0), 167, True, ("free-energy", "screened"),
        (("free-energy", "hard-core"), ("free-energy", "screened")),
        ("bending_persistence", "twist_persistence")),
    "3 forces x 110 points, each on data it made": (
        (0.5, 1.0, 2.0), 110, False, None,
        (("li-zhao", "hard-core"), ("free-energy", "screened")), ("twist_persistence",)),
}


def _data(dna, forces, points, torque, truth):
    import supercoil as sc

    u = sc.ureg
    extra = {"torque_noise": 1.0 * u.pN * u.nm} if torque else {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return sc.simulate_rotation_curves(dna.replace(twist_persistence=95 * u.nm),
                                           np.array(forces) * u.pN, points_per_force=points,
                                           noise=5 * u.nm, seed=3, model=truth[0],
                                           interaction=truth[1], **extra)


def fit_model_cost(dna=None, samples=3, problems=None):
    """CPU per cold fit of each construction of each problem (dict of lists, :data:`UNITS`).

    ``problems``: names of :data:`PROBLEMS` (default all).
    """
    import supercoil as sc
    from supercoil.benchmark.targets_fit import clear_kernel_caches
    from supercoil.dna.interactions import screened

    dna = dna or sc.load_parameters("dna_150mM_nacl")
    rows = {k: [] for k in UNITS}
    for name in problems or PROBLEMS:
        forces, points, torque, truth, fitted, vary = PROBLEMS[name]
        made = {}  # simulated once per truth: both constructions fit the same curves
        for c in fitted:
            if (truth or c) not in made:
                made[truth or c] = _data(dna, forces, points, torque, truth or c)
        data = {c: made[truth or c] for c in fitted}
        last = {}

        def fit(c, data=data, last=last, vary=vary):
            clear_kernel_caches()
            if "bending_persistence" in vary:  # each B's branch anew (else the samples
                screened.clear_tables()  # replay the first fit's B values from the cache)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                last[c] = sc.fit_hat_curves(data[c], dna, vary=list(vary), model=c[0],
                                            interaction=c[1])

        t = interleaved_cpu({c: lambda c=c: fit(c) for c in fitted}, samples=samples,
                            min_sample=0.0)
        for c in fitted:
            n = len(data[c])
            for key, v in (("measurement", f"fit_hat_curves, {name} (dna_150mM_nacl)"),
                           ("model", "/".join(c)), ("points", n), ("time", t[c]),
                           ("per_item", t[c] / n), ("rate", n / t[c]),
                           ("ratio_to_li_zhao", t[c] / t[fitted[0]]),
                           ("residual_rms", last[c].residual_rms.m_as("nm"))):
                rows[key].append(v)
    return rows
