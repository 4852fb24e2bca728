"""Raw magnetic-tweezers recordings -> rotation curves (I/O apart from the physics).

Readers turn an instrument's files into one tidy time-series table (the trace,
:mod:`supercoil.traces.trace`); :func:`rotation_curves` turns a trace into the
rotation-curve table of :func:`supercoil.read_tweezers_csv`, which the fits take
directly. Method: docs/theory/recordings.md.

* :func:`read_magscope`: MagScope ``Tracking Data <timestamp>.h5`` plus motor logs;
* :func:`read_calisto`: CALISTO HDF5, or headerless whitespace text;
* :func:`read_mtdat`: MultiMT ``.mtdat`` (YAML header, binary records;
  github.com/ddunlap91/MagTweezer);
* :func:`find_plateaus`, :func:`rotation_curves`, :func:`force_from_height`;
* :func:`blocking_error`: error of the mean of correlated frames
  (Flyvbjerg & Petersen, J. Chem. Phys. 91, 461 (1989));
* :func:`write_synthetic_magscope`, :func:`write_synthetic_calisto`: sample data.

HDF5 needs h5py: ``pip install 'supercoil[hdf5]'``.
"""

from .calisto import read_calisto
from .errors import BlockingResult, blocking_error
from .magscope import read_calibration, read_force_calibrant, read_magscope, read_motor_log
from .mtdat import read_mtdat, read_mtdat_records
from .plateaus import find_plateaus, force_from_height, rotation_curves
from .plot import plot_plateaus
from .synthetic import (
    SyntheticRecording,
    simulate_recording,
    synthetic_calibration,
    write_synthetic_calisto,
    write_synthetic_magscope,
)
from .trace import TRACE_UNITS, check_trace

__all__ = [
    "TRACE_UNITS",
    "BlockingResult",
    "SyntheticRecording",
    "blocking_error",
    "check_trace",
    "find_plateaus",
    "force_from_height",
    "plot_plateaus",
    "read_calibration",
    "read_calisto",
    "read_force_calibrant",
    "read_magscope",
    "read_motor_log",
    "read_mtdat",
    "read_mtdat_records",
    "rotation_curves",
    "simulate_recording",
    "synthetic_calibration",
    "write_synthetic_calisto",
    "write_synthetic_magscope",
]
