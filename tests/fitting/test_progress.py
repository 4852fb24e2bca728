"""Progress of fit_many: a tqdm.auto bar on a terminal or in a notebook, silent elsewhere
unless asked (progress="log": one line per molecule in a log)."""

import io

import numpy as np
import pytest
from fitting_helpers import FORCES

import supercoil as sc
from supercoil.dna.fitting import simulate_rotation_curves
from supercoil.dna.fitting.progress import Progress, is_terminal


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_silent_off_a_terminal_unless_asked():
    """Issue 22 item 11: a log, a pipe or a notebook's captured stream gets nothing by default."""
    out = io.StringIO()
    p = Progress(None, 3, stream=out)
    for m in ("a", "b", "c"):
        p.update(m)
    p.close()
    assert out.getvalue() == "" and p.bar is None


def test_lines_off_a_terminal_one_per_molecule_on_request():
    out = io.StringIO()
    p = Progress("log", 3, stream=out)
    for m in ("a", "b", "c"):
        p.update(m)
    p.close()
    assert out.getvalue().splitlines() == ["molecule a done (1/3)", "molecule b done (2/3)",
                                           "molecule c done (3/3)"]
    assert "\r" not in out.getvalue()  # a log gets no carriage returns


def test_bar_on_a_terminal_and_silence_on_request():
    term = _Terminal()
    assert is_terminal(term) and not is_terminal(io.StringIO()) and not is_terminal(object())
    p = Progress(None, 2, stream=term)
    assert p.bar is not None
    p.update("a")
    p.update("b")
    p.close()
    text = term.getvalue()
    assert "\r" in text and "2/2" in text and "molecule a done" not in text
    quiet = _Terminal()
    p = Progress(False, 2, stream=quiet)
    p.update("a")
    p.close()
    assert quiet.getvalue() == ""
    with pytest.raises(TypeError, match="progress must be None, True, False, 'log' or a call"):
        Progress("yes", 2)


def test_bar_is_tqdm_auto(monkeypatch):
    """The bar comes from tqdm.auto (a widget in a notebook, text on a terminal)."""
    import tqdm.auto

    made = []

    class Fake:
        def __init__(self, **kwargs):
            made.append(kwargs)

        def update(self, n):
            pass

        def set_postfix_str(self, *a, **k):
            pass

        def close(self):
            pass

    monkeypatch.setattr(tqdm.auto, "tqdm", Fake)
    p = Progress(None, 2, stream=_Terminal())
    p.update("a")
    p.close()
    assert made and made[0]["total"] == 2


def test_notebook_output_gets_the_bar(monkeypatch):
    """In a Jupyter kernel (stderr not a tty) the default is the bar, not one line per molecule."""
    import sys
    import types

    from supercoil.dna.fitting import progress as prog

    class ZMQInteractiveShell:
        pass

    fake_ipython = types.ModuleType("IPython")
    fake_ipython.get_ipython = lambda: ZMQInteractiveShell()
    monkeypatch.setitem(sys.modules, "ipykernel", types.ModuleType("ipykernel"))
    monkeypatch.setitem(sys.modules, "IPython", fake_ipython)
    out = io.StringIO()
    monkeypatch.setattr(sys, "stderr", out)
    assert prog.in_notebook(out) and not prog.in_notebook(io.StringIO())
    p = Progress(None, 2)
    assert p.bar is not None and not p.lines
    p.close()


def test_fit_many_default_progress_is_silent_off_a_terminal(true_dna, base, capsys):
    u = sc.ureg
    df = simulate_rotation_curves(true_dna, np.array(FORCES) * u.pN, points_per_force=30,
                                  molecules=2, seed=4)
    sc.fit_many(df, base)
    assert capsys.readouterr().err == ""
    sc.fit_many(df, base, progress="log")
    err = capsys.readouterr().err.splitlines()
    assert sorted(err) == ["molecule m1 done (1/2)", "molecule m2 done (2/2)"]
