"""Small-multiples figure of the stability map."""

from __future__ import annotations

import numpy as np

from supercoil.benchmark.stability.classify import (
    CATEGORIES,
    COLORS,
)


def _tick(v):
    if v == 0:
        return "0"
    if 0.98 < v < 1:
        return f"1-{1 - v:.0e}".replace("e-0", "e-")
    if abs(v) >= 1e4 or abs(v) < 1e-2:
        return f"{v:.0e}".replace("e+0", "e").replace("e-0", "e-").replace("e+", "e")
    return f"{v:.3g}"


def plot(table, path=None):
    """One categorical map per solver (small multiples) with a shared legend.

    Cells are drawn on their grid indices; the tick labels give the input
    values (the grids are logarithmic where the labels say so). Returns the
    figure; writes ``path`` (PNG) if given.
    """
    import matplotlib.pyplot as plt
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    solvers = list(dict.fromkeys(table["solver"]))
    labels = table.attrs.get("provenance", {}).get("axis_labels", {})
    ncol = 4
    nrow = int(np.ceil(len(solvers) / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.6 * ncol, 4.0 * nrow),
                             constrained_layout=True, squeeze=False)
    cmap = ListedColormap([COLORS[c] for c in CATEGORIES])
    norm = BoundaryNorm(np.arange(len(CATEGORIES) + 1) - 0.5, cmap.N)
    code = {c: k for k, c in enumerate(CATEGORIES)}
    for ax, solver in zip(axes.flat, solvers, strict=False):
        g = table[table["solver"] == solver]
        xq, yq = g["x_quantity"].iloc[0], g["y_quantity"].iloc[0]
        nx, ny = int(g["ix"].max()) + 1, int(g["iy"].max()) + 1
        grid = np.full((ny, nx), np.nan)
        grid[g["iy"].to_numpy(), g["ix"].to_numpy()] = [code[c] for c in g["category"]]
        ax.pcolormesh(np.arange(nx + 1) - 0.5, np.arange(ny + 1) - 0.5, grid, cmap=cmap,
                      norm=norm, edgecolors="white", linewidth=0.2)
        xs = g.drop_duplicates("ix").sort_values("ix")[xq].to_numpy()
        ys = g.drop_duplicates("iy").sort_values("iy")[yq].to_numpy()
        xt = np.unique(np.linspace(0, nx - 1, min(nx, 7)).round().astype(int))
        yt = np.unique(np.linspace(0, ny - 1, min(ny, 9)).round().astype(int))
        ax.set_xticks(xt, [_tick(xs[k]) for k in xt], fontsize=7, rotation=45)
        ax.set_yticks(yt, [_tick(ys[k]) for k in yt], fontsize=7)
        xl, yl = labels.get(solver, [xq, yq])
        ax.set(xlabel=xl, ylabel=yl)
        counts = g["category"].value_counts()
        ax.set_title(f"{solver}\n" + ", ".join(f"{c} {counts.get(c, 0)}" for c in CATEGORIES),
                     fontsize=9)
    for ax in axes.flat[len(solvers):]:
        ax.axis("off")
    fig.legend(handles=[Patch(color=COLORS[c], label=c) for c in CATEGORIES],
               loc="outside lower center", ncol=len(CATEGORIES), fontsize=10)
    quick = table.attrs.get("provenance", {}).get("quick")
    fig.suptitle("Stability map: outcome of every solver over its inputs"
                 + (" (quick grids)" if quick else ""))
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig
