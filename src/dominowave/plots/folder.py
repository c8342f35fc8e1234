"""Figures of a sweep or run folder (``dominowave plot DIR``).

* ``speed_vs_spacing.png`` -- wave speed ``v / sqrt(g l)`` against ``d / l`` (McLachlan's
  scaling, eq 1) on a logarithmic axis that holds every point and curve (nothing is cut
  off): one marker per point (error bar if the scenario measured one; an open marker on
  the bottom edge for a point whose wave did not settle),
  the theory curve ``v^s`` (eq 34) for each group of points that differ only in
  spacing (dotted where collisions overlap, ``T < T_c/2``, outside the theory's
  range), and the rigid EJ curve (eq 14, thin dominoes) for reference;
* ``arrival_times.png`` -- domino index against its first-contact time;
* ``local_speed.png`` -- local speed ``(x_{n+1} - x_n) / (t_{n+1} - t_n)`` against the
  domino index, with the theory's limit speed as a dashed line.

Figures are drawn with matplotlib's object API (no pyplot, no display needed).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from dominowave.io.atomic import atomic_path, ensure_writable_dir
from dominowave.io.config import scenario_from_dict
from dominowave.io.results import read_events, read_summary, result_status
from dominowave.plots.unsettled import UNSETTLED_LABEL, mark_unsettled

__all__ = ["plot_folder"]

MAX_CURVES = 12
"""Points drawn at most in the per-point figures (arrival times, local speed)."""

_GROUP_IGNORE = {"spacing", "d_over_l", "n_frames", "n_dominoes", "push_omega", "asymmetry_seed"}


def _model(record: dict):
    """The validated scenario model of a record (cached in the record)."""
    if "model" not in record:
        record["model"] = scenario_from_dict(record["config"], str(record["folder"]))
    return record["model"]


def _records(folder: Path) -> list[dict]:
    """Result records of a sweep folder, or the single record of a run folder."""
    import tomllib

    if (folder / "index.json").is_file():
        from dominowave.sweep.collect import point_records

        return [r for r in point_records(folder) if r["status"] == "ok"]
    if result_status(folder) == "ok":
        config = tomllib.loads((folder / "config.toml").read_text())["scenario"]
        return [
            {
                "key": folder.name,
                "swept": {},
                "config": config,
                "summary": read_summary(folder),
                "folder": folder,
            }
        ]
    raise ValueError(f"{folder}: neither a sweep folder (index.json) nor a finished run")


def _label(record: dict) -> str:
    swept = record["swept"]
    return (
        ", ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}" for k, v in swept.items())
        or record["key"]
    )


def _swept_order(record: dict) -> list:
    """Sort key: the swept values, numbers numerically."""
    return [
        (0, v, "") if isinstance(v, int | float) else (1, 0, str(v))
        for v in record["swept"].values()
    ]


def _group_key(config: dict) -> tuple:
    return tuple(sorted((k, str(v)) for k, v in config.items() if k not in _GROUP_IGNORE))


def _save(fig, path: Path) -> Path:
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=120, bbox_inches="tight")
    return path


def _speed_figure(records: list[dict]):
    from matplotlib.figure import Figure

    from dominowave import theory

    fig = Figure(figsize=(6.4, 4.4))
    ax = fig.add_subplot()
    grid = np.linspace(0.02, 0.98, 300)
    groups: dict[tuple, list[dict]] = {}
    for r in records:
        groups.setdefault(_group_key(r["config"]), []).append(r)
    colours = iter(_palette(len(groups)))
    unsettled_label = UNSETTLED_LABEL
    by_stiffness = sorted(
        groups.values(), key=lambda g: g[0]["summary"].get("stiffness_over_kstar", math.inf)
    )
    for members in by_stiffness:
        colour = next(colours)
        first = members[0]
        scale = _model(first).speed_scale
        x = np.array([r["summary"]["d_over_l"] for r in members])
        y = np.array([r["summary"]["speed"] for r in members]) / scale
        err = np.array([r["summary"].get("speed_err", np.nan) for r in members]) / scale
        k_ratio = first["summary"].get("stiffness_over_kstar", math.inf)
        label = f"k/k* = {k_ratio:.3g}" if math.isfinite(k_ratio) else "rigid"
        ax.errorbar(
            x,
            y,
            yerr=np.where(np.isfinite(err), err, 0.0),
            fmt="o",
            color=colour,
            label=f"{first['config']['kind']} {label}",
        )
        if mark_unsettled(ax, x[~np.isfinite(y)], colour, unsettled_label):
            unsettled_label = None  # one legend entry for all groups
        curve = _model(first).theory_speed(grid) / scale
        valid = _model(first).theory_valid(grid)
        ax.plot(grid, np.where(valid, curve, np.nan), color=colour, lw=1)
        ax.plot(grid, np.where(valid, np.nan, curve), color=colour, lw=1, ls=":")
    ax.plot(grid, theory.mclachlan_G(grid), "k--", lw=1, label="rigid thin, EJ (eq 14)")
    ax.plot([], [], "k:", lw=1, label="theory where T < T_c/2 (outside its range)")
    ax.set_xlabel("spacing d / l")
    ax.set_ylabel("wave speed v / sqrt(g l)")
    ax.set_yscale("log")  # from slow wide gaps to fast narrow ones, none cut off
    ax.set_title("Wave speed: points = runs, lines = theory v^s (eq 34)", fontsize=10)
    ax.legend(fontsize=7)
    return fig


def _palette(n: int) -> list:
    from matplotlib import colormaps

    cmap = colormaps["viridis"]
    return [cmap(x) for x in np.linspace(0.0, 0.9, max(n, 1))]


def _per_point_figures(records: list[dict]):
    from matplotlib.figure import Figure

    from dominowave.chain.wave import local_speeds

    shown = records[:MAX_CURVES]
    arrival_fig, speed_fig = Figure(figsize=(6.4, 4.4)), Figure(figsize=(6.4, 4.4))
    ax_t, ax_v = arrival_fig.add_subplot(), speed_fig.add_subplot()
    for r, colour in zip(shown, _palette(len(shown)), strict=True):
        events = read_events(r["folder"])
        if "arrival_time" not in events:
            continue
        n = events.get("domino", np.arange(1, events["arrival_time"].size + 1))
        ax_t.plot(events["arrival_time"], n, ".-", color=colour, ms=3, label=_label(r))
        v = local_speeds(events["arrival_time"], events["position"])
        ax_v.plot(n[:-1] + 0.5, v, ".-", color=colour, ms=3, label=_label(r))
        limit = float(_model(r).theory_speed(r["summary"]["d_over_l"]))
        ax_v.axhline(limit, color=colour, ls="--", lw=0.8)
    ax_t.set_xlabel("first contact time t_n [s]")
    ax_t.set_ylabel("domino n")
    ax_t.set_title("Arrival-time diagram")
    ax_v.set_xlabel("domino n (between n and n+1)")
    ax_v.set_ylabel("local speed [m/s]")
    ax_v.set_title("Local wave speed (dashed: theory limit v^s, eq 34)")
    for ax in (ax_t, ax_v):
        ax.legend(fontsize=7)
    return arrival_fig, speed_fig


def plot_folder(folder: str | Path, out: str | Path | None = None) -> list[Path]:
    """Draw the three figures of ``folder`` into ``out`` (default ``folder/figures``)."""
    folder = Path(folder)
    if not folder.is_dir():
        raise ValueError(f"{folder}: no such folder")
    records = sorted(_records(folder), key=_swept_order)
    if not records:
        raise ValueError(f"{folder}: no successful points to plot")
    out = ensure_writable_dir(Path(out) if out is not None else folder / "figures")
    arrival, speed = _per_point_figures(records)
    return [
        _save(_speed_figure(records), out / "speed_vs_spacing.png"),
        _save(arrival, out / "arrival_times.png"),
        _save(speed, out / "local_speed.png"),
    ]
