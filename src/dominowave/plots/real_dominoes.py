"""Speed against pitch for the standard domino, beside every published measurement.

Reads the CSVs of the study ``docs/real_dominoes/speed_vs_pitch.py`` (no runs here):

* ``speed_vs_pitch_band.csv`` -- the prediction band (5 %, 50 %, 95 % quantiles over the
  material ranges, ``dominowave predict``) at each gap;
* ``speed_vs_pitch_models.csv`` -- one speed per (model, gap): ``dem3d``, ``dem2d``,
  ``rods``, ``transient`` (the theory's transient over the same dominoes),
  ``eq34_rigid``, ``eq34_tc``;
* ``speed_vs_pitch_theory.csv`` -- eq 34 (rigid and with the collision time) on a grid.

and every row of the measurements file (``dominowave.chain.measurements``, so rows added
later appear). Left panel: speed [m/s] against pitch ``d + s`` [mm] of the standard
domino; a measurement of the same domino size sits on it at its pitch, one of a stated
other size does not (it is on the right panel), one of unstated size is drawn open at
its own printed spacing with a legend entry that says so. Right panel: ``v / sqrt(g l)``
against ``d / l``, where every measurement of known height sits beside the standard
domino's curves (geometric similarity assumed: ``s/l`` and the materials differ).

:func:`compare_measurements` sets each measurement beside the band (interpolated
linearly between the computed gaps, never extrapolated): the % difference of the
band's median and whether the measurement lies in the band.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from dominowave.units import G_STANDARD

__all__ = [
    "SAME_SIZE_TOLERANCE",
    "StudyData",
    "compare_measurements",
    "comparison_markdown",
    "plot_speed_vs_pitch",
    "read_study",
]

STANDARD = {"height": 0.048, "thickness": 0.0075}
"""The standard domino's height and thickness [m] (``materials.toml``)."""
SAME_SIZE_TOLERANCE = 0.05
"""Relative difference of height and thickness within which a measured domino counts as
the standard one (so its speed can be read at its pitch on the standard axes)."""

MODEL_STYLE = {
    "dem3d": dict(fmt="o", color="C0", label="DEM 3D box, nominal values"),
    "dem2d": dict(fmt="D", color="C2", label="DEM 2D box, nominal values"),
    "rods": dict(fmt="^", color="C3", label="rod model (hinged, block inertia)"),
    "transient": dict(fmt="s", color="k", mfc="none", label="theory transient, same dominoes"),
}


@dataclass
class StudyData:
    """The study's tables as columns (numpy arrays, SI units), sorted by gap.

    ``band`` keys of ``speed_vs_pitch_band.csv``; ``models`` model name -> its columns;
    ``theory`` columns of ``speed_vs_pitch_theory.csv``; ``height`` [m] of the domino.
    """

    band: dict[str, np.ndarray]
    models: dict[str, dict[str, np.ndarray]]
    theory: dict[str, np.ndarray]
    height: float = STANDARD["height"]


def _columns(rows: list[dict], skip=("model", "note", "floor")) -> dict[str, np.ndarray]:
    rows = sorted(rows, key=lambda r: float(r["gap_m"]))
    keys = [k for k in (rows[0] if rows else {}) if k not in skip]
    return {k: np.array([float(r[k]) for r in rows]) for k in keys}


