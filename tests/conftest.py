import os

import matplotlib
import pytest
from hypothesis import HealthCheck, settings

matplotlib.use("Agg")

settings.register_profile(
    "default", deadline=None, max_examples=60, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile(  # derandomized: CI runs the same examples every time
    "ci", deadline=None, max_examples=40, derandomize=True,
    suppress_health_check=[HealthCheck.too_slow]
)
settings.load_profile("ci" if os.environ.get("CI") else "default")


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


@pytest.fixture(scope="session")
def installed_wheel(tmp_path_factory):
    """The package built as a wheel and unpacked away from the checkout, once per session.

    Returns ``(names in the wheel, site folder, run)``; ``run(code)`` runs Python code with
    only the unpacked wheel on the path and returns its stdout.
    """
    import subprocess
    import sys
    import zipfile
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    tmp = tmp_path_factory.mktemp("wheel")
    proc = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation",
         "-w", str(tmp / "dist"), str(root)],
        capture_output=True, text=True, timeout=180,
    )
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    (wheel,) = (tmp / "dist").glob("supercoil-*.whl")
    site = tmp / "site"
    with zipfile.ZipFile(wheel) as zf:
        names = zf.namelist()
        zf.extractall(site)

    def run(code):
        env = dict(os.environ, PYTHONPATH=str(site))
        out = subprocess.run([sys.executable, "-c", code], cwd=tmp, env=env,
                             capture_output=True, text=True, timeout=60)
        assert out.returncode == 0, out.stderr
        return out.stdout

    return names, site, run


@pytest.fixture(scope="session")
def example_run(tmp_path_factory):
    """``run(name)``: ``(exit status, stderr, output folder)`` of ``python
    examples/<name>.py --out DIR --quick``, run once per session (a fresh process forked
    from the helper of :mod:`fresh_scripts`, headless), shared by every test that
    checks that example's outputs."""
    from pathlib import Path

    from fresh_scripts import FreshScripts

    examples = Path(__file__).resolve().parent.parent / "examples"
    env = dict(os.environ, MPLBACKEND="Agg")
    env.pop("DISPLAY", None)
    helper = FreshScripts(env)
    done = {}

    def run(name):
        if name not in done:
            cwd = tmp_path_factory.mktemp(f"example_{name}")
            status, _, stderr = helper.run(examples / f"{name}.py",
                                           ["--out", cwd / "out", "--quick"], cwd=cwd,
                                           timeout=240)
            done[name] = status, stderr, cwd / "out"
        return done[name]

    yield run
    helper.close()


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
