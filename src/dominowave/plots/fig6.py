"""The paper's Fig 6 (B-E) from a DEM sweep (the study :mod:`dominowave.sweep.fig6`).

Speeds are shown as ``v / sqrt(g l)`` against ``d/l``: DEM ensemble means with their
standard errors (members whose wave did not settle are left out and counted), the
limit theory eq 34 with the clump mapping (solid) and the paper's point-mass usage
(dashed), and the theory's *transient* fitted over the same dominoes as the DEM
(open squares) -- the like-for-like comparison for a 30-domino chain. An ensemble in
which no member settled is an open circle on the bottom edge at its d/l; one in which
only some did carries the count (e.g. "5/8") beside its point.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from dominowave.chain.build import ChainParams
from dominowave.chain.compare import theory_speed
from dominowave.chain.paper_fig6 import CONFIGS
from dominowave.plots.unsettled import mark_unsettled
from dominowave.units import speed_scale

__all__ = ["PANELS", "plot_fig6", "plot_fig6_beside"]

PANELS: dict[str, tuple[str, tuple[str, ...]]] = {
    "B": ("2D vs 3D model", ("2d", "3d", "3d_asym")),
    "C": ("contact stiffness", ("k1e3", "2d", "k1e5")),
    "D": ("local damping and floor friction", ("2d", "damp_small", "damp_large", "mu0.6")),
    "E": ("multiple collisions under small damping", ("2d", "damp_small", "damp_large")),
}

LABELS = {
    "2d": "2D, k/k*=1e4, no damping, phi_f=0.3",
    "3d": "3D, no asymmetry",
    "3d_asym": "3D, lateral asymmetry",
    "k1e3": "k/k* = 1e3",
    "k1e5": "k/k* = 1e5",
    "damp_small": "local damping 0.02",
    "damp_large": "local damping 0.1",
    "mu0.6": "phi_f = 0.6",
}
COLORS = dict(zip(CONFIGS, ["C0", "C1", "C2", "C3", "C4", "C5", "C6", "C7"], strict=True))


def _theory_curve(config: str, grid: np.ndarray, mapping: str, shape: str) -> np.ndarray:
    """eq 34 [m/s] on ``grid`` (d/l) from the mapped parameters of ``shape`` dominoes."""
    return np.array(
        [
            theory_speed(ChainParams(d_over_l=x, shape=shape, **CONFIGS[config]), mapping)
            for x in grid
        ]
    )


def _shape_of(summary: list[dict]) -> str:
    """The domino shape of a summary: a box summary has a ``shape`` column."""
    return summary[0].get("shape", "clump") if summary else "clump"


def _series(summary: list[dict], config: str) -> dict[str, np.ndarray]:
    rows = sorted((r for r in summary if r["config"] == config), key=lambda r: r["d_over_l"])
    keys = rows[0].keys() if rows else []
    return {k: np.array([r[k] for r in rows]) for k in keys if k not in ("config", "shape")}


def _settled_counts(ax, x, y, settled, members, color) -> None:
    """``settled/members`` beside each ensemble point that left members out."""
    for xi, yi, k, m in zip(x, y, settled, members, strict=True):
        if 0 < k < m and np.isfinite(yi):
            ax.annotate(
                f"{int(k)}/{int(m)}",
                (xi, yi),
                xytext=(4, 3),
                textcoords="offset points",
                fontsize=6,
                color=color,
            )


def _speed_axes(ax, summary, configs, scale, grid, theory_configs):
    unsettled_label = "no member settled: no speed (open, on the bottom edge)"
    for i, c in enumerate(configs):
        s = _series(summary, c)
        if not s:
            continue
        shift = 0.008 * (i - (len(configs) - 1) / 2)  # side by side, not on top
        ax.errorbar(
            s["d_over_l"] + shift,
            s["speed_mean"] / scale,
            yerr=s["speed_stderr"] / scale,
            fmt="o",
            color=COLORS[c],
            capsize=3,
            label=f"DEM {LABELS[c]}",
        )
        none_settled = s["n_settled"] == 0
        if mark_unsettled(ax, s["d_over_l"][none_settled] + shift, COLORS[c], unsettled_label):
            unsettled_label = None  # one legend entry per panel
        _settled_counts(
            ax,
            s["d_over_l"] + shift,
            s["speed_mean"] / scale,
            s["n_settled"],
            s["members"],
            COLORS[c],
        )
        ax.plot(
            s["d_over_l"] + shift,
            s["theory_window_speed"] / scale,
            "s",
            mfc="none",
            color=COLORS[c],
            ms=7,
        )
    shape = _shape_of(summary)
    for c in theory_configs:
        for mapping, style in (("clump", "-"), ("point", "--")):
            v = _theory_curve(c, grid, mapping, shape)
            ax.plot(grid, v / scale, style, color=COLORS[c], lw=1)
    ax.set_xlabel("d / l")
    ax.set_ylabel("v / sqrt(g l)")
    ax.set_yscale("log")
    ax.grid(alpha=0.3)


def _draw_panel(ax, ax2, summary, panel, present, scale, grid, title) -> None:
    """One panel of Fig 6 (the speeds on ``ax``, panel E's re-hit fraction on ``ax2``)."""
    theory_configs = present if panel == "C" else present[:1]
    _speed_axes(ax, summary, present, scale, grid, theory_configs)
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7)
    if ax2 is not None:
        for c in present:
            s = _series(summary, c)
            ax2.plot(
                s["d_over_l"],
                s["multiple_collision_fraction"],
                "o-",
                color=COLORS[c],
                label=LABELS[c],
            )
        ax2.set_ylabel("fraction of pairs hit > once\nbefore the next arrival")
        ax2.set_xlabel("d / l")
        ax2.grid(alpha=0.3)


