""".ci/constraints-minimum.txt pins exactly the lower bounds declared in pyproject.toml."""

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _lower_bounds():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    reqs = list(project["dependencies"]) + list(project["optional-dependencies"]["test"])
    bounds = {}
    for req in reqs:
        m = re.fullmatch(r"\s*([A-Za-z0-9_.-]+)(\[[^\]]*\])?\s*>=\s*([0-9][0-9A-Za-z.]*)\s*", req)
        assert m, f"requirement without a plain lower bound: {req!r}"
        bounds[m.group(1).lower()] = m.group(3)
    return bounds


def _pins():
    pins = {}
    for line in (ROOT / ".ci" / "constraints-minimum.txt").read_text().splitlines():
        line = line.split("#")[0].strip()
        if line:
            name, _, version = line.partition("==")
            assert version, f"not an == pin: {line!r}"
            pins[name.strip().lower()] = version.strip()
    return pins


def test_constraints_pin_the_declared_lower_bounds():
    assert _pins() == _lower_bounds()


def test_every_extra_bound_agrees_with_the_test_extra():
    # the extras repeat bounds of the test extra (h5py, dask, ...): one value each
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    bounds = _lower_bounds()
    for extra, reqs in project["optional-dependencies"].items():
        for req in reqs:
            m = re.fullmatch(r"\s*([A-Za-z0-9_.-]+)(\[[^\]]*\])?\s*>=\s*(\S+)\s*", req)
            if m and m.group(1).lower() in bounds:
                assert bounds[m.group(1).lower()] == m.group(3), (extra, req)
