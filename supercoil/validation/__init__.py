"""Validation of the DNA models against published measurements (docs/theory/validation.md).

:func:`load_published` reads the shipped table of published values
(``published.csv``: one row per number read in a source, with the citation
and whether it was read from a table, the text or digitised from a figure);
:func:`validate` evaluates each model with the parameters of a bundled
parameter set (never tuned per point) at the conditions of every row (force,
salt, contour length where the row states them) and returns prediction and
relative error per row; :func:`plot_validation` draws them.
"""

from __future__ import annotations

import contextlib
from importlib import resources

import numpy as np

from supercoil import display

__all__ = ["DEFAULT_CONFIGS", "TORQUE_QUANTITIES", "load_published", "plot_validation", "validate"]

#: (model, parameter set, interaction): the paper's construction on the seed set,
#: the consistent and the Marko 2007 model on the 150 mM set, the phase-ensemble
#: model with its defaults and the set fitted to the curves of Qian et al. (2024), and
#: its force-spread fit to the same curves (a "DNAModel" parameter set in the model's
#: place: the model with that set's values)
DEFAULT_CONFIGS = (
    ("li-zhao", "dna", "hard-core"),
    ("free-energy", "dna_150mM_nacl", "screened"),
    ("marko2007", "dna_150mM_nacl", None),
    ("ensemble", "dna_qian2024_fit", None),
    ("ensemble_qian2024_spread_fit", "dna_qian2024_spread_fit", None),
)
#: quantities proportional to the model's torque: a model set fitted with a torque scale
#: s (model torque = s x the trap's) predicts them in the trap's units as prediction / s
TORQUE_QUANTITIES = ("buckling_torque", "effective_twist_persistence")
#: where a row gives no force (or zero force, where the models hold no plectoneme),
#: the models are evaluated at this force (pN); the note of the row says so
FALLBACK_FORCE_PN = {"plectoneme_radius": 0.2, "extension_jump_ratio": 2.0}
#: quantities that depend on the contour length (the others are per length or per turn
#: of a long molecule); a row of one of these that states no length is not compared: its
#: prediction is bracketed over BRACKET_LENGTHS_UM instead (the comparison would
#: otherwise rest on a length the source did not state)
LENGTH_DEPENDENT = ("buckling_turns", "extension_jump_ratio")
#: the contour lengths of the bundled sets (dna: 750 nm; dna_150mM_nacl: 5.03 um)
BRACKET_LENGTHS_UM = (0.75, 5.03)
_FRACTION_OF_BUCKLING = 0.3  # C_eff from the stretched-phase torque at 0.3 N_b


def load_published():
    """The published measurements: a DataFrame, ``attrs["units"]``, each row's unit in ``unit``."""
    from supercoil.tables import read_csv

    path = resources.files("supercoil.validation") / "published.csv"
    with resources.as_file(path) as p:
        df = read_csv(p)
    for c in ("unit", "source", "location", "read_from", "notes"):
        df[c] = df[c].fillna("").astype(str)
    df.attrs.setdefault("provenance", {})["source_file"] = "supercoil/validation/published.csv"
    return df


def _molecule(set_name, row):
    import supercoil as sc

    dna = sc.load_parameters(set_name)
    changes = {}
    if np.isfinite(row["dna_length"]):
        changes["length"] = row["dna_length"] * sc.ureg.um
    if np.isfinite(row["salt"]) and dna.salt is not None:
        changes["salt"] = row["salt"] * sc.ureg.mM
    return dna.replace(**changes) if changes else dna


def _model(spec):
    """``(model spec, torque scale)``: a registered name as is (scale 1), or the instance
    and the fitted torque scale of a bundled ``"DNAModel"`` parameter set."""
    from supercoil.dna.models import available_models
    from supercoil.exceptions import ParameterError
    from supercoil.parameters import read_parameter_set

    if not isinstance(spec, str) or spec in available_models():
        return spec, 1.0
    pset = read_parameter_set(spec)
    if pset.kind != "DNAModel":
        raise ParameterError(f"validate: {spec!r} in a config's model place is a "
                             f"{pset.kind} set, not a model or a DNAModel parameter set")
    return pset.material, pset.calibration.get("torque_scale", 1.0)


