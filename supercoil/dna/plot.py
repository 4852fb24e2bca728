"""Figures of DNA hat curves (matplotlib imported only when drawing)."""

from __future__ import annotations

import numpy as np

__all__ = ["plot_hat_curves"]


#: fixed margins of the 15 x 4.5 inch figure (a layout engine would draw the figure twice
#: in the CLI's ``supercoil hat``)
_MARGINS = {"left": 0.05, "right": 0.99, "bottom": 0.12, "top": 0.90, "wspace": 0.22}


def plot_hat_curves(df, path=None, dna=None, pyplot=True):
    """Plot a :func:`hat_curve` table: extension vs N, vs eta, and torque vs N.

    Short-tail points are drawn dotted. Returns the figure; writes ``path`` if
    given (drawn once). ``pyplot=False`` builds a bare
    :class:`matplotlib.figure.Figure` on the Agg canvas, without pyplot (for
    scripts that only write the file: nothing to close, no GUI backend).
    """
    if pyplot:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(15, 4.5))
    else:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        fig = Figure(figsize=(15, 4.5))
        FigureCanvasAgg(fig)
    axes = fig.subplots(1, 3, gridspec_kw=_MARGINS)
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
    # plain Unicode, no mathtext: its parser is slow to load
    axes[1].set(xlabel="η = 2π N ξ_T / L", ylabel="extension z [nm]")
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
