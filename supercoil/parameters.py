"""Named parameter sets: TOML files with units written into every value.

A parameter file looks like::

    kind = "ElasticRod"          # or "DNA", or "DNAModel" (then also model = "<name>")
    title = "..."

    [parameters]
    young_modulus = "4.20 MPa"   # every value carries its unit
    ...

    [sources]
    young_modulus = "tensile test, ..."   # one source line per value

A ``"DNAModel"`` file holds values of a registered DNA model's declared parameters
(:class:`~supercoil.dna.model_parameters.ModelParameter`, each in a unit of its
dimension) and, optionally, a ``[calibration]`` table of the fit it comes from (the
``torque_scale`` the model's torques were fitted with, a plain number with its source
line): its material is the model instance and :attr:`ParameterSet.calibration` holds
the calibration.

The bundled sets live in the repository's top-level ``parameters/`` folder and
are shipped inside the wheel as ``supercoil/parameters/``, so
:func:`load_parameters` works from an installed package as well as from a
checkout.
"""

from __future__ import annotations

import dataclasses
import importlib.resources
import tomllib
from pathlib import Path

import pint

from supercoil.dna.material import DNA
from supercoil.exceptions import ParameterError
from supercoil.rod.material import ElasticRod
from supercoil.units import ureg

__all__ = ["ParameterSet", "available_parameter_sets", "load_parameters", "read_parameter_set"]

_KINDS = {"ElasticRod": ElasticRod, "DNA": DNA, "DNAModel": None}
_REQUIRED = {
    "ElasticRod": ("radius", "length", "young_modulus", "shear_modulus"),
    "DNA": ("length", "bending_persistence", "twist_persistence", "radius", "temperature"),
    "DNAModel": (),
}
#: the calibration values a "DNAModel" file may record from its fit
CALIBRATION_KEYS = ("torque_scale",)


@dataclasses.dataclass(frozen=True)
class ParameterSet:
    """A parameter file read and checked: its values as quantities, sources and material."""

    name: str
    path: Path
    kind: str
    title: str
    values: dict
    sources: dict
    material: object
    calibration: dict = dataclasses.field(default_factory=dict)

    def describe(self) -> str:
        """Human-readable listing: one line per value with its unit and source."""
        width = max(len(k) for k in self.values)
        lines = [f"{self.name} ({self.kind}): {self.title}", f"  file: {self.path}"]
        for key, q in self.values.items():
            val = f"{q:~P}" if hasattr(q, "units") else f"{q:g}"
            lines.append(f"  {key:<{width}} = {val:<14}  # {self.sources.get(key, '')}")
        for key, value in self.calibration.items():  # the fit's, of a "DNAModel" set
            lines.append(f"  {key:<{width}} = {value:<14g}  # calibration of the fit: "
                         f"{self.sources.get(key, '')}")
        return "\n".join(lines)


def _bundled_dirs():
    """Folders holding bundled sets: inside the installed package, then the checkout."""
    dirs = []
    try:
        pkg = importlib.resources.files("supercoil") / "parameters"
        if pkg.is_dir():
            dirs.append(Path(str(pkg)))
    except (ModuleNotFoundError, TypeError):  # pragma: no cover - odd loaders
        pass
    checkout = Path(__file__).resolve().parent.parent / "parameters"
    if checkout.is_dir() and checkout not in dirs:
        dirs.append(checkout)
    return dirs


def available_parameter_sets() -> list[str]:
    """Names of the bundled parameter sets."""
    names = set()
    for d in _bundled_dirs():
        names.update(p.stem for p in d.glob("*.toml"))
    return sorted(names)


def _resolve(name_or_path) -> tuple[str, Path]:
    if not isinstance(name_or_path, str | Path) and not hasattr(name_or_path, "__fspath__"):
        raise TypeError(f"name_or_path must be a parameter-set name (one of "
                        f"{', '.join(available_parameter_sets())}) or a path to a TOML file, "
                        f"got {type(name_or_path).__name__}")
    p = Path(name_or_path)
    if p.suffix == ".toml" or p.exists() or len(p.parts) > 1:
        if not p.is_file():
            raise ParameterError(f"parameter file not found: {p}")
        return p.stem, p
    for d in _bundled_dirs():
        cand = d / f"{name_or_path}.toml"
        if cand.is_file():
            return str(name_or_path), cand
    raise ParameterError(
        f"unknown parameter set {name_or_path!r}; bundled sets: "
        f"{', '.join(available_parameter_sets()) or '(none found)'}"
    )