def _read(path: Path) -> list[dict]:
    if not path.exists():
        return []
    with path.open(encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def read_study(folder) -> StudyData:
    """The three CSVs of the study in ``folder`` (a missing file gives empty columns)."""
    folder = Path(folder)
    models = {}
    for row in _read(folder / "speed_vs_pitch_models.csv"):
        models.setdefault(row["model"], []).append(row)
    return StudyData(
        band=_columns(_read(folder / "speed_vs_pitch_band.csv")),
        models={name: _columns(rows) for name, rows in models.items()},
        theory=_columns(_read(folder / "speed_vs_pitch_theory.csv")),
    )


def _same_size(m) -> bool:
    if m.height is None or m.thickness is None:
        return False
    return (
        abs(m.height / STANDARD["height"] - 1.0) <= SAME_SIZE_TOLERANCE
        and abs(m.thickness / STANDARD["thickness"] - 1.0) <= SAME_SIZE_TOLERANCE
    )


def _interp(x: float, xs: np.ndarray, ys: np.ndarray) -> float:
    """Linear interpolation inside ``[min xs, max xs]``; NaN outside (no extrapolation)."""
    ok = np.isfinite(ys)
    xs, ys = xs[ok], ys[ok]
    if xs.size < 2 or not xs.min() <= x <= xs.max():
        return math.nan
    return float(np.interp(x, xs, ys))


def compare_measurements(study: StudyData, measurements=None) -> list[dict]:
    """Each measurement beside the band: one dict of strings per row of the file.

    ``how``: ``same domino`` (compared at its pitch), ``scaled`` (another stated size:
    compared in ``v / sqrt(g l)`` at its ``d/l``), or why it cannot be compared.
    ``median_m_s`` and the band are the prediction at the measurement's spacing (in m/s
    of the measured domino); ``diff_pct`` is ``(median - measured) / measured``.
    """
    from dominowave.chain.measurements import load_measurements

    band = study.band
    scale = math.sqrt(G_STANDARD * study.height)
    out = []
    for m in load_measurements(measurements):
        q = (math.nan,) * 3
        if not band:
            how = "no band computed"
        elif m.height is None:
            how = "not comparable: domino size not stated"
        elif m.gap is None:
            how = "not comparable: thickness not stated (pitch basis)"
        elif _same_size(m):
            how = "same domino"
            q = tuple(_interp(m.pitch, band["pitch_m"], band[k]) for k in _Q)
        else:
            how = "scaled in d/l (other size)"
            own = math.sqrt(G_STANDARD * m.height)
            q = tuple(
                own * _interp(m.gap / m.height, band["d_over_l"], band[k] / scale) for k in _Q
            )
        if how in ("same domino", "scaled in d/l (other size)") and not np.isfinite(q[1]):
            how += ": outside the computed gaps"
        lo, mid, hi = q
        ok = np.isfinite(mid)
        out.append(
            {
                "key": m.key,
                "l_m": "n/a" if m.height is None else f"{m.height:.4g}",
                "spacing_m": f"{m.spacing:.4g} ({m.spacing_basis})",
                "measured_m_s": f"{m.speed:.3g}",
                "kind": m.speed_kind,
                "how": how,
                "median_m_s": f"{mid:.3g}" if ok else "n/a",
                "band_m_s": f"{lo:.3g} - {hi:.3g}" if ok else "n/a",
                "diff_pct": f"{100.0 * (mid - m.speed) / m.speed:+.0f}" if ok else "n/a",
                "in_band": ("yes" if lo <= m.speed <= hi else "no") if ok else "n/a",
            }
        )
    return out


_Q = ("q05_m_s", "q50_m_s", "q95_m_s")


def comparison_markdown(table: list[dict]) -> str:
    """The comparison as a Markdown table (columns as in :func:`compare_measurements`)."""
    if not table:
        return "(no measurements)"
    columns = list(table[0])
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    lines += ["| " + " | ".join(r[c] for c in columns) + " |" for r in table]
    return "\n".join(lines)


def _model_points(ax, study: StudyData, x_key: str, x_scale: float, v_scale: float):
    for name, style in MODEL_STYLE.items():
        col = study.models.get(name)
        if not col:
            continue
        style = dict(style)
        err = col.get("speed_err_m_s", np.zeros_like(col["speed_m_s"]))
        ax.errorbar(
            col[x_key] * x_scale,
            col["speed_m_s"] / v_scale,
            yerr=np.nan_to_num(err) / v_scale,
            fmt=style.pop("fmt"),
            ms=6,
            capsize=2,
            lw=1,
            **style,
        )
        dead = ~np.isfinite(col["speed_m_s"])
        if dead.any():  # a wave that died or a run that failed: no speed, a cross at the foot
            ax.plot(
                col[x_key][dead] * x_scale,
                np.full(int(dead.sum()), 0.03),
                "x",
                color=style["color"],
                transform=ax.get_xaxis_transform(),
                label=f"{name}: no speed (wave died / run failed)",
            )


def _band(ax, study: StudyData, x_key: str, x_scale: float, v_scale: float):
    band = study.band
    if not band:
        return
    x = band[x_key] * x_scale
    ax.fill_between(
        x,
        band["q05_m_s"] / v_scale,
        band["q95_m_s"] / v_scale,
        color="C1",
        alpha=0.3,
        lw=0,
        label="prediction, 5-95 % band (material ranges)",
    )
    ax.plot(x, band["q50_m_s"] / v_scale, "-", color="C1", marker=".", label="prediction, median")


def _theory(ax, study: StudyData, x_key: str, x_scale: float, v_scale: float):
    th = study.theory
    if not th:
        return
    x = th[x_key] * x_scale
    ax.plot(x, th["eq34_rigid_m_s"] / v_scale, "k-", lw=1, label="eq 34, rigid limit")
    ax.plot(x, th["eq34_tc_m_s"] / v_scale, "k--", lw=1, label="eq 34 with the box's T_c")


def plot_speed_vs_pitch(study: StudyData, out, measurements=None) -> Path:
    """Write the two-panel figure (see the module docstring) to ``out`` (PNG); returns it."""
    from dominowave.chain.measurements import load_measurements

    rows = load_measurements(measurements)
    l = study.height
    scale = math.sqrt(G_STANDARD * l)
    fig = Figure(figsize=(12.0, 7.0))
    ax1, ax2 = fig.subplots(1, 2)
    for ax, x_key, x_scale, v_scale in ((ax1, "pitch_m", 1e3, 1.0), (ax2, "d_over_l", 1.0, scale)):
        _band(ax, study, x_key, x_scale, v_scale)
        _theory(ax, study, x_key, x_scale, v_scale)
        _model_points(ax, study, x_key, x_scale, v_scale)
    same = [m for m in rows if _same_size(m)]
    unsized = [m for m in rows if m.height is None]
    sized = [m for m in rows if m.height is not None and m.gap is not None]
    if same:
        ax1.errorbar(
            [1e3 * m.pitch for m in same],
            [m.speed for m in same],
            yerr=[m.speed_unc or 0.0 for m in same],
            fmt="*",
            ms=10,
            color="C4",
            label="measured, standard domino",
        )
    if unsized:
        ax1.plot(
            [1e3 * m.spacing for m in unsized],
            [m.speed for m in unsized],
            "v",
            mfc="none",
            color="C5",
            ms=8,
            label="measured, domino size not stated (at its printed spacing)",
        )
    for group, marker, label in (
        ([m for m in sized if _same_size(m)], "*", "measured, standard domino"),
        ([m for m in sized if not _same_size(m)], "P", "measured, another stated size"),
    ):
        if not group:
            continue
        ax2.errorbar(
            [m.gap / m.height for m in group],
            [m.speed / math.sqrt(G_STANDARD * m.height) for m in group],
            yerr=[(m.speed_unc or 0.0) / math.sqrt(G_STANDARD * m.height) for m in group],
            fmt=marker,
            ms=10 if marker == "*" else 8,
            color="C4",
            label=label,
        )
    left_out = len(rows) - len(sized)
    if left_out:
        ax2.text(
            0.02,
            0.02,
            f"{left_out} measurement(s) without a stated height or gap: not placeable in d/l",
            transform=ax2.transAxes,
            fontsize=7,
        )
    ax1.set_xlabel("pitch d + s [mm] (standard domino, s = 7.5 mm)")
    ax1.set_ylabel("front speed [m/s]")
    ax1.set_title("standard 48 x 24 x 7.5 mm domino", fontsize=10)
    ax2.set_xlabel("d / l")
    ax2.set_ylabel("v / sqrt(g l)")
    ax2.set_title("dimensionless (measurements of any stated height)", fontsize=10)
    for ax in (ax1, ax2):
        ax.set_yscale("log")
        ax.grid(alpha=0.3, which="both")
    handles = {}
    for ax in (ax1, ax2):  # one legend for both panels, below them
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            handles.setdefault(label, handle)
    fig.tight_layout(rect=(0.0, 0.14, 1.0, 1.0))
    fig.legend(handles.values(), handles.keys(), loc="lower center", ncol=3, fontsize=8)
    out = Path(out)
    fig.savefig(out, dpi=110)
    return out
