"""Run scripts as fresh ``python SCRIPT ARGS`` processes without paying their imports each time.

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
imports fails here as it would in a fresh interpreter.

Used by ``tests/test_examples.py``.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

#: the helper process: imports once, then one fork per request line (JSON) on stdin
_HELPER = r"""
import json, os, runpy, signal, sys, traceback
import numpy, scipy.integrate, scipy.optimize, pandas, matplotlib
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
                                      text=True)

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