def read_parameter_set(name_or_path) -> ParameterSet:
    """Read and check a parameter set (bundled name or path to a TOML file)."""
    name, path = _resolve(name_or_path)
    try:
        doc = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as exc:
        raise ParameterError(f"{path}: not valid TOML: {exc}") from None
    kind = doc.get("kind")
    if kind not in _KINDS:
        raise ParameterError(f"{path}: 'kind' must be one of {sorted(_KINDS)}, got {kind!r}")
    raw = doc.get("parameters")
    if not isinstance(raw, dict):
        raise ParameterError(f"{path}: missing [parameters] table")
    sources = doc.get("sources", {})
    if kind == "DNAModel":
        material, values, calibration = _model_set(path, doc, raw, sources)
        return ParameterSet(name, path, kind, str(doc.get("title", name)), values,
                            dict(sources), material, calibration)
    cls = _KINDS[kind]
    fields = {f.name for f in dataclasses.fields(cls)}
    for key in _REQUIRED[kind]:
        if key not in raw:
            raise ParameterError(f"{path}: missing key {key!r} in [parameters] ({kind})")
    values = {key: _quantity(path, key, text, fields, kind, sources)
              for key, text in raw.items()}
    try:
        material = cls(**values)
    except pint.DimensionalityError as exc:
        raise ParameterError(f"{path}: wrong dimension: {exc}") from None
    except ValueError as exc:
        raise ParameterError(f"{path}: {exc}") from None
    title = str(doc.get("title", name))
    return ParameterSet(name, path, kind, title, values, dict(sources), material)


def _quantity(path, key, text, fields, kind, sources):
    """One ``[parameters]`` entry as a quantity; ParameterError naming the key otherwise."""
    if key not in fields:
        raise ParameterError(
            f"{path}: unknown key {key!r} in [parameters]; {kind} takes {sorted(fields)}"
        )
    if key not in sources:
        raise ParameterError(f"{path}: no source line for {key!r} in [sources]")
    if not isinstance(text, str | int | float):
        raise ParameterError(f"{path}: {key} must be a string like '4.2 MPa', got {text!r}")
    try:
        return ureg.Quantity(text)
    except (pint.UndefinedUnitError, pint.errors.DefinitionSyntaxError) as exc:
        raise ParameterError(f"{path}: {key} = {text!r}: unknown unit ({exc})") from None
    except Exception as exc:  # pint raises several parser errors
        raise ParameterError(f"{path}: {key} = {text!r} cannot be parsed ({exc})") from None


def _model_set(path, doc, raw, sources):
    """``(model instance, values, calibration)`` of a ``"DNAModel"`` file (checked)."""
    from supercoil.dna.models import available_models, get_model

    name = doc.get("model")
    if name not in available_models():
        raise ParameterError(f"{path}: 'model' must be one of {available_models()}, "
                             f"got {name!r}")
    declared = get_model(name).parameters
    values = {}
    for key, text in raw.items():
        q = values[key] = _quantity(path, key, text, set(declared), f"model {name!r}", sources)
        unit = declared[key].unit or "dimensionless"
        if q.dimensionality != ureg.Quantity(1.0, unit).dimensionality:
            raise ParameterError(f"{path}: {key} = {text!r}: wrong dimension, {key} is in "
                                 f"{unit}")
    calibration = {}
    for key, value in doc.get("calibration", {}).items():
        if key not in CALIBRATION_KEYS:
            raise ParameterError(f"{path}: unknown key {key!r} in [calibration]; it takes "
                                 f"{list(CALIBRATION_KEYS)}")
        if key not in sources:
            raise ParameterError(f"{path}: no source line for {key!r} in [sources]")
        if not isinstance(value, int | float) or not value > 0:
            raise ParameterError(f"{path}: {key} must be a positive number, got {value!r}")
        calibration[key] = float(value)
    try:  # the model converts each quantity to SI and checks its range
        model = get_model(name, **values)
    except ValueError as exc:
        raise ParameterError(f"{path}: {exc}") from None
    return model, values, calibration


def load_parameters(name_or_path):
    """Load a named parameter set and return its material.

    Parameters
    ----------
    name_or_path : str or path
        A bundled set (``"dna"``, ``"silicone_rubber_rod"``) or a path to a
        TOML file in the same format.

    Returns
    -------
    ElasticRod, DNA or DNAModel
        A ``"DNAModel"`` file gives the model instance with the file's values.

    Raises
    ------
    ParameterError
        Unknown name, missing key, unknown unit, wrong dimension, no source.
    """
    return read_parameter_set(name_or_path).material
