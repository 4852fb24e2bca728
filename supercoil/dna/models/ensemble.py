"""``model="ensemble"``: the phase-ensemble model of real DNA rotation curves.

A cooperatively melting worm-like-chain tail (exact Bouchiat force-extension,
resummed Moroz-Nelson twist stiffness with a twist-bend softening factor), up to two
plectoneme domains whose twist stiffness grows with torque, each with an end loop,
summed over the domains' number, length and position at fixed turns; extension and
torque are derivatives of the one free energy ``G = -kT ln Z``. Kernel:
:mod:`supercoil.core.dna.ensemble`; derivation, sources and the fit to measured
curves: ``docs/theory/ensemble.md``.
"""

from __future__ import annotations

from functools import lru_cache
from typing import ClassVar

import numpy as np

from supercoil import display as _d
from supercoil.core.dna import ensemble as _en
from supercoil.core.dna import equilibrium as _eq
from supercoil.core.dna import phases as _ph
from supercoil.dna.model_parameters import ModelParameter
from supercoil.dna.models.base import Buckling, DNAModel, HatPoints
from supercoil.exceptions import ModelError, ValidityError

__all__ = ["Ensemble"]

_FIT = ("fit to Qian et al. 2024 Fig. S5 source data, this package: bioRxiv "
        "10.1101/2024.10.15.618270, averaged rotation curves at 0.3-2 pN, both sides, with "
        "the parameter set dna_qian2024_fit, docs/theory/ensemble.md#5-fit")
_BP = 0.34e-9  # rise per base pair of B-DNA, m
SHORT_TAIL_PERSISTENCE_LENGTHS = 3.0
#: the forces where the ensemble is evaluated: from kT/(4A) (0.02 pN for A = 50 nm; at
#: 0.01 pN the coexistence solve leaves the float range, measured) to 1e6 pN (at 1e30 pN
#: it does too); outside, a ValidityError naming the force and the limit
FORCE_MIN_PER_KT_OVER_A = 0.25
FORCE_MAX = 1e-6
#: the longest molecule (m) whose domain-length entropies stay in floats (1e300 nm overflowed)
LENGTH_MAX = 1.0


def check_forces(force, dna):
    """ValidityError naming the force outside ``[kT/(4A), 1e6 pN]`` or a length beyond 1 m."""
    if dna.length > LENGTH_MAX:
        raise ValidityError(f"ensemble model: length L = {dna.length:.6g} m is beyond "
                            f"{LENGTH_MAX:g} m, where its domain entropies leave the float range")
    f = np.asarray(force, float)
    if not f.size:
        return
    lo = FORCE_MIN_PER_KT_OVER_A * dna.kT / dna.bending_persistence
    bad = (f < lo) | (f > FORCE_MAX)
    if np.any(bad):
        x = float(f[bad].flat[0])
        raise ValidityError(
            f"ensemble model at force {_d.text(x, 'force')}: outside [kT/(4A) = "
            f"{_d.text(lo, 'force', '.4g')}, {_d.text(FORCE_MAX, 'force', '.0e')}], where its "
            "phases are evaluated (below, the worm-like-chain tail is not stretched: no "
            "coexistence to solve)")


#: points of the superhelix table of the derived plectoneme (cubic Hermite in the torque)
PLECTONEME_TABLE_POINTS = 240


@lru_cache(maxsize=32)
def _superhelix_table(B, kT, lam, prefactor, confinement, radius, points):
    """``(M_k, T_k, tau_k, R_k)`` along the screened superhelix's stable branch, increasing M."""
    from supercoil.dna.interactions.screened import partials_function, stable_branch

    part = partials_function(B, kT, lam, prefactor, confinement)
    # the stable branch over the screened interaction's range (hard core to 1000 a)
    br = stable_branch(B, kT, lam, prefactor, confinement, radius)
    R = np.geomspace(br.radius[0], br.radius[-1], points)
    alpha = _eq.solve_tilt(R, B, part)
    M = _eq.torque(alpha, R, B, part)
    T = _eq.tension(alpha, R, B, part)
    tau = np.sin(alpha) * np.cos(alpha) / R
    order = np.argsort(M)
    keep = M[order] > 0.0
    tables = (M[order][keep], T[order][keep], tau[order][keep], R[order][keep])
    for a in tables:
        a.setflags(write=False)
    return tables


