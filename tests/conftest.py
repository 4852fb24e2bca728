import os
import shutil
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

import matplotlib
import numpy as np
import pytest
from fresh_scripts import Lane, background_job
from hypothesis import HealthCheck, settings

matplotlib.use("Agg")
ROOT = Path(__file__).resolve().parent.parent

# Property-based tests run derandomized by default: the README's test command (and .ci/run,
# which calls it verbatim) draws the same examples on every machine, so a red run is
# reproducible. SUPERCOIL_HYPOTHESIS=explore draws fresh random examples, more of them.
settings.register_profile(
    "default", deadline=None, max_examples=40, derandomize=True,
    suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile(
    "explore", deadline=None, max_examples=200, suppress_health_check=[HealthCheck.too_slow]
)
settings.load_profile(os.environ.get("SUPERCOIL_HYPOTHESIS", "default"))

# pytest.approx adds abs=1e-12 when no abs is given: on SI values (a torque of 1e-20 N m,
# kT 4e-21 J) that tolerance exceeds the value itself and the comparison cannot fail. Every
# approx whose default abs would exceed its relative tolerance tenfold must name abs (abs=0
# for a purely relative comparison); this wrapper raises where one does not (tenfold, not
# onefold: a property test's drawn values must not make it flaky across versions).
_approx = pytest.approx


def _approx_naming_abs(expected, rel=None, abs=None, nan_ok=False):
    if abs is None:
        values = expected.values() if isinstance(expected, dict) else expected
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # e.g. pint's UnitStrippedWarning
                mag = np.abs(np.asarray(list(values) if isinstance(expected, dict) else values,
                                        float)).ravel()
        except Exception:  # not numbers (strings, objects): approx decides
            mag = np.array([])
        mag = mag[np.isfinite(mag) & (mag > 0)]
        if mag.size and mag.min() * (1e-6 if rel is None else rel) < 1e-13:
            raise AssertionError(
                f"pytest.approx({mag.min():.3g}, rel={rel}) without abs: the default "
                "abs=1e-12 exceeds the relative tolerance; give abs= (abs=0: relative only)")
    return _approx(expected, rel=rel, abs=abs, nan_ok=nan_ok)


pytest.approx = _approx_naming_abs


@pytest.fixture
def ureg():
    import supercoil

    return supercoil.ureg


@pytest.fixture
def dna():
    import supercoil

    return supercoil.load_parameters("dna")


@pytest.fixture
def rubber_rod():
    import supercoil

    return supercoil.load_parameters("silicone_rubber_rod")


@background_job("wheel")
def _build_wheel(lane, folder):
    """The package built as a wheel and unpacked in ``folder``: ``(names, site folder)``."""
    import zipfile

    proc = lane.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation",
                     "-w", str(folder / "dist"), str(ROOT)], timeout=180)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    (wheel,) = (folder / "dist").glob("supercoil-*.whl")
    site = folder / "site"
    with zipfile.ZipFile(wheel) as zf:
        names = zf.namelist()
        zf.extractall(site)
    return names, site


@pytest.fixture(scope="session")
def installed_wheel(background):
    """The package built as a wheel and unpacked away from the checkout, once per session
    (the background job ``wheel``: tests that use it carry ``background("wheel")``).

    Returns ``(names in the wheel, site folder, run)``; ``run(code)`` runs Python code with
    only the unpacked wheel on the path and returns its stdout.
    """
    names, site = background.result("wheel")

    def run(code):
        env = dict(os.environ, PYTHONPATH=str(site))
        out = subprocess.run([sys.executable, "-c", code], cwd=site.parent, env=env,
                             capture_output=True, text=True, timeout=60)
        assert out.returncode == 0, out.stderr
        return out.stdout

    return names, site, run


def _example_job(script):
    def job(lane, folder):
        status, _, stderr = lane.scripts().run(script, ["--out", folder / "out", "--quick"],
                                               cwd=folder, timeout=240)
        return status, stderr, folder / "out"
    return job


#: every example is the background job ``example:<name>``
EXAMPLES = sorted((ROOT / "examples").glob("*.py"))
for _script in EXAMPLES:
    background_job(f"example:{_script.stem}", _example_job(_script))


@pytest.fixture(scope="session")
def example_run(background):
    """``run(name)``: ``(exit status, stderr, output folder)`` of ``python
    examples/<name>.py --out DIR --quick``, run once per session in the background lane
    (the job ``example:<name>``: a fresh process forked from the helper of
    :mod:`fresh_scripts`, headless), shared by every test that checks that example's
    outputs (they carry ``background("example:<name>")``)."""
    return lambda name: background.result(f"example:{name}")


