"""Progress of fit_many: a tqdm bar on a terminal, one line per molecule in a log, or silent."""

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


def test_lines_off_a_terminal_one_per_molecule():
    out = io.StringIO()
    p = Progress(None, 3, stream=out)
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
    with pytest.raises(TypeError, match="progress must be None, True, False or a callable"):
        Progress("yes", 2)


def test_fit_many_default_progress_writes_lines_to_stderr(true_dna, base, capsys):
    u = sc.ureg
    df = simulate_rotation_curves(true_dna, np.array(FORCES) * u.pN, points_per_force=30,
                                  molecules=2, seed=4)
    sc.fit_many(df, base)
    err = capsys.readouterr().err.splitlines()
    assert sorted(err) == ["molecule m1 done (1/2)", "molecule m2 done (2/2)"]
    sc.fit_many(df, base, progress=False)
    assert capsys.readouterr().err == ""
