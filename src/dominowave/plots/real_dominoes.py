"""Speed against pitch for the standard domino, beside every published measurement.

Reads the CSVs of the study ``docs/real_dominoes/speed_vs_pitch.py`` (no runs here):

* ``speed_vs_pitch_band.csv`` -- the prediction band (5 %, 50 %, 95 % quantiles over the
  material ranges, ``dominowave predict``) at each gap;
* ``speed_vs_pitch_models.csv`` -- one speed per (model, gap): ``dem3d``, ``dem3d_long``
  (a longer chain fitted from a later domino), ``dem2d``,
  ``rods``, ``rods_ideal``, ``transient`` (the theory's transient over the same dominoes),
  ``eq34_rigid``, ``eq34_tc``;
* ``speed_vs_pitch_theory.csv`` -- eq 34 (rigid and with the collision time) on a grid.

and every row of the measurements file (``dominowave.chain.measurements``, so rows added
later appear). Left panel: speed [m/s] against pitch ``d + s`` [mm] of the standard
domino; a measurement of the same domino size sits on it at its pitch (filled star);
one with the standard thickness but no published height sits there as if it were the
standard domino (open star, and the legend says so); one of a stated other size does
not (it is on the right panel); one of unstated size is drawn open at its own printed
spacing with a legend entry that says so. Right panel: ``v / sqrt(g l)`` against
``d / l``, where every measurement of known (or, open star, assumed) height sits beside
the standard domino's curves (geometric similarity assumed for another size: ``s/l`` and
the materials differ).

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
    "speeds_markdown",
]

STANDARD = {"height": 0.048, "thickness": 0.0075}
"""The standard domino's height and thickness [m] (``materials.toml``)."""
SAME_SIZE_TOLERANCE = 0.05
"""Relative difference of height and thickness within which a measured domino counts as
the standard one (so its speed can be read at its pitch on the standard axes)."""

