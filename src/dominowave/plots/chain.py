"""The figure of one chain run or ensemble (``dominowave chain --out``).

Top: the first-contact time of every domino [s] (dots: each run; dashed: the theory's
transient for the measured push, eqs 8, 12, 19). Bottom: the local speed between
neighbours [m/s] with the theory's transient, its limit eq 34 (clump mapping) and, if
the wave settled, the steady fit over the dominoes it used (shaded).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from dominowave.chain.scenario import ChainEnsemble, ChainRun
from dominowave.chain.wave import local_speeds

__all__ = ["plot_chain_run"]


def plot_chain_run(run: ChainRun, ens: ChainEnsemble | None, path: Path) -> Path:
    """Write ``chain.png``: first-contact times and local speeds of ``run`` (and of every
    member of ``ens``) beside the theory's transient and limit; returns ``path``."""
    fig = Figure(figsize=(6.4, 6.4))
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    n = np.arange(run.arrival.size)
    runs = ens.runs if ens is not None else [run]
    for r in runs:
        ax1.plot(n, r.arrival, ".", color="C0", alpha=0.6)
        ax2.plot(n[1:], local_speeds(r.arrival, r.positions), "-", color="C0", alpha=0.4)
    ax1.plot(n, run.theory_arrival, "k--", label="theory transient (eqs 8, 12, 19)")
    ax1.set_ylabel("first-contact time [s]")
    ax1.legend(fontsize=8)
    v_th = local_speeds(run.theory_arrival, run.positions)
    ax2.plot(n[1:], v_th, "k--", label="theory transient")
    ax2.axhline(run.theory_speed, color="k", lw=0.8, label="eq 34 limit (mapped parameters)")
    if run.wave.settled:
        ax2.axhline(run.wave.speed, color="C3", label="DEM steady fit")
        ax2.axvspan(run.wave.first, run.wave.last, color="C3", alpha=0.1)
    ax2.set_xlabel("domino n")
    ax2.set_ylabel("local speed [m/s]")
    ax2.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    return path
