"""Figure of a recording's trace with the detected plateaus."""

from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = ["plot_plateaus"]


def plot_plateaus(trace, plateaus, beads=None, path=None, max_points=20000):
    """Plot bead z, magnet rotation and height versus time; shade the kept plateau frames.

    Parameters
    ----------
    trace : pandas.DataFrame
        A trace table.
    plateaus : pandas.DataFrame
        From :func:`supercoil.traces.find_plateaus`.
    beads : sequence of str, optional
        Beads to draw (default: the first three, and the first reference bead).
    path : str or Path, optional
        Save the figure there (PNG) and close it; else return it.
    max_points : int
        At most this many points per line (every k-th frame).
    """
    import matplotlib.pyplot as plt

    labels = list(pd.unique(trace["bead"]))  # the recording's order
    refs = list(trace.attrs.get("reference_beads", []))
    if beads is None:
        beads = [b for b in labels if b not in refs][:3] + refs[:1]
    fig, axes = plt.subplots(3, 1, figsize=(9, 6.5), sharex=True, layout="constrained",
                             height_ratios=(3, 1, 1))
    for bead in beads:
        sub = trace[trace["bead"] == bead]
        step = max(1, len(sub) // max_points)
        kind = " (reference)" if bead in refs else ""
        axes[0].plot(sub["time"].to_numpy()[::step], sub["z"].to_numpy()[::step], lw=0.5,
                     label=f"bead {bead}{kind}")
    frames = trace.drop_duplicates("time").sort_values("time")
    step = max(1, len(frames) // max_points)
    axes[1].plot(frames["time"].to_numpy()[::step], frames["turns"].to_numpy()[::step], "k",
                 lw=0.8)
    axes[2].plot(frames["time"].to_numpy()[::step], frames["height"].to_numpy()[::step], "k",
                 lw=0.8)
    for ax in axes:
        for a, b in zip(plateaus["used_from"], plateaus["used_to"], strict=True):
            ax.axvspan(a, b, color="tab:green", alpha=0.12, lw=0)
    axes[0].set_ylabel("z [nm]")
    axes[0].legend(fontsize="small", loc="upper right", ncol=2)
    axes[0].set_title(f"{len(plateaus)} plateaus (green: frames kept after settling)",
                      fontsize="medium")
    axes[1].set_ylabel("magnet turns")
    axes[2].set_ylabel("height [mm]")
    axes[2].set_xlabel("time [s]")
    if np.ptp(frames["height"].to_numpy()) == 0:
        axes[2].set_ylim(frames["height"].iloc[0] - 0.5, frames["height"].iloc[0] + 0.5)
    if path is None:
        return fig
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
