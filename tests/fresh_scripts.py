"""Fresh processes for the suite: scripts without paying their imports each time, and the
background lane that runs the suite's subprocess jobs on the second core.

**Scripts.**

A helper process (started once, with ``MPLBACKEND=Agg`` and no display) imports the
third-party libraries every example needs (numpy, scipy, pandas, matplotlib) and
``supercoil``, then forks one child per script. Each child is a new process: it sets
``sys.argv`` and ``sys.path[0]`` as the interpreter does for ``python SCRIPT``, runs the
script as ``__main__`` (:func:`runpy.run_path`) in the given folder with its standard
streams on files, and exits with the script's status; nothing a script does reaches the
next one. What differs from a fresh interpreter is only that those modules are already
imported (at the state their import leaves them in): the start-up of the interpreter and
most of the CPU of a short script are paid once. Only top-level packages are imported
ahead (and ``matplotlib.pyplot``), so that a script which uses a submodule it never
imports fails here as it would in a fresh interpreter; scipy's submodules are the
exception (scipy loads them on first attribute access anyway, so nothing that fails in a
fresh interpreter passes here): ``scipy.integrate``, ``scipy.optimize`` and
``scipy.stats``, which the fitting module and its scripts import (about half a second
per script otherwise).

Used by the background lane for the examples, the tutorials, the benchmark smoke run and
the tests of :func:`in_background` (:meth:`Lane.scripts`, :meth:`Lane.call`).

**The background lane** (:class:`Lane`, started by ``tests/conftest.py``): CI has two cores
and no pytest-xdist, and the slowest tests are subprocesses the suite only waits for (the
benchmark smoke run, the examples, the README's commands, the tutorials, the wheel build)
or a few costly self-contained tests (:func:`in_background`). The lane is one thread that
runs such jobs one after another, in subprocesses, while the in-process tests run on the
other core. A job is a function ``job(lane, folder)`` registered by name in
:data:`JOBS` (:func:`background_job`); a test that needs it carries
``@pytest.mark.background(name)`` (the suite starts the job at the start of the session and
runs the test near the end) and reads the job's result with ``background.result(name)``,
where it checks it (a job that raises, or whose subprocess outlives its timeout, fails only
the tests that read it, with the output). Selecting a few tests (``-k``, a file) starts
only their jobs.
"""

from __future__ import annotations

import concurrent.futures
import json
import os
import re
import signal
import subprocess
import sys
import threading
from pathlib import Path

#: the helper process: imports once, then one fork per request line (JSON) on stdin
_HELPER = r"""
import json, os, runpy, signal, sys, traceback
import numpy, scipy.integrate, scipy.optimize, scipy.stats, pandas, matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot
import supercoil

for line in sys.stdin:
    job = json.loads(line)
    pid = os.fork()
    if pid == 0:  # the child: a fresh process for one script
        code = 1
        try:
            null = os.open(os.devnull, os.O_RDONLY)
            os.dup2(null, 0)
            for fd, path in ((1, job["stdout"]), (2, job["stderr"])):
                f = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
                os.dup2(f, fd)
            sys.stdin = open(0, closefd=False)
            os.chdir(job["cwd"])
            signal.alarm(int(job["timeout"]))  # the default action ends the child
            sys.argv = [job["script"], *job["args"]]
            sys.path[0] = os.path.dirname(os.path.abspath(job["script"]))
            try:
                runpy.run_path(job["script"], run_name="__main__")
                code = 0
            except SystemExit as exc:
                code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
                if not isinstance(exc.code, int | type(None)):
                    print(exc.code, file=sys.stderr)
            except BaseException:
                traceback.print_exc()
                code = 1
            sys.stdout.flush()
            sys.stderr.flush()
        finally:
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    print(json.dumps({"status": os.waitstatus_to_exitcode(status)}), flush=True)
"""


class FreshScripts:
    """The helper process; :meth:`run` runs one script in a fresh forked child."""

    def __init__(self, env):
        self._proc = subprocess.Popen([sys.executable, "-c", _HELPER], env=env,
                                      stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                      text=True, start_new_session=True)

    def run(self, script, args, cwd, timeout):
        """``(exit status, stdout, stderr)`` of ``python script *args`` run in ``cwd``.

        A negative status is the signal that ended the script (SIGALRM after
        ``timeout`` seconds).
        """
        out, err = os.path.join(cwd, ".stdout"), os.path.join(cwd, ".stderr")
        job = {"script": str(script), "args": [str(a) for a in args], "cwd": str(cwd),
               "stdout": out, "stderr": err, "timeout": timeout}
        self._proc.stdin.write(json.dumps(job) + "\n")
        self._proc.stdin.flush()
        reply = self._proc.stdout.readline()
        if not reply:
            raise RuntimeError("the script helper process ended")
        with open(out) as f_out, open(err) as f_err:
            texts = f_out.read(), f_err.read()
        os.remove(out)
        os.remove(err)
        return json.loads(reply)["status"], *texts

    def close(self):
        self._proc.stdin.close()
        self._proc.wait(timeout=60)
        self._proc.stdout.close()

    def kill(self):
        """End the helper and the script it runs now (one process group)."""
        _kill_group(self._proc)
        self._proc.wait(timeout=60)