def _write_csv(rows: list[dict], path: Path) -> None:
    fields = list(dict.fromkeys(k for r in rows for k in r))  # clump rows have no shape
    with path.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)


def _present(configs, rows: list[dict]) -> list[str]:
    """The ``configs`` that have rows in ``rows``, in their order."""
    return [c for c in configs if any(r["config"] == c for r in rows)]


def _save_panel(fig, out: Path, name: str, rows: list[dict], dpi: int) -> list[Path]:
    """Save ``fig`` as ``out/name.png`` at ``dpi`` and its ``rows`` as ``out/name.csv``;
    returns the two paths."""
    fig.tight_layout()
    png = out / f"{name}.png"
    fig.savefig(png, dpi=dpi)
    path = out / f"{name}.csv"
    _write_csv(rows, path)
    return [png, path]


def _grid(summaries) -> np.ndarray:
    dls = sorted({r["d_over_l"] for s in summaries for r in s})
    return np.linspace(max(0.05, min(dls) - 0.05), min(0.9, max(dls) + 0.05), 60)


def plot_fig6(summary: list[dict], out) -> list[Path]:
    """Write ``fig6B..E.png`` and ``fig6B..E.csv`` (the plotted ensemble data) to ``out``.

    ``summary`` is :func:`dominowave.sweep.fig6.summarise` output (of clump or of box
    dominoes: eq 34 is drawn from the mapped parameters of that shape). Returns the
    written paths.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    l, g = ChainParams().height, ChainParams().g
    scale = float(speed_scale(l, g))
    grid = _grid([summary])
    boxes = " (box dominoes)" if _shape_of(summary) == "box" else ""
    written = []
    for panel, (title, configs) in PANELS.items():
        present = _present(configs, summary)
        if not present:
            continue
        fig = Figure(figsize=(6.4, 6.4 if panel == "E" else 4.8))
        if panel == "E":
            ax, ax2 = fig.subplots(2, 1, sharex=True)
        else:
            ax, ax2 = fig.subplots(), None
        heading = (
            f"Fig 6{panel}: {title}{boxes}\n(lines: eq 34, solid clump / dashed point mass; "
            "squares: transient theory)"
        )
        _draw_panel(ax, ax2, summary, panel, present, scale, grid, heading)
        rows = [r for r in summary if r["config"] in present]
        written += _save_panel(fig, out, f"fig6{panel}", rows, dpi=120)
    return written


def plot_fig6_beside(clump: list[dict], box: list[dict], out) -> list[Path]:
    """Fig 6B-E with clump dominoes (left) beside box dominoes (right), same axes.

    ``clump`` and ``box`` are :func:`dominowave.sweep.fig6.summarise` outputs of a clump
    and a box preset. Writes ``fig6B..E_beside.png`` and ``.csv`` (the rows of both,
    the box rows with ``shape = box``) to ``out``; returns the written paths.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    l, g = ChainParams().height, ChainParams().g
    scale = float(speed_scale(l, g))
    grid = _grid([clump, box])
    written = []
    for panel, (title, configs) in PANELS.items():
        present = _present(configs, clump + box)
        if not present:
            continue
        fig = Figure(figsize=(12.0, 7.2 if panel == "E" else 5.0))
        if panel == "E":
            axes = fig.subplots(2, 2, sharex=True, sharey="row")
            pairs = [(axes[0, 0], axes[1, 0]), (axes[0, 1], axes[1, 1])]
        else:
            axes = fig.subplots(1, 2, sharey=True)
            pairs = [(axes[0], None), (axes[1], None)]
        for (ax, ax2), summary, name in zip(pairs, (clump, box), ("clump", "box"), strict=True):
            here = _present(present, summary)
            if not here:
                continue
            heading = (
                f"Fig 6{panel}: {title}, {name} dominoes\n(lines: eq 34 of the {name}, "
                "solid clump / dashed point mass; squares: transient)"
            )
            _draw_panel(ax, ax2, summary, panel, here, scale, grid, heading)
        rows = [r for r in clump + box if r["config"] in present]
        written += _save_panel(fig, out, f"fig6{panel}_beside", rows, dpi=110)
    return written