def _table(dna, charge_fraction, confinement, radius, points=PLECTONEME_TABLE_POINTS):
    from supercoil.dna.interactions import get_interaction

    si = getattr(dna, "si", dna)
    inter = type(get_interaction("screened"))(charge_fraction=charge_fraction,
                                             confinement=confinement, hard_core_radius=radius)
    lam, _, _, pref = inter.screening(si)  # ParameterError naming salt if the DNA has none
    return _superhelix_table(float(si.bending_rigidity), float(si.kT), float(lam),
                             float(pref), float(confinement), float(radius), int(points))


def superhelix_table(dna, charge_fraction, confinement, radius=1e-9,
                     points=PLECTONEME_TABLE_POINTS):
    """Torque, tension and writhe density of the screened plectoneme's superhelix (SI).

    The uniform superhelix of :mod:`supercoil.core.dna.equilibrium` with the screened
    interaction (``interaction="screened"``: Debye-Hueckel repulsion of Stigter's
    charge ``charge_fraction`` times the bare one, the entropic confinement term times
    ``confinement``, hard core ``radius`` in m) for the DNA's bending stiffness, salt
    and temperature, on ``points`` radii of its stable branch: ``(M_k [N m], T_k [N],
    tau_k [1/m])`` with ``dT/dM = tau`` (docs/theory/ensemble.md#221-derived-plectoneme).
    Raises :class:`~supercoil.exceptions.ParameterError` naming ``salt`` if the DNA
    has none.
    """
    return _table(dna, charge_fraction, confinement, radius, points)[:3]


def superhelix_radius(torque, dna, charge_fraction, confinement, radius=1e-9):
    """Radius (m) of the screened superhelix at ``torque`` (N m): interpolated in log R
    along the table of :func:`superhelix_table` (the hard core beyond its largest torque)."""
    Mk, _, _, Rk = _table(dna, charge_fraction, confinement, radius)
    return np.exp(np.interp(np.abs(np.asarray(torque, float)), Mk, np.log(Rk)))


def _p(name, unit, default, lo, hi, description, source):
    return ModelParameter(name, unit, default, lo, hi, description, source)


