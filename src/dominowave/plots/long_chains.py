"""The front speed along a long chain: DEM members beside the theory's transient and limit.

One panel per chain (configuration and d/l): the *window speed* of every DEM member,
``v_n = (x_{n+w} - x_n) / (t_{n+w} - t_n)`` over ``w`` dominoes (a local speed between
neighbours scatters too much to read on a 300-domino chain), the same window speed of
the theory's transient for the same push (eqs 8, 12, 19) and the limit eq 34. Speeds are
drawn as ``v / sqrt(g l)``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from dominowave.checks import check_in_range

__all__ = ["SpeedPanel", "plot_speed_along_chain", "window_speed"]


def window_speed(arrival, positions, window: int) -> np.ndarray:
    """Speed over ``window`` dominoes ``(x[n+w] - x[n]) / (t[n+w] - t[n])`` [m/s].

    ``arrival`` [s] and ``positions`` [m] of shape (N,); returns shape (N - w,), entry
    ``n`` for the window starting at domino ``n`` (NaN where an arrival is missing).
    """
    t = np.asarray(arrival, dtype=float)
    x = np.asarray(positions, dtype=float)
    if t.shape != x.shape or t.ndim != 1:
        raise ValueError(
            f"arrival and positions must be 1-D of the same shape, got {t.shape} and {x.shape}"
        )
    check_in_range("window", window, 1, t.size - 1, lo_inclusive=True, hi_inclusive=True)
    if int(window) != window:
        raise ValueError(f"window = {window!r} is not a whole number of dominoes")
    window = int(window)
    with np.errstate(invalid="ignore", divide="ignore"):
        return (x[window:] - x[:-window]) / (t[window:] - t[:-window])


@dataclass(frozen=True)
class SpeedPanel:
    """One chain's data: ``title``; ``positions`` (N,) [m]; ``members`` (M, N) DEM
    arrival times [s]; ``theory`` (N,) the transient's arrival times [s]; ``limit`` eq 34
    [m/s]; ``scale`` sqrt(g l) [m/s]."""

    title: str
    positions: np.ndarray
    members: np.ndarray
    theory: np.ndarray
    limit: float
    scale: float


def plot_speed_along_chain(
    panels: list[SpeedPanel], path: Path, window: int = 10, ncols: int = 1
) -> Path:
    """Write the figure of ``panels`` (row by row, ``ncols`` per row) to ``path`` (PNG);
    returns ``path``."""
    if not panels:
        raise ValueError("panels is empty: nothing to draw")
    check_in_range("ncols", ncols, 1, len(panels), lo_inclusive=True, hi_inclusive=True)
    nrows = -(-len(panels) // ncols)
    fig = Figure(figsize=(4.2 * ncols, 2.2 * nrows + 0.6))
    axes = np.atleast_1d(fig.subplots(nrows, ncols, sharex=True, squeeze=False)).ravel()
    for ax, p in zip(axes, panels, strict=False):
        n = np.arange(p.positions.size - window) + window / 2
        for k, member in enumerate(np.atleast_2d(p.members)):
            v = window_speed(member, p.positions, window) / p.scale
            label = "DEM members" if k == 0 else None
            ax.plot(n, v, "-", color="C0", alpha=0.5, lw=0.8, label=label)
        v_th = window_speed(p.theory, p.positions, window) / p.scale
        ax.plot(n, v_th, "k--", label="theory transient (same push)")
        ax.axhline(p.limit / p.scale, color="k", lw=0.8, label="eq 34 limit (mapped parameters)")
        ax.set_title(p.title, fontsize=9)
        ax.set_ylabel(f"v / sqrt(g l), {window} dominoes", fontsize=8)
        ax.set_ylim(bottom=0)
    for ax in axes[len(panels) :]:
        ax.set_visible(False)
    axes[0].legend(fontsize=7, loc="lower right")
    for ax in axes[(nrows - 1) * ncols :]:
        ax.set_xlabel("domino n (window centre)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    return path
