"""The screened electrostatic interaction of the two strands of a DNA plectoneme.

``interaction="screened"``: Debye-Hueckel repulsion of the two helical strands, each a
line of Stigter's effective charge, plus (by default) the paper's entropic confinement
term, with a hard-core radius below which the strands cannot come. Derivations and the
literature comparison: docs/theory/screened-interaction.md. Float kernels:
:mod:`supercoil.core.dna.electrostatics`, :mod:`supercoil.core.dna.screened`,
:mod:`supercoil.core.dna.equilibrium`.

Per unit DNA length (docs/theory/screened-interaction.md, sections 3 and 4)::

    w = w_el + c_conf w_conf,
    w_el   = (nu^2 kT l_B / (2 cos alpha)) int exp(-d/lambda_D)/d dz,
    w_conf = kT A^(-1/3) [R^(-2/3) + (pi R cot alpha)^(-2/3)],

with ``nu`` Stigter's effective line charge of a cylinder of radius
``hard_core_radius`` carrying ``charge_fraction`` times the bare B-DNA charge
(2 e / 0.34 nm), ``lambda_D`` and ``l_B`` from the DNA's salt and temperature.
"""

from __future__ import annotations

from functools import lru_cache
from typing import ClassVar

import numpy as np

from supercoil import display as _d
from supercoil._checks import check_scale
from supercoil.core.blocks import in_blocks
from supercoil.core.dna import contact as _ct
from supercoil.core.dna import electrostatics as _el
from supercoil.core.dna import equilibrium as _eq
from supercoil.core.dna import screened as _sc
from supercoil.core.dna.plectoneme import PlectonemeState
from supercoil.dna.interactions.base import Interaction
from supercoil.dna.model_parameters import ModelParameter
from supercoil.exceptions import ParameterError, ValidityWarning
from supercoil.units import U, quantity

__all__ = ["Screened"]

#: outer end of the tabulated branch, in hard-core radii (1 um for a = 1 nm)
_R_MAX_FACTOR = 1000.0
#: mol/m^3 (the SI salt) to mol/L, from pint
_MOLAR = _d.spec("M")[1]
#: validity of Stigter's far-field charge: the strands' surface gap 2 (R - a) must be at
#: least this many Debye lengths; below it (and in contact, gap 0) ValidityWarning
#: (docs/theory/screened-interaction.md#validity)
MIN_GAP_DEBYE_LENGTHS = 1.0


def _si(dna):
    si = getattr(dna, "si", dna)
    if getattr(si, "salt", None) is None:
        raise ParameterError(
            "the screened interaction needs the salt concentration: the DNA has "
            "salt=None; give it one, e.g. DNA(..., salt=150 * ureg.mM), or set 'salt' "
            "in the parameter file")
    return si


@lru_cache(maxsize=128)
def _screening(salt, temperature, kT, radius, fraction):
    lB = float(_el.bjerrum_length(temperature))
    lam = float(_el.debye_length(salt, temperature))
    nu = _el.effective_line_charge(salt, temperature, radius, fraction * _el.BARE_LINE_CHARGE)
    return lam, lB, nu, nu * nu * kT * lB


def partials_function(B, kT, lam, prefactor, conf, electrostatic=None):
    """``partials(alpha, R) -> (w, w_alpha, w_R)`` of the screened interaction with the
    confinement term (SI: bending rigidity ``B``, ``kT``, Debye length ``lam``).

    ``electrostatic(alpha, R)``: the B-free electrostatic partials, if not
    :func:`supercoil.core.dna.screened.electrostatic_partials` itself (a memo of them).
    """
    def partials(alpha, R):
        if electrostatic is None:
            w, w_a, w_R = _sc.electrostatic_partials(alpha, R, lam, prefactor)
        else:
            w, w_a, w_R = electrostatic(alpha, R)
        if conf:
            c, c_a, c_R = _sc.confinement_partials(alpha, R, B, kT)
            w, w_a, w_R = w + conf * c, w_a + conf * c_a, w_R + conf * c_R
        return w, w_a, w_R

    return partials


#: the grid end (``core.dna.equilibrium.grid_end_of``) of the last branch built for each
#: buffer and interaction, any B: a fit's next B solves only that much of the grid
_GRID_ENDS: dict = {}


