"""Package metadata: LICENSE matches pyproject; authors, classifiers."""

import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_license_file_matches_pyproject():
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert meta["license"] == {"text": "MIT"}
    text = (ROOT / "LICENSE").read_text()
    assert text.startswith("MIT License")
    assert "Permission is hereby granted, free of charge" in text
    assert "License :: OSI Approved :: MIT License" in meta["classifiers"]
    sdist = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["hatch"]["build"][
        "targets"]["sdist"]["include"]
    assert "LICENSE" in sdist


def test_authors_and_classifiers():
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert meta["authors"] and all(a.get("name") for a in meta["authors"])
    assert any(c.startswith("Topic :: Scientific/Engineering") for c in meta["classifiers"])
    py = [c for c in meta["classifiers"] if c.startswith("Programming Language :: Python :: 3.")]
    assert py and min(py) == "Programming Language :: Python :: 3.11"  # = requires-python
    assert meta["requires-python"] == ">=3.11"
