"""The leaning train beside the paper's rigid limit and the filmed real chains.

For the standard 48 x 7.5 mm domino: the steady speed of the leaning train
(:mod:`dominowave.theory.leaning`) at several frictions between dominoes, the paper's
eq 34 in the rigid limit (elastic pair collisions, ``T_c = 0``) and the high-speed films
shipped in ``chain/data/measurements.csv`` (their height is not published; 48 mm, the
standard domino's, is assumed as everywhere in the package).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from dominowave import theory as th
from dominowave.chain.measurements import load_measurements
from dominowave.theory import leaning

__all__ = ["FRICTIONS", "HEIGHT", "THICKNESS", "leaning_figure"]

HEIGHT, THICKNESS = 0.048, 0.0075  # the standard toppling domino [m]
FRICTIONS = (0.0, 0.1, 0.3, 0.525)  # 0.525: the handbook nominal of materials.toml
_COLOURS = ("tab:blue", "tab:cyan", "tab:green", "tab:olive")
_FILMS = {"hardwood": ("s", "tab:brown"), "felt": ("o", "tab:purple")}


def _films():
    """(gap [m], speed [m/s], floor) of the asymptotic film speeds of standard dominoes."""
    rows = []
    for m in load_measurements():
        if m.speed_kind == "asymptotic" and m.thickness and abs(m.thickness - THICKNESS) < 1e-4:
            rows.append((m.gap, m.speed, m.floor))
    return rows


def leaning_figure(out: Path) -> list[Path]:
    """``leaning.png`` and ``leaning.csv``: front speed [m/s] against the gap [mm]."""
    lower, upper = leaning.gap_limits(HEIGHT, THICKNESS, 0.0, xtol=1e-7)
    gaps = np.linspace(max(lower, 5e-4) * 1.001, upper * 0.999, 160)
    speeds = leaning.limit_speed(
        height=HEIGHT, thickness=THICKNESS, gap=gaps[:, None], friction=np.array(FRICTIONS)
    )
    beta = np.arcsin(gaps / HEIGHT)
    rigid = th.wave_speed_rigid(beta, HEIGHT) * (gaps + THICKNESS) / gaps  # eq 34, T_c = 0
    fig = Figure(figsize=(6.4, 4.6), layout="constrained")
    ax = fig.add_subplot()
    ax.plot(1e3 * gaps, rigid, color="tab:red", lw=1.6, label="paper eq 34, rigid (elastic pairs)")
    columns = {"gap_m": gaps, "eq34_rigid_m_s": rigid}
    for j, (mu, colour) in enumerate(zip(FRICTIONS, _COLOURS, strict=True)):
        ax.plot(
            1e3 * gaps, speeds[:, j], color=colour, lw=1.6, label=f"leaning train, $\\mu$ = {mu:g}"
        )
        columns[f"leaning_mu{mu:g}_m_s"] = speeds[:, j]
    for floor, (marker, colour) in _FILMS.items():
        pts = [(gap, v) for gap, v, f in _films() if f == floor]
        if pts:
            g_mm, v = 1e3 * np.array(pts).T[0], np.array(pts).T[1]
            ax.plot(g_mm, v, marker, color=colour, ms=5, mfc="none", label=f"films, {floor}")
    ax.axvline(1e3 * upper, color="grey", lw=0.6, ls=":")
    ax.text(1e3 * upper, 0.25, " dominoes\n lie flat", fontsize=7, color="grey")
    ax.set_ylim(0.0, 2.5)
    ax.set_xlabel("clear gap $d$ [mm] (48 x 7.5 mm dominoes)")
    ax.set_ylabel("front speed [m/s]")
    ax.set_title("Leaning train (inelastic, friction $\\mu$ between dominoes)")
    ax.legend(fontsize=7, loc="upper right")
    png, csv = out / "leaning.png", out / "leaning.csv"
    fig.savefig(png, dpi=130)
    data = np.column_stack(list(columns.values()))
    np.savetxt(csv, data, delimiter=",", header=",".join(columns), comments="", fmt="%.17g")
    return [png, csv]
