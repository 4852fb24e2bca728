"""Every Python block and every ``supercoil`` command of the README runs as written.

Python blocks run in a temporary folder (files they write land there). Command
lines (the README's indented code lines that start with ``supercoil`` or
``python -c``) are expanded by bash exactly as a user's shell would (quotes,
``$(...)``, comments). In a virtual environment with the console script (the set-up
commands make one) they run as a user runs them after the set-up (below); elsewhere
they run in-process through :func:`supercoil.cli.main` (``python -c`` lines through
``exec``). ``supercoil bench`` and ``supercoil docs figures`` take minutes: they are
only parsed, in-process. The two set-up commands are not run (they build a virtual
environment); they are checked against ``.ci/run``, which runs the test command
verbatim.

The commands run as written run in the suite's background lane (``tests/fresh_scripts.py``),
one job per command. As a user runs them after the set-up: in a shell
whose environment is activated (the interpreter's ``bin`` first on ``PATH``, no
``PYTHONPATH``), the ``python -c`` lines in the repository folder itself (where the
repository's ``supercoil/`` is first on ``sys.path``), the ``supercoil`` lines through
the installed console script.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import stat
import subprocess
import sys
import warnings
from pathlib import Path

import matplotlib.pyplot as plt
import pytest
from fresh_scripts import background_job

from supercoil import cli

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text()
CI = (ROOT / ".ci" / "run").read_text()

PYTHON_BLOCKS = re.findall(r"^```python\n(.*?)^```", README, re.M | re.S)
COMMANDS = [line[4:] for line in README.splitlines()
            if re.match(r"^    (supercoil|python -c) ", line)]
SETUP = [line[4:] for line in README.splitlines()
         if line.startswith("    python3 -m venv")]
#: commands that take minutes (bench; docs figures reruns every script): parsed, not run
PARSE_ONLY = ("bench", "docs")
#: the line that activates the set-up's environment (the README says it after SETUP)
ACTIVATE = ". .venv/bin/activate"
BIN = Path(sys.executable).parent
#: the suite runs in a virtual environment with the console script (the set-up commands
#: make one): every command then runs as written from the activated environment
IN_VENV = (BIN / "supercoil").is_file() and sys.prefix != sys.base_prefix
#: the commands run in-process: the parsed-only ones, and all of them outside a venv
#: (inside one, the activated-environment test below runs the others as written; running
#: them in-process too would check the same outputs twice)
IN_PROCESS = [c for c in COMMANDS if not IN_VENV or c.split()[1] in PARSE_ONLY]


def test_readme_has_blocks_and_commands():
    assert len(PYTHON_BLOCKS) >= 2
    subcommands = {c.split()[1] for c in COMMANDS if c.startswith("supercoil ")}
    assert {"params", "hat", "rod", "fit"} <= subcommands
    assert len(SETUP) == 2, SETUP


def test_readme_cites_no_path_outside_the_repository():
    assert "../shared" not in README
    assert "MODEL.md" not in README
    for target in re.findall(r"\]\(((?!https?://)[^)#]+)(?:#[^)]*)?\)", README):
        assert (ROOT / target).exists(), f"README links to a missing file {target}"


@pytest.mark.parametrize("index", range(len(PYTHON_BLOCKS)))
def test_python_block_runs(index, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__readme__"}
    with contextlib.redirect_stdout(io.StringIO()):
        exec(compile(PYTHON_BLOCKS[index], f"README.md python block {index}", "exec"), namespace)
    plt.close("all")
    comment = re.search(r"#\s*R = ([\d.]+), ([\d.]+), ([\d.]+) nm", PYTHON_BLOCKS[index])
    if comment and "eq" in namespace:  # the numbers quoted in the README are the computed ones
        quoted = [float(x) for x in comment.groups()]
        assert [round(x, 2) for x in namespace["eq"].radius.m_as("nm")] == quoted


def _argv(command, tmp_path):
    """The words bash makes of a README command line (``$(...)`` runs with this Python)."""
    bindir = tmp_path / "bin"
    bindir.mkdir(exist_ok=True)
    shim = bindir / "python"
    shim.write_text(f'#!/bin/sh\nexec "{sys.executable}" "$@"\n')
    shim.chmod(shim.stat().st_mode | stat.S_IEXEC)
    env = dict(os.environ, PATH=f"{bindir}{os.pathsep}{os.environ.get('PATH', '')}",
               PYTHONPATH=str(ROOT), MPLBACKEND="Agg")
    proc = subprocess.run(["bash", "-c", f"printf '%s\\0' {command}"], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.split("\0")[:-1]


@pytest.mark.parametrize("command", IN_PROCESS, ids=[c.split()[1] for c in IN_PROCESS])
def test_command_runs(command, tmp_path, monkeypatch):
    argv = _argv(command, tmp_path)
    monkeypatch.chdir(tmp_path)
    out, err = io.StringIO(), io.StringIO()
    if argv[:2] == ["python", "-c"]:
        with contextlib.redirect_stdout(out):
            exec(compile(argv[2], "README python -c", "exec"), {"__name__": "__main__"})
        assert Path(out.getvalue().strip()).is_file()  # the line prints the sample's path
        return
    assert argv[0] == "supercoil", argv
    if argv[1] in PARSE_ONLY:
        args = cli.build_parser().parse_args(argv[1:])
        assert args.func is not None
        return
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = cli.main(argv[1:])
    plt.close("all")
    assert status == 0, err.getvalue()[-2000:]
    if "--out" in argv:
        written = list((tmp_path / argv[argv.index("--out") + 1]).rglob("*"))
        assert any(p.suffix == ".csv" for p in written), written


def test_setup_commands_are_the_ones_ci_runs(tmp_path, monkeypatch):
    main_job, test_command = SETUP
    assert test_command in CI.splitlines(), "README's test command is not in .ci/run verbatim"
    venv, install, job = main_job.split(" && ")
    ci_venv, ci_install, _ = test_command.split(" && ")
    assert venv == ci_venv
    assert install == ci_install.replace(" '.[test]'", " .")
    assert job.startswith(".venv/bin/supercoil ")
    monkeypatch.chdir(tmp_path)
    err = io.StringIO()
    with (contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err),
          warnings.catch_warnings(record=True) as caught):
        warnings.simplefilter("always")
        assert cli.main(job.split()[1:]) == 0
    plt.close("all")
    assert list((tmp_path / "results").glob("*.csv"))
    # the user who runs the main job sees no warning
    assert err.getvalue() == "" and caught == []


def test_readme_says_to_activate_the_environment_before_bare_commands():
    """Issue 22 item 10: after the set-up the README used bare ``supercoil`` and ``python``
    without a word on ``.venv`` (the repository's ``supercoil/`` then shadows the install:
    "No module named 'pint'")."""
    lines = README.splitlines()
    activate = lines.index("    " + ACTIVATE)
    setup = max(i for i, line in enumerate(lines) if line.startswith("    python3 -m venv"))
    first_bare = min(i for i, line in enumerate(lines)
                     if re.match(r"^    (supercoil|python -c) ", line))
    assert setup < activate < first_bare
    assert ".venv/bin/supercoil" in "\n".join(lines[setup:first_bare])  # the alternative


def _activated_env():
    """The environment of a shell after ``. .venv/bin/activate`` of this interpreter's venv."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    env.update(PATH=f"{BIN}{os.pathsep}{os.environ.get('PATH', '')}",
               VIRTUAL_ENV=str(BIN.parent), MPLBACKEND="Agg")
    return env