MODEL_STYLE = {  # 2D drawn small over 3D: at the nominal values they nearly coincide
    "dem3d": dict(fmt="o", color="C0", ms=9, label="DEM 3D box, nominal values"),
    "dem3d_long": dict(
        fmt="o", color="C0", mfc="none", ms=9, label="DEM 3D box, nominal, long chain"
    ),
    "dem2d": dict(fmt="D", color="C2", ms=4, label="DEM 2D box, nominal values"),
    "rods": dict(fmt="^", color="C3", label="rod model (hinged, block inertia)"),
    "rods_ideal": dict(fmt="^", color="C3", mfc="none", label="rod model, frictionless elastic"),
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


def _close(a: float | None, b: float) -> bool:
    return a is not None and abs(a / b - 1.0) <= SAME_SIZE_TOLERANCE


def _same_size(m) -> bool:
    """The standard domino: height and thickness as published match it."""
    return _close(m.height, STANDARD["height"]) and _close(m.thickness, STANDARD["thickness"])


def _assumed_standard(m) -> bool:
    """Height not published, thickness the standard one: placed as a standard domino,
    an assumption every table and legend states."""
    return m.height is None and _close(m.thickness, STANDARD["thickness"])


def _interp(x: float, xs: np.ndarray, ys: np.ndarray) -> float:
    """Linear interpolation inside ``[min xs, max xs]``; NaN outside (no extrapolation)."""
    ok = np.isfinite(ys)
    xs, ys = xs[ok], ys[ok]
    if xs.size < 2 or not xs.min() <= x <= xs.max():
        return math.nan
    return float(np.interp(x, xs, ys))


def compare_measurements(study: StudyData, measurements=None) -> list[dict]:
    """Each measurement beside the band: one dict of strings per row of the file.

    ``how``: ``same domino`` (compared at its pitch); the standard thickness but no
    published height (compared at its pitch as a standard domino: :data:`ASSUMED`
    says so); another stated size (compared in ``v / sqrt(g l)`` at its ``d/l``); or
    why it cannot be compared. Computed only inside the computed gaps.
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
        elif _same_size(m) or _assumed_standard(m):
            how = "same domino" if _same_size(m) else ASSUMED
            q = tuple(_interp(m.pitch, band["pitch_m"], band[k]) for k in _Q)
        elif m.height is None:
            how = "not comparable: domino size not stated"
        elif m.gap is None:
            how = "not comparable: thickness not stated (pitch basis)"
        else:
            how = SCALED
            own = math.sqrt(G_STANDARD * m.height)
            q = tuple(
                own * _interp(m.gap / m.height, band["d_over_l"], band[k] / scale) for k in _Q
            )
        if how in ("same domino", ASSUMED, SCALED) and not np.isfinite(q[1]):
            how += ": outside the computed gaps"
        lo, mid, hi = q
        ok = np.isfinite(mid)
        out.append(
            {
                "key": m.key,
                "l_m": "n/a" if m.height is None else f"{m.height:.4g}",
                "floor": m.floor,
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
ASSUMED = "height not stated, taken as 48 mm (thickness standard)"
SCALED = "scaled in d/l (other size)"


def comparison_markdown(table: list[dict]) -> str:
    """The comparison as a Markdown table (columns as in :func:`compare_measurements`)."""
    if not table:
        return "(no measurements)"
    columns = list(table[0])
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    lines += ["| " + " | ".join(r[c] for c in columns) + " |" for r in table]
    return "\n".join(lines)


def speeds_markdown(study: StudyData) -> str:
    """The speeds of the figure's left panel as a Markdown table, one row per gap [m/s]."""
    gaps = sorted(
        {round(float(g), 9) for col in study.models.values() for g in col["gap_m"]}
        | {round(float(g), 9) for g in study.band.get("gap_m", [])}
    )
    names = [n for n in (*MODEL_STYLE, "eq34_tc", "eq34_rigid") if n in study.models]
    head = ["gap d [mm]", "pitch [mm]", "d/l", "band 5-95 %", "median", *names]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]

    def at(col, gap, key):
        hit = np.isclose(col["gap_m"], gap, rtol=0, atol=1e-9) if col else np.array([])
        return float(col[key][hit][0]) if hit.any() else math.nan

    def fmt(v):
        return "n/a" if not np.isfinite(v) else f"{v:.3g}"

    for gap in gaps:
        lo, mid, hi = (at(study.band, gap, k) for k in _Q)
        cells = [f"{1e3 * gap:g}", f"{1e3 * (gap + STANDARD['thickness']):g}"]
        band = f"{fmt(lo)} - {fmt(hi)}" if np.isfinite(mid) else "n/a"
        cells += [f"{gap / study.height:.3f}", band, fmt(mid)]
        cells += [fmt(at(study.models[n], gap, "speed_m_s")) for n in names]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _model_points(ax, study: StudyData, x_key: str, x_scale: float, v_scale: float):
    for name, style in MODEL_STYLE.items():
        col = study.models.get(name)
        if not col:
            continue
        style = dict(style)
        if name == "dem3d_long":  # say how long and from where it is fitted
            n, k = int(col["n_dominoes"][0]), int(col["fit_from"][0])
            style["label"] += f" ({n} dominoes, fit from {k})"
        err = col.get("speed_err_m_s", np.zeros_like(col["speed_m_s"]))
        ax.errorbar(
            col[x_key] * x_scale,
            col["speed_m_s"] / v_scale,
            yerr=np.nan_to_num(err) / v_scale,
            fmt=style.pop("fmt"),
            ms=style.pop("ms", 6),
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
    assumed = [m for m in rows if _assumed_standard(m)]
    unsized = [m for m in rows if m.height is None and not _assumed_standard(m)]
    other = [m for m in rows if m.height is not None and m.gap is not None and not _same_size(m)]
    groups = (  # (rows, marker, open, label), each on both panels where it can be placed
        (same, "*", False, "measured, standard domino"),
        (assumed, "*", True, "measured, standard thickness, height not stated (taken 48 mm)"),
        (other, "P", False, "measured, another stated size (right panel only)"),
    )
    for group, marker, hollow, label in groups:
        if not group:
            continue
        style = dict(fmt=marker, ms=10 if marker == "*" else 8, color="C4", label=label)
        if hollow:
            style["mfc"] = "none"
        heights = [m.height or STANDARD["height"] for m in group]
        if group is not other:
            ax1.errorbar(
                [1e3 * m.pitch for m in group],
                [m.speed for m in group],
                yerr=[m.speed_unc or 0.0 for m in group],
                **style,
            )
        ax2.errorbar(
            [m.gap / h for m, h in zip(group, heights, strict=True)],
            [m.speed / math.sqrt(G_STANDARD * h) for m, h in zip(group, heights, strict=True)],
            yerr=[
                (m.speed_unc or 0.0) / math.sqrt(G_STANDARD * h)
                for m, h in zip(group, heights, strict=True)
            ],
            **style,
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
    no_gap = [m for m in rows if m.height is not None and m.gap is None]
    left_out = len(unsized) + len(no_gap)
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