def _predict(quantity, force_pn, dna, model, interaction, unit):
    """One model prediction (magnitude in ``unit``) and a note, or (nan, reason)."""
    from supercoil.dna.hat import resolve
    from supercoil.units import ureg

    si, f, _, m, inter = resolve(dna, force_pn * ureg.pN, True, model,
                                 interaction or "hard-core")
    kT = si.kT
    if quantity == "plectoneme_radius":
        if not m.uses_interaction:
            return np.nan, "the model has no plectoneme geometry"
        return _radius(m, f, si, inter)
    b = m.buckling(f, si, True, inter)
    if quantity == "buckling_torque":
        return display.to_display(float(b.torque[0]), "torque"), ""
    if quantity == "buckling_turns":
        return float(b.turns[0]), ""
    if quantity == "post_buckling_slope":
        return display.to_display(abs(float(b.slope[0])), "length"), "magnitude of dz/dN"
    if quantity == "effective_twist_persistence":
        n = np.array([_FRACTION_OF_BUCKLING * float(b.turns[0])])
        p = m.points(n, f, si, True, inter, None)
        c_eff = float(p.torque[0]) * si.length / (2 * np.pi * n[0])  # N m^2
        value = (c_eff * display.spec("pN*nm**2")[1] if unit == "pN nm^2"
                 else display.to_display(c_eff / kT, "length"))
        return value, f"stretched-phase torque at {_FRACTION_OF_BUCKLING:g} N_b"
    if quantity == "extension_jump_ratio":
        if "end_loop" not in m.options():
            return np.nan, "the model has no end loop"
        m = m.replace(end_loop=True)
        b = m.buckling(f, si, True, inter)
        nb, eps = float(b.turns[0]), 1e-6
        p = m.points(np.array([nb - eps, nb + eps]), np.repeat(f, 2), si, True, inter, None)
        jump = float(p.extension[0] - p.extension[1])
        return jump / abs(float(b.slope[0])), "end loop on"
    return np.nan, f"no prediction for {quantity}"


def _radius(m, f, si, inter):
    """The plectoneme radius (nm) at the tension the model puts on the plectoneme, and a note.

    :meth:`~supercoil.dna.models.base.DNAModel.plectoneme_tension`: li-zhao (the paper's
    construction) holds the plectoneme at the full force F; the free-energy model at the
    tail's effective tension ``T_eff = F - (kT^2/B) sqrt(Q*)`` of its coexistence
    (docs/theory/free-energy.md#coexistence). Where the model gives no tension (e.g. the
    free-energy model at 10 mM, 0.2 pN: the tail's bracket closes) there is no radius: NaN
    and the note says why.
    """
    from supercoil.exceptions import SupercoilError

    try:
        pull = m.plectoneme_tension(f, si, True, inter)
    except SupercoilError as exc:
        salt = getattr(si, "salt", None)  # mol/m^3 = mM
        salt = f", {salt:g} mM" if salt is not None else ""
        return np.nan, (f"no radius at {display.text(float(f[0]), 'force', 'g')}{salt}: "
                        f"{type(exc).__name__}: {exc}")[:300]
    radius = display.to_display(float(inter.equilibrium(pull, si).radius[0]), "radius")
    if np.array_equal(pull, f):
        return radius, "plectoneme at the force F"
    return radius, (f"plectoneme at the tail's effective tension T_eff = "
                    f"{display.text(float(pull[0]), 'force', '.4g')}")


def _conditions(row, set_name, model, interaction):
    """Notes on the row's conditions the evaluation cannot take from the source."""
    import supercoil as sc

    dna = sc.load_parameters(set_name)
    uses_salt = interaction == "screened" and dna.salt is not None
    notes = []
    if np.isfinite(row["salt"]) and not uses_salt:
        notes.append(f"the row's {row['salt']:g} mM is no condition of {model}"
                     f"{' with ' + interaction if interaction else ''} (it takes no salt)")
    elif not np.isfinite(row["salt"]) and uses_salt:
        notes.append(f"the source states no salt: the set's {dna.salt.m_as('mM'):g} mM")
    return notes