@lru_cache(maxsize=64)
def stable_branch(B, kT, lam, prefactor, conf, radius):
    """The stable free branch (:func:`supercoil.core.dna.equilibrium.branch_table`) of the
    screened interaction from the hard core to ``1000 a`` (SI arguments; memoised). Each
    new B solves the grid only as far as the last branch of the same buffer ended
    (bit for bit the whole grid's table)."""
    partials = partials_function(B, kT, lam, prefactor, conf)
    key, r_max = (kT, lam, prefactor, conf, radius), _R_MAX_FACTOR * radius
    branch = _eq.branch_table(B, partials, radius, r_max, grid_end=_GRID_ENDS.get(key))
    if len(_GRID_ENDS) > 256:
        _GRID_ENDS.clear()
    _GRID_ENDS[key] = _eq.grid_end_of(branch, radius, r_max)  # None: the whole grid
    return branch


@lru_cache(maxsize=16)
def _contact_electrostatics(lam, prefactor, radius):
    """The electrostatic partials at R = a on the contact table's tilts
    (:data:`supercoil.core.dna.contact.TILTS`): B-free, so every B's table reuses them (the
    quadrature at its 401 tilts was 0.6 of a contact table's CPU)."""
    out = _sc.electrostatic_partials(_ct.TILTS, np.full(_ct.TILTS.shape, radius), lam,
                                     prefactor)
    for a in out:
        a.setflags(write=False)
    return out


@lru_cache(maxsize=64)
def _contact(B, kT, lam, prefactor, conf, radius):
    def electrostatic(alpha, R):
        if alpha is _ct.TILTS:  # the table's own tilts, at R = a
            return _contact_electrostatics(lam, prefactor, radius)
        return _sc.electrostatic_partials(alpha, R, lam, prefactor)

    partials = partials_function(B, kT, lam, prefactor, conf, electrostatic)
    return _ct.contact_table(B, partials, radius)


def clear_tables():
    """Forget the memoised branch and contact tables (:func:`stable_branch`), keeping each
    buffer's last grid end: what a new molecule in the same buffer finds (benchmarks)."""
    stable_branch.cache_clear()
    _contact.cache_clear()


#: tension (N) above which the gap is below the limit, per buffer and interaction
_ONSETS: dict = {}


def _onset(gap_at, limit, lo, hi):
    """The tension (N) in ``[lo, hi]`` where the gap falls below ``limit`` (bisection).

    The equilibrium radius falls as the tension rises (also across the jump to
    contact), so the gap is monotone; 3 significant digits are enough for the message.
    """
    if lo <= 0.0:
        lo = hi * 1e-3
        while lo > 1e-16 and gap_at(lo) < limit:
            lo *= 1e-3
    for _ in range(60):
        if hi - lo <= 1e-4 * hi:
            break
        mid = 0.5 * (lo + hi)
        if gap_at(mid) < limit:
            hi = mid
        else:
            lo = mid
    return hi


