"""One small synthetic recording, written in every format (module-scoped: built once)."""

import pytest

from supercoil.traces import simulate_recording, write_synthetic_calisto, write_synthetic_magscope


@pytest.fixture(scope="session")
def recording():
    """2 molecules + 1 reference bead, 0.4 and 0.7 pN, 9 plateaus per force, 60 Hz."""
    return simulate_recording(molecules=2, reference=1, seed=11)


@pytest.fixture(scope="session")
def written(recording, tmp_path_factory):
    root = tmp_path_factory.mktemp("recordings")
    return {
        "magscope": write_synthetic_magscope(root / "magscope", recording),
        "calisto-hdf5": write_synthetic_calisto(root / "calisto" / "rot.h5", recording),
        "calisto-text": write_synthetic_calisto(root / "text" / "rot.txt", recording, text=True),
        "root": root,
    }
