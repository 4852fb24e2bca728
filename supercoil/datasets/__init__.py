"""Sample data shipped with the package, loadable by name.

>>> from supercoil.datasets import available_datasets, dataset_path, load_dataset
>>> available_datasets()
['rotation_curves']
>>> data = load_dataset("rotation_curves")      # what read_tweezers_csv returns
>>> sorted(data.attrs["units"].items())[:2]
[('extension', 'um'), ('force', 'pN')]

``dataset_path(name)`` gives the CSV file itself, for the command line
(``supercoil fit PATH ...``). Every data set is synthetic and documents how it
was made in its ``#`` provenance lines (true parameters, offsets, noise, seed);
:mod:`supercoil.datasets.make` regenerates it. See docs/tutorials/fitting.md.

Published measurements (:mod:`supercoil.datasets.published`):
``read_published_curves(path)`` reads the user's copy of a published source-data
file (not shipped: its license) into the same table;
``load_published_summary()`` gives the small per-force summary numbers shipped
in ``published.csv``, cited on each line.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from supercoil.exceptions import DataError

__all__ = ["available_datasets", "dataset_path", "load_dataset", "load_published_summary",
           "read_published_curves"]

#: shipped CSV files that are not rotation-curve data sets (summary numbers)
_SUMMARIES = ("published.csv",)


def _folder():
    return resources.files(__name__)


def available_datasets() -> list[str]:
    """Names of the shipped data sets (sorted)."""
    return sorted(p.name[:-4] for p in _folder().iterdir()
                  if p.name.endswith(".csv") and p.name not in _SUMMARIES)


def dataset_path(name) -> Path:
    """Path of the CSV file of the data set ``name``.

    Raises
    ------
    DataError
        If there is no such data set (the message lists the available ones).
    """
    if not isinstance(name, str) or name not in available_datasets():
        raise DataError(f"no sample data set {name!r}; available: {available_datasets()}")
    return Path(str(_folder() / f"{name}.csv"))


def load_dataset(name):
    """Load the data set ``name`` with :func:`supercoil.read_tweezers_csv`.

    Returns
    -------
    pandas.DataFrame
        The rotation-curve table convention: float magnitudes in the file's
        units, ``attrs["units"]``, ``attrs["provenance"]`` (with the recipe the
        data were made from) and ``attrs["lines"]``.

    Raises
    ------
    DataError
        If there is no such data set.
    """
    from supercoil.dna.tweezers import read_tweezers_csv

    return read_tweezers_csv(dataset_path(name))


def __getattr__(name):
    """The readers of published data, imported on first use."""
    if name in ("read_published_curves", "load_published_summary"):
        from supercoil.datasets import published

        return getattr(published, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
