"""Theory figures of the paper: Fig 1D, Fig 4A, Fig 4B and Fig 5B (and the leaning train).

Each figure is computed in dimensionless form (``l = g = m = 1``, hence ``k* = 1`` and
``k = k/k*``), written as a PNG (matplotlib's Agg canvas, no display needed) and as a
CSV of exactly the plotted data. Stiffnesses are the paper's per-particle ``k``
(convention ``"paper"``, ``k_r = k/2``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure
from matplotlib.patches import Patch

from dominowave import theory as th
from dominowave.plots.leaning import leaning_figure

__all__ = ["FIGURES", "fig1d", "fig4", "fig5b", "write_all"]

# Paper's parameters
FIG1D_BETAS = (0.4, 0.7, 1.0)  # rad; convergence speeds up with beta (section 2.1)
FIG1D_PUSH = (0.5, 1.5)  # Omega_1 / Omega, below and above the limit
FIG4_K_RATIOS = (1.0, 1e4, 1e8)  # k / k*
FIG4_THICKNESS = 0.1  # s / l of Fig 4B
FIG5B_K_RATIOS = (1.0, 10.0, 100.0)
FIG5B_MU, FIG5B_THICKNESS = 0.3, 0.1

_K_COLOURS = ("tab:green", "tab:orange", "tab:purple")


def _ratio_tag(ratio: float) -> str:
    """``1 -> "1"``, ``1e4 -> "1e4"``, ``100 -> "1e2"``: for column names and labels."""
    return "1" if ratio == 1 else f"{ratio:.0e}".replace("e+0", "e").replace("e+", "e")


def _stiffness_label(ratio: float) -> str:
    return "$k$ = $k^*$" if ratio == 1 else f"$k$ = {_ratio_tag(ratio)} $k^*$"


def _write_csv(path: Path, columns: dict[str, np.ndarray]) -> None:
    data = np.column_stack([np.asarray(v, dtype=float) for v in columns.values()])
    np.savetxt(path, data, delimiter=",", header=",".join(columns), comments="", fmt="%.17g")


def _save(fig: Figure, out: Path, name: str, columns: dict[str, np.ndarray]) -> list[Path]:
    png, csv = out / f"{name}.png", out / f"{name}.csv"
    fig.savefig(png, dpi=130)
    _write_csv(csv, columns)
    return [png, csv]


def fig1d(out: Path) -> list[Path]:
    """Fig 1D: Omega_n (eq 8) against n for three beta, pushes below and above Omega."""
    n = np.arange(1, 81)
    fig = Figure(figsize=(6.4, 4.4), layout="constrained")
    ax = fig.add_subplot()
    columns: dict[str, np.ndarray] = {"n": n}
    for beta, colour in zip(FIG1D_BETAS, _K_COLOURS, strict=True):
        limit = th.omega_limit(beta, 1.0, 1.0)
        ax.axhline(limit, color=colour, lw=0.8, ls=":")
        for ratio, marker in zip(FIG1D_PUSH, ("o", "s"), strict=True):
            omega = np.sqrt(th.omega_n_squared(n, ratio * limit, beta, 1.0, 1.0))
            label = rf"$\beta$ = {beta:g}, $\Omega_1$ = {ratio:g} $\Omega$"
            ax.plot(n, omega, marker=marker, ms=2.5, lw=1, color=colour, label=label)
            columns[f"omega_beta{beta:g}_push{ratio:g}"] = omega
        columns[f"omega_limit_beta{beta:g}"] = np.full(n.shape, limit)
    ax.set_xlabel("domino number $n$")
    ax.set_ylabel(r"$\Omega_n$  [$\sqrt{g/l}$ = 1]")
    ax.set_title(r"Fig 1D: $\Omega_n$ (eq 8) converges to $\Omega$ (eq 9, dotted)")
    ax.legend(fontsize=7, ncol=2)
    return _save(fig, out, "fig1d", columns)


def fig4(out: Path, thick: bool) -> list[Path]:
    """Fig 4A (thin, eqs 20, 33) or 4B (s/l = 0.1, eqs 34, 35): v / sqrt(g l) against beta.

    Solid where the pair-collision regime ``T > T_c/2`` holds, thin dotted where it does
    not (eq 20 is then outside its validity); dashed: P-wave speeds.
    """
    s = FIG4_THICKNESS if thick else 0.0
    beta = np.geomspace(1e-3, np.pi / 2 - 1e-3, 400)
    d = np.sin(beta)
    fig = Figure(figsize=(6.4, 4.8), layout="constrained")
    ax = fig.add_subplot()
    v_rigid = th.wave_speed_rigid(beta, 1.0, 1.0) * (d + s) / d
    ax.plot(beta, v_rigid, color="tab:red", lw=2, label=r"$k = \infty$ (EJ)")
    columns = {"beta": beta, "d_over_l": d, "v_rigid": v_rigid}
    for ratio, colour in zip(FIG4_K_RATIOS, _K_COLOURS, strict=True):
        v = th.wave_speed_thick(beta, 1.0, 1.0, ratio, s, 1.0)
        v_w = th.p_wave_speed_thick(beta, 1.0, 1.0, ratio, s)
        pair = th.pair_regime_holds(beta, 1.0, 1.0, ratio, 1.0)
        label, tag = _stiffness_label(ratio), _ratio_tag(ratio)
        ax.plot(beta, np.where(pair, v, np.nan), color=colour, lw=1.6, label=label)
        ax.plot(beta, np.where(pair, np.nan, v), color=colour, lw=0.8, ls=":")
        ax.plot(beta, v_w, color=colour, lw=1, ls="--", label=f"P-wave, {label}")
        columns |= {f"v_k{tag}": v, f"vw_k{tag}": v_w, f"pair_k{tag}": pair}
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_ylim(1e-2 if thick else 1e-4, 3e4)
    ax.set_xlabel(r"collision angle $\beta = \arcsin(d/l)$  [rad]")
    if thick:
        ax.set_ylabel(r"$v^s / \sqrt{g l}$")
        ax.set_title(rf"Fig 4B: thick dominoes, $s/l$ = {s:g} (eqs 34, 35)")
    else:
        ax.set_ylabel(r"$v / \sqrt{g l}$")
        ax.set_title("Fig 4A: thin dominoes (eqs 14, 20, 33)")
    ax.plot([], [], color="grey", lw=0.8, ls=":", label=r"outside pair regime ($T < T_c/2$)")
    ax.legend(fontsize=7, loc="lower left")
    return _save(fig, out, "fig4b" if thick else "fig4a", columns)


def fig5b(out: Path) -> list[Path]:
    """Fig 5B: regimes of Fig 5A in the (beta, F_m/mg) plane, with F_m (eq 37) in blue.

    Hatched: the base slides (eq 39) but the paper's eqs 38, 41, 42 do not say how the
    block moves; shaded there by :func:`dominowave.theory.sliding_rotation_sign`.
    """
    mu, s_over_l = FIG5B_MU, FIG5B_THICKNESS
    beta = np.linspace(0.01, np.pi / 2 - 0.005, 600)
    force = np.geomspace(1e-2, 1e3, 400)
    regimes = th.classify_regime(beta[None, :], force[:, None], mu, s_over_l)
    colours = ("#e8f4e8", "#fde2c8", "#f8d0d8", "#dcd4f0")
    fig = Figure(figsize=(6.8, 4.8), layout="constrained")
    ax = fig.add_subplot()
    ax.pcolormesh(beta, force, regimes.code, cmap=ListedColormap(colours), vmin=0.5, vmax=4.5)
    # hatched: the base slides (eq 39) but eqs 38, 41, 42 leave the motion open; decided
    # by the signed moment balance of a sliding block (sliding_rotation_sign)
    open_set = (~regimes.by_paper).astype(float)
    ax.contourf(beta, force, open_set, levels=[0.5, 1.5], colors="none", hatches=["////"])
    b = th.regime_boundaries(beta, mu, s_over_l)
    ax.plot(beta, b.rotation, "k-", lw=1, label="eq 38 (rotation)")
    ax.plot(beta, b.sliding, "k--", lw=1, label="eq 39 (sliding)")
    ax.plot(beta, b.friction_moment, "k-.", lw=1, label="eq 41 (friction moment)")
    ax.plot(beta, b.toppling, "k:", lw=1.2, label=r"eq 42 (toppling, $\cos^2\beta$)")
    columns = {
        "beta": beta,
        "rotation_eq38": b.rotation,
        "sliding_eq39": b.sliding,
        "friction_moment_eq41": b.friction_moment,
        "toppling_eq42": b.toppling,
    }
    for ratio, lw in zip(FIG5B_K_RATIOS, (1.0, 1.6, 2.2), strict=True):
        fm = th.peak_contact_force(beta, 1.0, 1.0, ratio, 1.0)  # = F_m / (m g)
        ax.plot(beta, fm, color="tab:blue", lw=lw, label=f"$F_m/mg$, {_stiffness_label(ratio)}")
        columns[f"fm_over_mg_k{_ratio_tag(ratio)}"] = fm
        on_curve = th.classify_regime(beta, fm, mu, s_over_l)
        columns[f"regime_k{_ratio_tag(ratio)}"] = on_curve.code
        columns[f"by_paper_k{_ratio_tag(ratio)}"] = on_curve.by_paper
    ax.axvline(np.pi / 3, color="grey", lw=0.6)
    ax.set_yscale("log")
    ax.set_ylim(force[0], force[-1])
    ax.set_xlim(0, np.pi / 2)
    ax.set_xlabel(
        r"collision angle $\beta$  [rad]  (contact below centre of mass for $\beta > \pi/3$)"
    )
    ax.set_ylabel(r"$F_m / (m g)$")
    ax.set_title(rf"Fig 5B: base-slip regimes, $\mu$ = {mu:g}, $s/l$ = {s_over_l:g}")
    handles, _ = ax.get_legend_handles_labels()
    handles += [Patch(color=c, label=th.REGIME_NAMES[i + 1]) for i, c in enumerate(colours)]
    handles.append(
        Patch(facecolor="white", edgecolor="grey", hatch="////", label="not classified by paper")
    )
    ax.legend(handles=handles, fontsize=6.5, loc="upper left", ncol=2)
    return _save(fig, out, "fig5b", columns)


FIGURES = {
    "fig1d": fig1d,
    "fig4a": lambda out: fig4(out, thick=False),
    "fig4b": lambda out: fig4(out, thick=True),
    "fig5b": fig5b,
    "leaning": leaning_figure,  # beyond the paper: the leaning train and the films
}


def write_all(out) -> list[Path]:
    """Write every theory figure (PNG + CSV) into directory ``out`` (created if needed)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    return [path for make in FIGURES.values() for path in make(out)]