def _bracket(q, force, set_name, row, model, interaction):
    """``(low, high, note)``: a length-dependent prediction at BRACKET_LENGTHS_UM."""
    import supercoil as sc
    from supercoil.exceptions import SupercoilError

    values = []
    for length in BRACKET_LENGTHS_UM:
        dna = _molecule(set_name, row).replace(length=length * sc.ureg.um)
        try:
            with _quiet():
                values.append(_predict(q, force, dna, model, interaction, row["unit"])[0])
        except SupercoilError:
            values.append(np.nan)
    text = " to ".join(f"{v:.3g} at {L:g} um" for v, L in
                       zip(values, BRACKET_LENGTHS_UM, strict=True))
    return values[0], values[1], (f"the source states no DNA length and {q} depends on it: "
                                  f"{text} (the bundled sets' lengths); not compared")


@contextlib.contextmanager
def _quiet():
    """SupercoilWarnings ignored (the bracket's evaluations; the row's own are recorded)."""
    import warnings

    from supercoil.exceptions import SupercoilWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SupercoilWarning)
        yield


def _evaluate(row, q, force, model, set_name, interaction, label=None):
    """``(predicted, note, low, high)`` of one published row for one config (``model``: a
    name or an instance; ``label``: the config's name of it in the notes)."""
    import warnings

    from supercoil.exceptions import SupercoilError, SupercoilWarning

    dna = _molecule(set_name, row)
    try:
        with warnings.catch_warnings(record=True) as rec:
            warnings.simplefilter("always", SupercoilWarning)
            pred, note = _predict(q, force, dna, model, interaction, row["unit"])
        if rec:
            note += "; warned: " + str(rec[0].message)[:120]
    except SupercoilError as exc:
        pred, note = np.nan, f"{type(exc).__name__}: {exc}"[:200]
    low = high = np.nan
    notes = _conditions(row, set_name, label or model, interaction)
    if q in LENGTH_DEPENDENT and not np.isfinite(row["dna_length"]) and np.isfinite(pred):
        # the source lacks a condition the prediction depends on: no comparison, the
        # prediction's range over the bundled lengths instead
        low, high, why = _bracket(q, force, set_name, row, model, interaction)
        pred, note = np.nan, "; ".join(x for x in (note, why) if x)
    return pred, "; ".join(x for x in (note, *notes) if x), low, high