#: the background jobs by name: ``job(lane, folder) -> result`` (:func:`background_job`)
JOBS = {}


def background_job(name, job=None):
    """Register ``job(lane, folder)`` as the background job ``name`` (a decorator without
    ``job``); ``folder`` is an empty folder of its own."""
    if job is None:
        return lambda fn: background_job(name, fn)
    JOBS[name] = job
    return job


def in_background(test):
    """Run a test function that takes no fixtures in a fresh process of the lane.

    For the costliest self-contained in-process tests: the same function, its asserts and
    the suite's warnings-as-errors, forked from the lane's helper (:meth:`Lane.call`) while
    the other tests run; the test that pytest sees reads its exit status and fails with its
    traceback (plain ``assert`` messages: pytest does not rewrite the module there).
    """
    import pytest

    path = sys.modules[test.__module__].__file__
    name = f"test:{Path(path).stem}::{test.__name__}"
    background_job(name, lambda lane, folder: lane.call(path, test.__name__, timeout=900,
                                                        cwd=folder))

    def wrapper(background):
        proc = background.result(name)
        assert proc.returncode == 0, f"{name} failed in the background lane:\n" + \
            proc.stdout[-3000:] + proc.stderr[-5000:]

    wrapper.__name__, wrapper.__qualname__ = test.__name__, test.__qualname__
    wrapper.__doc__, wrapper.__module__ = test.__doc__, test.__module__
    wrapper.background_body = test
    return pytest.mark.background(name)(wrapper)


def _kill_group(proc):
    """Kill a process started with ``start_new_session=True`` and everything it started."""
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


class Lane:
    """One background thread that runs the jobs of :data:`JOBS` in the order submitted.

    Parameters
    ----------
    folder : path
        Where each job gets its own empty folder.
    """

    def __init__(self, folder):
        self.folder = Path(folder)
        self._pool = concurrent.futures.ThreadPoolExecutor(1, "supercoil-background-lane")
        self._futures = {}
        self._procs = set()
        self._lock = threading.Lock()
        self._closed = False
        self._scripts = None

    def submit(self, name):
        """Queue the job ``name`` (once; later calls return the same future)."""
        with self._lock:
            if name not in self._futures:
                job = JOBS[name]
                folder = self.folder / re.sub(r"[^\w.-]", "_", name)
                self._futures[name] = self._pool.submit(self._start, job, folder)
            return self._futures[name]

    def _start(self, job, folder):
        if self._closed:
            raise RuntimeError("the background lane was closed before this job started")
        folder.mkdir(parents=True)
        return job(self, folder)

    def result(self, name, timeout=1800):
        """The result of job ``name`` (queued now if no test asked for it at the start);
        re-raises the job's exception. ``timeout`` (seconds) bounds the wait, queue included.
        """
        return self.submit(name).result(timeout)

    def run(self, args, timeout, **popen):
        """``subprocess.run(args, capture_output=True, text=True)`` that the lane can end:
        on ``timeout`` (seconds) the process and its children are killed and a
        ``RuntimeError`` carries their output."""
        proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True, start_new_session=True, **popen)
        with self._lock:
            self._procs.add(proc)
        try:
            out, err = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            _kill_group(proc)
            out, err = proc.communicate()
            raise RuntimeError(f"{args} did not end within {timeout} s\n--- stdout ---\n"
                               f"{out[-3000:]}\n--- stderr ---\n{err[-3000:]}") from None
        finally:
            with self._lock:
                self._procs.discard(proc)
        return subprocess.CompletedProcess(args, proc.returncode, out, err)

    def call(self, module_file, function, *args, timeout, cwd):
        """``function(*args)`` (strings) of the test module ``module_file`` in a fresh
        process forked from :meth:`scripts` (in ``cwd``), as the suite would call it:
        headless, warnings are errors (the suite's ``filterwarnings``). A
        ``CompletedProcess`` whose status is the function's return value (0 for None).
        """
        args = [str(module_file), function, *map(str, args)]
        status, out, err = self.scripts().run(__file__, args, cwd=cwd, timeout=timeout)
        return subprocess.CompletedProcess(args, status, out, err)

    def scripts(self):
        """The lane's :class:`FreshScripts` helper (headless; started on first use)."""
        if self._scripts is None:
            env = dict(os.environ, MPLBACKEND="Agg")
            env.pop("DISPLAY", None)
            self._scripts = FreshScripts(env)
        return self._scripts

    def close(self):
        """Cancel the jobs not started, kill the running one, wait for the thread."""
        self._closed = True
        with self._lock:
            for future in self._futures.values():
                future.cancel()
            for proc in self._procs:
                _kill_group(proc)
        if self._scripts is not None:
            self._scripts.kill()
        self._pool.shutdown(wait=True)


if __name__ == "__main__":  # Lane.call: python fresh_scripts.py MODULE_FILE FUNCTION ARGS...
    import importlib
    import warnings

    _file, _function, *_args = sys.argv[1:]
    sys.path.insert(0, os.path.dirname(_file))
    _module = importlib.import_module(Path(_file).stem)
    warnings.simplefilter("error")  # as pytest's filters, set after the imports
    _call = getattr(_module, _function)
    sys.exit(getattr(_call, "background_body", _call)(*_args))  # in_background: the test
