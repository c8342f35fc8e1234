"""Figures of the rods-vs-theory study (``dominowave compare-rods``, docs/theory_vs_rods.md).

The data are :class:`~dominowave.chain.theory_vs_rods.Comparison` rows (one per grid
point) and :class:`~dominowave.chain.theory_vs_rods.OmegaProfile` runs, as the study
:mod:`dominowave.sweep.compare_rods` returns them. Speeds are shown as ``v / sqrt(g l)``,
durations and forces as ratios to the theory's ``T_c`` (eq 31) and ``F_m`` (eq 37).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from dominowave import theory
from dominowave.plots.unsettled import UNSETTLED_LABEL, mark_unsettled

__all__ = ["plot_comparisons", "plot_omega_profiles"]


def _grouped(comparisons):
    """``{(normal, k/k*): sorted list of comparisons over d/l}``."""
    groups: dict[tuple[str, float], list] = {}
    for c in comparisons:
        groups.setdefault((c.normal, c.k_over_kstar), []).append(c)
    return {key: sorted(v, key=lambda c: c.d_over_l) for key, v in sorted(groups.items())}


def plot_comparisons(comparisons, out_dir) -> list[Path]:
    """Write the comparison figures (PNG) into ``out_dir``; returns their paths.

    ``collision.png``: T_c and F_m measured/theory; ``collision_map.png``: transfer and
    rebound ratios with f_+ and f_+/f_-; ``speed.png``: speed measured, eq 20/34, the
    rigid EJ speed and the P-wave bound, all vs d/l.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    groups = _grouped(comparisons)
    styles = {"geometric": "-", "head-on": "--"}
    paths = []

    def values(group, name):
        return np.array([getattr(c, name) for c in group], dtype=float)

    def plot_measured(axes, *ratios):
        """Each group's measured ``(name, over)`` ratios against d/l, a ratio a panel
        (``over`` None: the value itself)."""
        for (normal, k_ratio), group in groups.items():
            x = values(group, "d_over_l")
            label = f"{normal}, k/k*={k_ratio:g}"
            for ax, (name, over) in zip(axes, ratios, strict=True):
                y = values(group, name)
                if over is not None:
                    y = y / values(group, over)
                ax.plot(x, y, styles[normal], marker="o", label=label)

    def save(fig, name):
        fig.tight_layout()
        paths.append(out_dir / name)
        fig.savefig(paths[-1], dpi=120)

    fig = Figure(figsize=(10, 4))
    axes = fig.subplots(1, 2)
    plot_measured(axes, ("tc_first", "tc_theory"), ("f_first", "fm_theory"))
    axes[0].set_ylim(0.0, 2.5)  # k/k* <= 100 at extreme d/l goes beyond (see the CSV)
    axes[1].set_ylim(0.0, 1.5)
    axes[0].set_ylabel("measured duration / T_c (eq 31)")
    axes[1].set_ylabel("measured peak force / F_m (eq 37)")
    for ax in axes:
        ax.axhline(1.0, color="k", lw=0.5)
        ax.set_xlabel("d/l")
    axes[0].legend(fontsize=6)
    save(fig, "collision.png")

    fig = Figure(figsize=(10, 4))
    axes = fig.subplots(1, 2)
    grid = np.linspace(0.02, 0.98, 200)
    beta = np.arcsin(grid)
    f_p = theory.f_plus(beta)
    axes[0].plot(grid, f_p, "k", lw=2, label="f_+ (eq 4)")
    axes[1].plot(grid, f_p / theory.f_minus(beta), "k", lw=2, label="f_+/f_- (eq 3)")
    plot_measured(axes, ("transfer_first", None), ("rebound_first", None))
    axes[0].set_ylim(-0.05, 1.3)  # k/k* = 1 (no collisions in any useful sense) goes beyond
    axes[0].set_ylabel("Omega_{n+1} / Omega_fn")
    axes[1].set_ylabel("Omega_bn / Omega_fn")
    for ax in axes:
        ax.set_xlabel("d/l")
    axes[0].legend(fontsize=6)
    save(fig, "collision_map.png")

    fig = Figure(figsize=(7, 5))
    ax = fig.subplots()
    unsettled_label = UNSETTLED_LABEL
    for (normal, k_ratio), group in groups.items():
        x = values(group, "d_over_l")
        scale = values(group, "speed_scale")
        speed = values(group, "speed") / scale
        (line,) = ax.plot(
            x,
            speed,
            styles[normal],
            marker="o",
            label=f"rods {normal}, k/k*={k_ratio:g}",
        )
        if mark_unsettled(ax, x[~np.isfinite(speed)], line.get_color(), unsettled_label):
            unsettled_label = None  # one legend entry for all groups
        ax.plot(
            x,
            values(group, "speed_end") / scale,
            styles[normal],
            marker="x",
            color=line.get_color(),
            alpha=0.5,
        )
        if normal == "geometric":
            ax.plot(
                x,
                values(group, "speed_theory") / scale,
                ":",
                color=line.get_color(),
                label=f"eq 20/34, k/k*={k_ratio:g}",
            )
    ax.plot(grid, theory.mclachlan_G(grid), "k", label="rigid EJ (eq 14)")
    for k_ratio in sorted({c.k_over_kstar for c in comparisons}):
        group = [c for c in groups.get(("geometric", k_ratio), groups.get(("head-on", k_ratio)))]
        ax.plot(
            values(group, "d_over_l"),
            values(group, "speed_p_wave") / values(group, "speed_scale"),
            color="grey",
            lw=0.8,
            alpha=0.6,
        )
    ax.plot([], [], color="grey", lw=0.8, label="P-wave bound (eq 33/35)")
    ax.set_yscale("log")
    ax.set_xlabel("d/l")
    ax.set_ylabel("v / sqrt(g l)  (o settled fit, x last 10 %)")
    ax.legend(fontsize=6)
    save(fig, "speed.png")
    return paths


def plot_omega_profiles(profiles, labels, path) -> Path:
    """Plot ``Omega_n / Omega`` measured (markers) and eq 8 (lines) for several runs."""
    fig = Figure(figsize=(7, 4.5))
    ax = fig.subplots()
    for profile, label in zip(profiles, labels, strict=True):
        n = np.arange(1, profile.measured.size + 1)
        (line,) = ax.plot(n, profile.measured / profile.omega_limit, "o", ms=3, label=label)
        ax.plot(n, profile.theory / profile.omega_limit, "-", color=line.get_color())
    ax.set_xlabel("domino n")
    ax.set_ylabel("Omega_n / Omega (markers: rods, lines: eq 8)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=120)
    return path