def validate(configs=DEFAULT_CONFIGS, published=None):
    """Each model's prediction of every published row, with the relative error.

    Parameters
    ----------
    configs : sequence of (model, parameter set, interaction)
        Default :data:`DEFAULT_CONFIGS`.
    published : DataFrame, optional
        Default :func:`load_published`.

    Returns
    -------
    pandas.DataFrame
        One row per (published row, config): ``quantity``, ``force`` [pN],
        ``salt`` [mM], ``measured``, ``uncertainty``, ``unit``, ``model``,
        ``parameter_set``, ``interaction``, ``predicted``, ``relative_error``
        (``predicted / measured - 1``), ``predicted_low``, ``predicted_high``,
        ``source``, ``read_from``, ``note``. Rows the model cannot predict have NaN
        and say why in ``note``. A row compares only at the conditions its source
        states: a length-dependent quantity (:data:`LENGTH_DEPENDENT`) of a row without
        a length has no ``predicted`` and gives the prediction at the bundled sets'
        lengths (:data:`BRACKET_LENGTHS_UM`) in ``predicted_low``/``predicted_high``;
        a salt the source does not state, or one the model does not take, is said in
        ``note``.
    """
    from supercoil.tables import make_table, provenance

    pub = load_published() if published is None else published
    cols = {k: [] for k in ("quantity", "force", "salt", "measured", "uncertainty", "unit",
                            "model", "parameter_set", "interaction", "predicted",
                            "relative_error", "predicted_low", "predicted_high",
                            "torque_scale", "predicted_trap_torque",
                            "relative_error_trap_torque", "source", "read_from", "note")}
    resolved = {c[0]: _model(c[0]) for c in configs}  # each set read once
    for _, row in pub.iterrows():
        q = row["quantity"]
        force = row["force"]
        note0 = ""
        if not (np.isfinite(force) and force > 0):
            force = FALLBACK_FORCE_PN.get(q, np.nan)
            note0 = (f"measured at {'zero force' if row['force'] == 0 else 'an unstated force'};"
                     f" evaluated at {force:g} pN; ")
        for model, set_name, interaction in configs:
            m, s = resolved[model]
            pred, note, low, high = _evaluate(row, q, force, m, set_name, interaction, model)
            measured = float(row["value"])
            trap = pred / s if q in TORQUE_QUANTITIES and s != 1.0 else np.nan
            for k, v in (("quantity", q), ("force", force), ("salt", row["salt"]),
                         ("measured", measured), ("uncertainty", row["uncertainty"]),
                         ("unit", row["unit"]), ("model", model), ("parameter_set", set_name),
                         ("interaction", interaction or ""), ("predicted", pred),
                         ("relative_error", pred / measured - 1.0),
                         ("predicted_low", low), ("predicted_high", high),
                         ("torque_scale", s), ("predicted_trap_torque", trap),
                         ("relative_error_trap_torque", trap / measured - 1.0),
                         ("source", row["source"]), ("read_from", row["read_from"]),
                         ("note", (note0 + note).strip("; "))):
                cols[k].append(v)
    units = {k: "" for k in cols} | {"force": "pN", "salt": "mM"}
    return make_table(cols, units, provenance(None, scene="validation against published "
                                              "measurements", configs=[list(map(str, c))
                                                                       for c in configs]))


def plot_validation(table, path=None):
    """One panel per quantity: measured values (with errors) and each model's prediction
    (open markers: a torque quantity divided by the set's torque scale)."""
    import matplotlib.pyplot as plt

    quantities = list(dict.fromkeys(table["quantity"]))
    fig, axes = plt.subplots(1, len(quantities), figsize=(4.2 * len(quantities), 3.8),
                             constrained_layout=True, squeeze=False)
    markers = dict(zip(dict.fromkeys(table["model"]), "osd^v", strict=False))
    for ax, q in zip(axes[0], quantities, strict=True):
        t = table[table["quantity"] == q]
        meas = t.drop_duplicates(["source", "force", "salt", "measured"])
        ax.errorbar(np.arange(len(meas)), meas["measured"], yerr=meas["uncertainty"].fillna(0),
                    fmt="k_", ms=14, capsize=3, label="measured")
        for j, (model, g) in enumerate(t.groupby("model", sort=False)):
            x = np.arange(len(g)) + 0.1 * (j + 1)
            line, = ax.plot(x, g["predicted"], markers[model], label=model)
            if "predicted_trap_torque" in g and np.isfinite(g["predicted_trap_torque"]).any():
                # a set fitted with a torque scale s: its torques also in the trap's units
                ax.plot(x, g["predicted_trap_torque"], markers[model], mfc="none",
                        color=line.get_color(), label=f"{model} / torque_scale")
            # rows whose source lacks a condition: the prediction's range, not a point
            ax.vlines(x, g["predicted_low"], g["predicted_high"], color=line.get_color(),
                      lw=2, alpha=0.6)
        labels = [f"{f:g} pN" + (f", {s:g} mM" if np.isfinite(s) else "")
                  for f, s in zip(meas["force"], meas["salt"], strict=True)]
        ax.set_xticks(np.arange(len(meas)), labels, rotation=30, fontsize=7)
        ax.set_title(q.replace("_", " "), fontsize=9)
        ax.set_ylabel(meas["unit"].iloc[0] or "ratio")
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=7)
    fig.suptitle("DNA models against published measurements (parameters from the bundled "
                 "sets, not fitted)", fontsize=10)
    if path is not None:
        fig.savefig(path, dpi=120)
    return fig