class Ensemble(DNAModel):
    """Phase-ensemble model (docs/theory/ensemble.md).

    Options (not fitted): ``finite_size`` (the sum over domains; False: the
    thermodynamic-limit coexistence), ``physical_loop`` (end loop of
    docs/theory/end-loop.md; default False: a constant nucleation, which fitted
    measured curves better, docs/theory/ensemble.md#5-fit), ``exact_wlc``
    (Bouchiat; False: Marko's expansion), ``resummed`` (Moroz-Nelson resummed;
    False: first order), ``melting`` (the melted phase in the tail),
    ``multi_domain`` (up to two domains; default False: one), ``ss_melted`` (the melted
    phase's extension x_m(F) of two single strands; default False: the constant
    ``melted_extension``) and ``plectoneme_melting`` (bubbles inside the plectonemes
    too; default False), both docs/theory/melting.md#the-ensembles-melted-phase (each
    paid in AIC there with the previous positive side; off here until refitted jointly
    with the present defaults, docs/theory/ensemble.md#51-the-packages-public-fit), and
    ``screened_plectoneme`` (the plectoneme
    phase derived from the screened superhelix at the DNA's salt; default False: the
    power law ``P(M)``), and ``effective_tension`` (the stretched phase at the
    Moroz-Nelson effective tension ``F - k M^2/(4 kT A)``,
    docs/theory/ensemble.md#211-effective-tension; default False: the torque to second
    order in ``c_s(F)``).
    """

    name: ClassVar[str] = "ensemble"
    summary: ClassVar[str] = ("phase ensemble: melting WLC tail + plectoneme domains with "
                              "torque-dependent stiffness, summed at fixed turns")
    uses_interaction: ClassVar[bool] = False
    OPTIONS: ClassVar[dict] = {"finite_size": True, "physical_loop": False, "exact_wlc": True,
                               "resummed": True, "melting": True, "multi_domain": False,
                               "ss_melted": False, "plectoneme_melting": False,
                               "screened_plectoneme": False, "effective_tension": False}
    parameters: ClassVar[dict[str, ModelParameter]] = {
        "twist_bend_softening": _p(
            "twist_bend_softening", "", 2.25, 1.0, 8.0,
            "factor k on the Moroz-Nelson term of 1/c_s (1: Moroz-Nelson, the lower bound; "
            ">1 stands for twist-bend coupling)",
            "1: Moroz & Nelson, PNAS 94, 14418 (1997), resummed C_eff (the lower bound: the "
            "writhe softening of the chain's own bending fluctuations, docs/theory/"
            "ensemble.md#5-fit); default 2.25: " + _FIT),
        "plectoneme_twist_persistence_ref": _p(
            "plectoneme_twist_persistence_ref", "nm", 13.61e-9, 3e-9, 60e-9,
            "P0: the plectoneme's effective twist stiffness at the reference torque", _FIT),
        "plectoneme_stiffness_exponent": _p(
            "plectoneme_stiffness_exponent", "", 0.179, -0.5, 0.9,
            "a of P(M) = P0 (|M|/M0)^a (0: Marko 2007's constant P)", _FIT),
        "reference_torque": _p(
            "reference_torque", "pN*nm", 10e-21, 1e-21, 50e-21,
            "M0 of P(M) (a convention: P0 and M0 are degenerate)", "choice"),
        "domain_nucleation": _p(
            "domain_nucleation", "pN*nm", 83.9e-21, -100e-21, 150e-21,
            "extra free energy per plectoneme domain beyond its end loop", _FIT),
        "end_loop_writhe": _p(
            "end_loop_writhe", "", 1.0, 0.5, 1.5,
            "turns of linking absorbed as writhe by each domain's end loop",
            "one closed loop, docs/theory/end-loop.md#2-loop"),
        "melting_free_energy": _p(
            "melting_free_energy", "pN*nm", 4.43e-21, 0.5e-21, 25e-21,
            "free energy of melting one base pair at zero force and torque", _FIT),
        "melting_cooperativity": _p(
            "melting_cooperativity", "pN*nm", 63.3e-21, 0.0, 250e-21,
            "boundary free energy of one melted bubble (both ends)", _FIT),
        "melted_extension": _p(
            "melted_extension", "", 0.165, -0.5, 1.5,
            "extension per B-DNA contour length of the melted phase (used only with "
            "ss_melted=False)", _FIT),
        "plectoneme_charge_fraction": _p(
            "plectoneme_charge_fraction", "", 1.0, 0.05, 1.5,
            "screened_plectoneme: fraction of the bare charge on Stigter's cylinder",
            "1: the screened interaction's default (docs/theory/screened-interaction.md)"),
        "plectoneme_confinement": _p(
            "plectoneme_confinement", "", 0.0, 0.0, 1.0,
            "screened_plectoneme: coefficient of the entropic confinement term",
            "0: Clauvelin, Audoly & Neukirch, Biophys. J. 96, 3716 (2009); 1: Marko & "
            "Siggia, Phys. Rev. E 52, 2912 (1995)"),
        "positional_length": _p(
            "positional_length", "nm", 1e-9, 0.1e-9, 100e-9,
            "b: microscopic length of a domain's positional and length entropy (degenerate "
            "with domain_nucleation: 2 kT ln b per domain)", "choice"),
    }

    @property
    def symmetric_in_turns(self):
        """False with the melted phase (negative turns melt), True without it."""
        return not self.melting

    @property
    def describes_denaturation(self):
        """True with the melted phase in the tail."""
        return bool(self.melting)

    def __repr__(self):
        vals = ", ".join(f"{k}={v:.6g}" for k, v in self.values.items())
        return f"Ensemble({vals}, {self.options()})"

    def has_free_energy(self, thermal: bool) -> bool:
        """True with thermal fluctuations (the model has no athermal limit)."""
        return bool(thermal)

    def kernel_parameters(self, dna, thermal=True, nodes=70):
        """The kernel's :class:`~supercoil.core.dna.ensemble.EnsembleParameters`."""
        if not thermal:
            raise ModelError("model 'ensemble' has no athermal limit (its phases are "
                             "thermal: the WLC free energy and the domains' entropy); "
                             "use thermal=True")
        v = self.values
        melt = v["melting_free_energy"] / _BP if self.melting else np.inf
        return _en.EnsembleParameters(
            dna.length, dna.bending_persistence, dna.twist_persistence, dna.kT,
            v["twist_bend_softening"], v["plectoneme_twist_persistence_ref"],
            v["plectoneme_stiffness_exponent"], v["reference_torque"],
            v["domain_nucleation"], v["end_loop_writhe"], melt, v["melting_cooperativity"],
            v["melted_extension"], segment=_BP, microscopic_length=v["positional_length"],
            exact_wlc=self.exact_wlc, resummed=self.resummed,
            physical_loop=self.physical_loop, max_domains=2 if self.multi_domain else 1,
            nodes=nodes, finite_size=self.finite_size, melt_ss_elastic=self.ss_melted,
            plectoneme_melting=self.plectoneme_melting,
            plectoneme_table=superhelix_table(dna, v["plectoneme_charge_fraction"],
                                              v["plectoneme_confinement"])
            if self.screened_plectoneme else None,
            effective_tension=self.effective_tension)

    def _buckling(self, force, dna, thermal, interaction):
        """Thermodynamic-limit buckling: turns, coexistence torque, slope (ensemble.md#4)."""
        check_forces(force, dna)
        par = self.kernel_parameters(dna, thermal)
        f = np.asarray(force, float)
        Mb = _en.coexistence_torque(f, par)
        t, _ = _en.tail_gibbs(f, Mb, par)
        om_t = -t.dphi_dM
        om_p = -_en.plectoneme_phase(f, Mb, par).dphi_dM
        slope = -2.0 * np.pi * (-t.dphi_dF) / (om_p - om_t)
        return Buckling(dna.length * om_t / (2.0 * np.pi), Mb, slope)

    def plectoneme_radius(self, force, dna):
        """Superhelix radius (m) at the thermodynamic-limit coexistence torque, or None
        without ``screened_plectoneme`` (the power-law plectoneme has no geometry)."""
        if not self.screened_plectoneme:
            return None
        check_forces(force, dna)
        par = self.kernel_parameters(dna)
        Mb = _en.coexistence_torque(np.asarray(force, float), par)
        v = self.values
        return superhelix_radius(Mb, dna, v["plectoneme_charge_fraction"],
                                 v["plectoneme_confinement"])

    def _points(self, turns, force, dna, thermal, interaction, short_tail_length):
        """Ensemble averages: extension, torque, plectoneme length, phase, G."""
        check_forces(force, dna)
        par = self.kernel_parameters(dna, thermal)
        pt = _en.points(np.asarray(turns, float).ravel(), np.asarray(force, float).ravel(),
                        par)
        if short_tail_length is None:
            short_tail_length = SHORT_TAIL_PERSISTENCE_LENGTHS * dna.bending_persistence
        tail = dna.length - pt.plectoneme_length
        phase = np.where(pt.stretched_probability > 0.5, 0,
                         np.where(tail < short_tail_length, 2, 1)).astype(np.int8)
        with np.errstate(divide="ignore", invalid="ignore"):
            zeta = np.where(tail > 0.0, pt.extension / tail, 0.0)
        return HatPoints(pt.extension, pt.torque, pt.plectoneme_length, phase,
                         tail < short_tail_length, zeta, pt.free_energy)

    def _validity(self, turns, force, points, dna, thermal):
        """With ``effective_tension``: where the reported torque puts the stretched phase
        below the floor of its effective tension (its continuation, ensemble.md#211)."""
        if not self.effective_tension or not thermal:
            return []
        k = self.values["twist_bend_softening"]
        A, kT = dna.bending_persistence, dna.kT
        torque = np.asarray(points.torque, float)
        fe = _ph.effective_tension(force, torque, A, kT, k)
        reduced = _ph.EFFECTIVE_TENSION_FLOOR if self.exact_wlc else _ph.MARKO_TENSION_FLOOR
        floor = reduced * kT / A
        bad = fe < floor
        if not np.any(bad):
            return []
        i = int(np.flatnonzero(bad)[0])
        return [f"ensemble model (effective_tension) at force {_d.text(force[i], 'force')}, "
                f"turns {turns[i]:.6g}: torque {_d.text(torque[i], 'torque', '.4g')} leaves the "
                "stretched phase an effective tension F - k M^2/(4 kT A) = "
                f"{_d.text(fe[i], 'force', '.4g')} below its floor "
                f"{_d.text(floor, 'force', '.4g')} (near the chain's torque-induced instability "
                "at 0); there the phase is a continuation, not the worm-like chain"]

    def _free_energy(self, turns, force, dna, thermal, interaction):
        """G(N, F) = -kT ln Z in J (ensemble.md#32-fixed-turns)."""
        check_forces(force, dna)
        par = self.kernel_parameters(dna, thermal)
        return _en.points(np.asarray(turns, float).ravel(), np.asarray(force, float).ravel(),
                          par).free_energy