#: the commands that run as written from an activated environment (in a venv)
AS_WRITTEN = [c for c in COMMANDS if c.split()[1] not in PARSE_ONLY]


def _as_written_job(command):
    """The background job of one command: (process, folder it ran in)."""
    def job(lane, folder):
        # python -c lines in the repository folder, where the checkout's package shadows the
        # installed one
        cwd = ROOT if command.startswith("python -c ") else folder
        return lane.run(["bash", "-c", command], timeout=600, cwd=cwd,
                        env=_activated_env()), folder
    return job


for _i, _command in enumerate(AS_WRITTEN):
    background_job(f"readme:{_i}", _as_written_job(_command))


@pytest.mark.skipif(not IN_VENV, reason="needs the suite to run in a virtual environment "
                    "with the supercoil console script (the set-up commands make one)")
@pytest.mark.parametrize("index", [
    pytest.param(i, marks=() if not IN_VENV else pytest.mark.background(f"readme:{i}"),
                 id=c.split()[1]) for i, c in enumerate(AS_WRITTEN)])
def test_command_runs_as_written_from_an_activated_environment(index, background):
    """Each command runs in the background lane (the job ``readme:<index>``)."""
    command = AS_WRITTEN[index]
    proc, folder = background.result(f"readme:{index}")
    assert proc.returncode == 0, proc.stderr[-2000:]
    if command.startswith("python -c "):
        assert Path(proc.stdout.strip()).is_file()
    elif "--out" in command.split():
        out = command.split()[command.split().index("--out") + 1]
        assert any(p.suffix == ".csv" for p in (folder / out).rglob("*"))