class Screened(Interaction):
    """Screened (Debye-Hueckel) strand repulsion with Stigter's effective charge.

    Parameters (keywords; pint quantities or SI floats)
    ----------------------------------------------------
    charge_fraction : float, default 1
        Fraction of the bare B-DNA charge put on Stigter's cylinder before the
        Poisson-Boltzmann far-field matching, in (0, 1.5]; Maffeo et al., PRL 105,
        158101 (2010) report 0.4 from fits of supercoiling in monovalent salt.
    hard_core_radius : Quantity [length], default 1.0 nm
        Geometric radius a of B-DNA: the strands cannot come closer than 2a (axis to
        axis), and a is the radius of Stigter's charged cylinder.
    confinement : float, default 1
        Coefficient of the paper's entropic confinement term: 1 as in the paper and
        Marko & Siggia (1995), 0 for none (Clauvelin, Audoly & Neukirch 2009).
    hard_contact : float, default 1
        1: where the repulsion cannot hold the strands apart they touch at R = a (hard
        contact, the counterpart of the paper's condition (HC) for the rod), and at each
        force the state of lower torque (free or in contact) is the equilibrium; 0: no
        contact states, such forces raise :class:`NoEquilibriumError`.

    Notes
    -----
    Needs the DNA's ``salt``; raises :class:`~supercoil.exceptions.ParameterError`
    naming ``salt`` if it is ``None``.
    """

    name: ClassVar[str] = "screened"
    summary: ClassVar[str] = ("Debye-Hueckel repulsion of the two helical strands with "
                              "Stigter's effective charge, entropic confinement, hard core")
    parameters: ClassVar[dict[str, ModelParameter]] = {
        "charge_fraction": ModelParameter(
            "charge_fraction", "", 1.0, 0.0, 1.5,
            "fraction of the bare charge 2e/0.34 nm on Stigter's PB cylinder",
            "Maffeo et al., Phys. Rev. Lett. 105, 158101 (2010): 0.4 from supercoiling fits"),
        "hard_core_radius": ModelParameter(
            "hard_core_radius", "nm", 1.0e-9, 0.5e-9, 1.5e-9,
            "geometric radius of B-DNA (closest axis distance 2a; PB cylinder radius)",
            "B-DNA diameter about 2 nm; Stigter, Biopolymers 16, 1435 (1977) uses a = 1 nm"),
        "confinement": ModelParameter(
            "confinement", "", 1.0, 0.0, 1.0,
            "coefficient of the entropic confinement term (1 paper, 0 none)",
            "Marko & Siggia, Phys. Rev. E 52, 2912 (1995); 0 as in Clauvelin et al., "
            "Biophys. J. 96, 3716 (2009)"),
        "hard_contact": ModelParameter(
            "hard_contact", "", 1.0, 0.0, 1.0,
            "1: strands may touch at R = a (contact states); 0: no contact states",
            "hard contact of the paper's rods, condition (HC) (Li, Zhao et al.)"),
    }

    def __init__(self, **values):
        super().__init__(**values)  # bounds checked there (ValueError naming the parameter)
        if self.values["hard_contact"] not in (0.0, 1.0):
            raise ParameterError("screened.hard_contact must be 0 or 1, got "
                                 f"{self.values['hard_contact']:g}")
        if self.values["charge_fraction"] <= 0.0:
            raise ParameterError("screened.charge_fraction must be positive (bounds (0, 1.5]), "
                                 f"got {self.values['charge_fraction']:g}")

    # ---- float level (SI) -------------------------------------------------
    def _check(self, dna):
        """ParameterError naming ``salt`` if the DNA has none; ValidityError if it is absurd.

        The Debye length must lie between ``a / 300`` and ``1000 a`` (``a`` the
        hard-core radius; about 8e3 M to 9e-8 M for a = 1 nm at 25 degC): below,
        ``exp(a / lambda_D)`` of Stigter's far-field matching leaves the float range
        (at a / lambda_D ~ 709; the branch solver already fails near 3e4 M); above,
        the repulsion is unscreened over the whole tabulated branch (R up to
        1000 a) and no confined branch exists in it (measured at 5e-8 M). A
        salt of 1e300 M would otherwise end in a ZeroDivisionError.
        """
        si = _si(dna)
        a = self.values["hard_core_radius"]
        with np.errstate(over="ignore", under="ignore", divide="ignore"):
            lam = float(_el.debye_length(si.salt, si.temperature))
        check_scale(lam / a, lambda: "the Debye length over the hard-core radius, lambda_D/a "
                    f"(salt {si.salt * _MOLAR:.6g} M, lambda_D = {_d.text(lam, 'length')}, "
                    f"a = {_d.text(a, 'length')})", lo=1.0 / 300.0, hi=_R_MAX_FACTOR,
                    why="the screened interaction is solved for a / 300 <= lambda_D <= "
                        f"{_R_MAX_FACTOR:g} a (docs/theory/screened-interaction.md)")

    def screening(self, dna):
        """``(lambda_D [m], l_B [m], nu [1/m], nu^2 kT l_B [J/m])`` for the DNA's buffer."""
        si = _si(dna)
        return _screening(si.salt, si.temperature, si.kT, self.values["hard_core_radius"],
                          self.values["charge_fraction"])

    def screening_functions(self, dna):
        """``(dna SI, Debye length (m), interaction prefactor (J/m))`` of ``dna``."""
        si = _si(dna)
        lam, _, _, pref = self.screening(si)
        return si, lam, pref

    def _partials(self, alpha, radius, dna):
        """``(w, w_alpha, w_R)`` in (J/m, J/m, J/m^2); analytic under the quadrature."""
        si, lam, pref = self.screening_functions(dna)
        f = partials_function(si.bending_rigidity, si.kT, lam, pref,
                               self.values["confinement"])
        return f(np.asarray(alpha, float), np.asarray(radius, float))

    def branch(self, dna):
        """The tabulated stable branch (:class:`supercoil.core.dna.equilibrium.Branch`)."""
        si, lam, pref = self.screening_functions(dna)
        return stable_branch(si.bending_rigidity, si.kT, lam, pref, self.values["confinement"],
                       self.values["hard_core_radius"])

    def contact_branch(self, dna):
        """The tabulated contact branch at R = a (:mod:`supercoil.core.dna.contact`) or None."""
        if not self.values["hard_contact"]:
            return None
        si, lam, pref = self.screening_functions(dna)
        return _contact(si.bending_rigidity, si.kT, lam, pref, self.values["confinement"],
                        self.values["hard_core_radius"])

    def _equilibrium(self, tension, dna):
        """Uniform plectoneme at each tension T (N): (GE1), (GE2) and the tension
        equation with this ``w`` (:mod:`supercoil.core.dna.equilibrium`).

        With ``hard_contact=1`` (default) a force may also be held by the contact state
        R = a (:mod:`supercoil.core.dna.contact`); the state of lower torque wins.

        Raises
        ------
        NoEquilibriumError
            Naming the force: not positive, below the branch (no confinement: R beyond
            1000 a), or, with ``hard_contact=0``, above the free branch's largest tension
            (the strands would be pressed onto the hard core or pass through each other).
        ParameterError
            If the DNA has no salt.
        """
        si, lam, pref = self.screening_functions(dna)
        B = si.bending_rigidity
        partials = partials_function(B, si.kT, lam, pref, self.values["confinement"])
        branch, contact = self.branch(si), self.contact_branch(si)
        force = np.asarray(tension, dtype=float)
        # blocks of 1024 forces: the solver's temporaries (~8 kB per force) stay bounded
        state = in_blocks(lambda f: self._state(f, si, partials, branch, contact), force, 1024,
                          keep="force")
        self._warn_validity(state, si, lam, partials, branch, contact)
        return state

    def _warn_validity(self, state, si, lam, partials, branch, contact):
        """ValidityWarning where the strands' surface gap is below one Debye length.

        The message names the salt, the Debye length and the tension above which the
        equilibrium's gap ``2 (R - a)`` is below :data:`MIN_GAP_DEBYE_LENGTHS` Debye
        lengths (the same text for every call on one buffer, so it is shown once).
        """
        a = self.values["hard_core_radius"]
        limit = MIN_GAP_DEBYE_LENGTHS * lam
        gap = 2.0 * (np.asarray(state.radius, float) - a)
        outside = gap < limit * (1.0 - 1e-9)
        if not np.any(outside):
            return
        key = (si.bending_rigidity, si.kT, lam, self.values["confinement"], a,
               self.values["hard_contact"], self.values["charge_fraction"])
        onset = _ONSETS.get(key)
        if onset is None:  # once per buffer and interaction: the text is the same each call
            lowest = float(np.min(np.asarray(state.force, float)[outside]))

            def gap_at(t):
                R = self._state(np.array([t]), si, partials, branch, contact).radius[0]
                return 2.0 * (R - a)

            onset = _ONSETS[key] = _onset(gap_at, limit, 0.0, lowest)
        import warnings

        warnings.warn(
            f"screened interaction outside its validity at {si.salt:g} mM: above "
            f"{_d.text(onset, 'force', '.3g')} tension the strands' surface gap 2(R - a) is "
            f"below {MIN_GAP_DEBYE_LENGTHS:g} Debye length ({_d.text(lam, 'length', '.3g')}; 0 "
            "in contact), "
            "where Stigter's far-field charge does not give the near-field repulsion: the "
            "radius, torque and slope there are qualitative (the screened-interaction "
            "theory page, 'Validity of the far-field charge')", ValidityWarning, stacklevel=3)

    @staticmethod
    def _state(force, si, partials, branch, contact):
        B, C = si.bending_rigidity, si.torsional_rigidity
        alpha, R, M, w = _eq.solve_equilibrium(force, B, partials, branch, contact,
                                               energy=True)
        s, c = np.sin(alpha), np.cos(alpha)
        kappa, tau = s * s / R, s * c / R
        omega = M / C
        return PlectonemeState(
            force=force, alpha=alpha, radius=R, pitch=2.0 * np.pi * R / np.tan(alpha),
            omega=omega, torque=M, curvature=kappa, torsion=tau,
            bending_energy=0.5 * B * kappa * kappa, twist_energy=0.5 * C * omega * omega,
            interaction_energy=w)

    # ---- unit level -------------------------------------------------------
    def lengths(self, dna):
        """Debye length, Bjerrum length (nm) and effective line charge (1/nm) as quantities."""
        lam, lB, nu, _ = self.screening(dna)
        return {"debye_length": _d.quantity(lam, "length"),
                "bjerrum_length": _d.quantity(lB, "length"),
                "effective_line_charge": quantity(nu, U.m**-1).to(U.per_nm)}