# --- the background lane (tests/fresh_scripts.py: Lane) ---------------------------------
# Why: CI runs the suite on two cores without pytest-xdist, and the slowest tests are
# processes the suite only waits for (the benchmark smoke run, the examples, the README's
# commands, the tutorials, the wheel build) or a few costly self-contained tests
# (fresh_scripts.in_background). One background lane runs those processes, one after
# another, on the second core while the in-process tests run on the first: every job that
# a selected test names in its ``background`` marker is queued when collection ends (a
# file or a -k selection queues only its own jobs; a session that runs every test it
# collects queues each file's jobs as soon as that file is collected), the tests that
# wait for a job run last (in their order), and each checks its job's result. A job that
# fails or outlives its timeout fails the tests that read it, with its output, never the
# session; the lane is closed (jobs not started cancelled, running processes killed) when
# pytest ends.
LANE = pytest.StashKey()
#: the session's config, for :func:`pytest_collectreport` (a report does not carry it)
_CONFIG = {}


def pytest_configure(config):
    config.addinivalue_line(
        "markers", "background(*jobs): the test reads these jobs of tests/fresh_scripts.py's "
        "JOBS (queued at the start of the session, run in the background lane); the test "
        "runs after the tests that need none")
    _CONFIG["config"] = config
    if not config.option.collectonly:
        # the lane's script helper starts now: its imports (a few seconds of CPU) run on the
        # second core while this process collects, not after (a selection without
        # background jobs only pays them there, and the helper is ended with the session)
        _lane(config).scripts()


def _jobs(item):
    return [name for mark in item.iter_markers("background") for name in mark.args]


def pytest_collection_modifyitems(config, items):
    """The tests that wait for background jobs run last, so that their jobs have run."""
    items[:] = ([item for item in items if not _jobs(item)]
                + [item for item in items if _jobs(item)])


def _selects_every_collected_test(config):
    """Whether the session runs every test of every file it collects: no ``-k``, ``-m``,
    ``--deselect``, ``--lf`` or ``--sw``, and no node ids (``file::test``) among the
    arguments (a file's collection report lists all its tests)."""
    return not (config.option.collectonly or config.option.keyword or config.option.markexpr
                or config.getoption("deselect", None) or config.getoption("lf", False)
                or config.getoption("stepwise", False)
                or any("::" in str(arg) for arg in config.args))


def pytest_collectreport(report):
    """When every collected test runs, queue the background jobs of a file's tests as soon
    as the file is collected: the lane starts while the rest of the suite is collected,
    in the order of collection (:func:`pytest_collection_finish` then queues nothing new)."""
    config = _CONFIG.get("config")
    if config is None or not report.passed or not _selects_every_collected_test(config):
        return
    lane = _lane(config)
    for node in report.result:
        if isinstance(node, pytest.Item):
            for name in _jobs(node):
                lane.submit(name)


def pytest_collection_finish(session):
    """Queue the background jobs of the selected tests, in the order the tests run (those
    queued while collecting keep their place)."""
    if session.config.option.collectonly:
        return
    lane = _lane(session.config)
    for item in session.items:
        for name in _jobs(item):
            lane.submit(name)


def _lane(config):
    if LANE not in config.stash:
        config.stash[LANE] = Lane(tempfile.mkdtemp(prefix="supercoil-tests-"))
    return config.stash[LANE]


def pytest_unconfigure(config):
    lane = config.stash.get(LANE, None)
    if lane is not None:
        lane.close()
        shutil.rmtree(lane.folder, ignore_errors=True)


@pytest.fixture(scope="session")
def background(request):
    """The session's background lane (:class:`fresh_scripts.Lane`)."""
    return _lane(request.config)


def pytest_addoption(parser):
    parser.addoption("--qian-s5", default=None,
                     help="path of the Figure S5 workbook of Qian et al. (bioRxiv "
                          "2024.10.15.618270) for the real-data tests (else the environment "
                          "variable SUPERCOIL_QIAN_S5)")


@pytest.fixture(scope="session")
def qian_s5(request):
    """Path of the user's Figure S5 workbook, or skip with the reason (the file is GPL)."""
    from supercoil.datasets.published import ENV_VAR, published_curves_path

    path = request.config.getoption("--qian-s5") or os.environ.get(ENV_VAR)
    if not path:
        pytest.skip(f"real-data test: give --qian-s5 PATH or set {ENV_VAR} to the Figure S5 "
                    "workbook of Qian et al. (WangLabCornell/Qian_et_al, 'Source Data/Figure "
                    "S5.xlsx'; GPL, not shipped)")
    return published_curves_path(path)
