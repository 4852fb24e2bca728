"""Figures of DNA hat curves (matplotlib imported only when drawing)."""

from __future__ import annotations

import numpy as np

__all__ = ["plot_hat_curves"]


def plot_hat_curves(df, path=None, dna=None):
    """Plot a :func:`hat_curve` table: extension vs N, vs eta, and torque vs N.

    Short-tail points are drawn dotted. Returns the figure; writes ``path`` if given.
    """
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5), constrained_layout=True)
    for force, g in df.groupby("force", sort=True):
        g = g.sort_values("turns")
        label = f"{force:g} pN"
        long_tail = ~g["short_tail"].to_numpy()
        line = None
        for ax, x, y in ((axes[0], "turns", "extension"), (axes[1], "eta", "extension"),
                         (axes[2], "turns", "torque")):
            xs, ys = g[x].to_numpy(), g[y].to_numpy()
            ym = np.where(long_tail, ys, np.nan)
            (ln,) = ax.plot(xs, ym, label=label, color=None if line is None else line)
            line = ln.get_color()
            ax.plot(xs, np.where(long_tail, np.nan, ys), ":", color=line)
    axes[0].set(xlabel="turns N", ylabel="extension z [nm]")
    axes[1].set(xlabel=r"$\eta = 2\pi N \xi_T / L$", ylabel="extension z [nm]")
    axes[2].set(xlabel="turns N", ylabel="torque [pN nm]")
    for ax in axes:
        ax.grid(alpha=0.3)
    axes[0].legend(title="force")
    thermal = df.attrs.get("provenance", {}).get("thermal")
    fig.suptitle("DNA hat curves (Marko-Siggia plectoneme"
                 + (", Moroz-Nelson tail)" if thermal else ", athermal)")
                 + "; dotted: tail shorter than the short-tail length")
    if path is not None:
        fig.savefig(path, dpi=120)
    return fig
