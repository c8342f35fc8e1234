"""Commands ``dominowave rods`` (one run of the hinged-domino model) and ``compare-rods``.

Dimensionless like ``dominowave theory``: ``l = g = m = 1``, so angular velocities are
in ``sqrt(g/l)``, times in ``sqrt(l/g)``, speeds in ``sqrt(g l)``, forces in ``m g``
and the stiffness is ``k / k*`` (the paper's per-particle ``k``; the contact spring of
the model is ``k/2``, eq 24).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from dominowave import theory
from dominowave.chain import theory_vs_rods as tvr
from dominowave.chain.wave import steady_speed, unsettled_reason
from dominowave.checks import check_in_range
from dominowave.cli.compiling import notice_if_compiling
from dominowave.cli.theory import parse_values
from dominowave.io.atomic import ensure_writable_dir
from dominowave.rods import first_collisions, simulate

__all__ = ["register"]

QUICK_D_OVER_L = "0.2,0.4,0.7"
QUICK_K_RATIO = "1e2,1e4"
MAX_PUSH = 100.0
"""Largest push of ``dominowave rods``, in units of the chain's steady Omega (eq 9)."""
MIN_D_OVER_L = 1e-3
"""Smallest gap d/l of ``dominowave rods``."""
FULL_D_OVER_L = "0.05,0.1,0.2,0.3,0.4,0.5,0.6,0.7,0.8,0.9,0.95"
FULL_K_RATIO = "1,1e2,1e4,1e6,1e8"

UNITS = (
    "dimensionless, l = g = m = 1: times in sqrt(l/g), angular velocities in sqrt(g/l), "
    "forces in m g, speeds in sqrt(g l), angles in rad; -: not defined"
)
"""The units of the tables of ``rods`` and ``compare-rods``, printed above them."""

Normal = Annotated[str, typer.Option(help="contact normal: geometric or head-on")]
Mass = Annotated[str, typer.Option(help="mass distribution: point, rod or block")]


def _fmt(x) -> str:
    if isinstance(x, bool | np.bool_):
        return "yes" if x else "no"
    if isinstance(x, int | np.integer):
        return str(int(x))
    if isinstance(x, str):
        return x
    return "-" if not math.isfinite(x) else f"{x:.4g}"  # "-": not defined (NaN)


def _print_table(header, rows) -> None:
    cells = [list(header)] + [[_fmt(v) for v in row] for row in rows]
    widths = [max(len(r[i]) for r in cells) for i in range(len(header))]
    for r in cells:
        typer.echo("  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)))


def rods_command(
    d_over_l: Annotated[float, typer.Option(help="gap / height d/l in [0.001, 1)")] = 0.4,
    stiffness_ratio: Annotated[float, typer.Option(help="paper's stiffness k/k*")] = 1e4,
    n: Annotated[int, typer.Option(help="number of dominoes")] = 40,
    push: Annotated[float, typer.Option(help="push of domino 1 [Omega, eq 9], (0, 100]")] = 1.0,
    normal: Normal = "geometric",
    mass_model: Mass = "point",
    s_over_l: Annotated[float, typer.Option(help="thickness s/l")] = 0.0,
    law: Annotated[str, typer.Option(help="linear or hertz")] = "linear",
    damping_ratio: Annotated[float, typer.Option(help="damping ratio zeta in [0, 1)")] = 0.0,
    friction_dominoes: Annotated[float, typer.Option(help="friction between dominoes")] = 0.0,
    gravity_in_contact: Annotated[
        bool, typer.Option(help="gravity acts during contacts (off = theory's assumption)")
    ] = True,
    rows: Annotated[int, typer.Option(help="collisions shown in the table")] = 15,
) -> None:
    """One run of the hinged-domino model: its collisions and wave speed (dimensionless)."""
    # Outside these ranges the run says nothing about a domino wave: a push far above
    # the chain's own steady Omega drives the first contacts through the dominoes, and
    # below d/l = 1e-3 Omega (~ l/d) and the collision rate outgrow any time step.
    check_in_range("push", push, 0.0, MAX_PUSH, hi_inclusive=True)
    check_in_range("d_over_l", d_over_l, MIN_D_OVER_L, 1.0, lo_inclusive=True)
    chain = tvr.paper_chain(
        d_over_l,
        stiffness_ratio,
        n,
        normal=normal,
        mass_model=mass_model,
        s_over_l=s_over_l,
        law=law,
        g=1.0,
        damping_ratio=damping_ratio,
        mu=friction_dominoes,
        gravity_in_contact=gravity_in_contact,
    )
    beta = math.asin(d_over_l)
    omega_lim = float(theory.omega_limit(beta, 1.0, 1.0))
    notice_if_compiling("rods")
    run = simulate(chain, push=push * omega_lim)
    col = first_collisions(run)
    header = (
        "n",
        "t_on",
        "T_coll",
        "F_peak",
        "Omega_fn",
        "Omega_bn",
        "Omega_n+1",
        "contacts",
        "theta_min",
        "|H|/V",
    )
    shown = range(min(rows, n - 1))
    typer.echo(UNITS)
    _print_table(
        header,
        [
            (
                i + 1,
                col.t_on[i],
                col.duration[i],
                col.peak_force[i],
                col.omega_f[i],
                col.omega_b[i],
                col.omega_next[i],
                col.n_contacts[i],
                col.rebound[i],
                col.hv_struck[i],
            )
            for i in shown
        ],
    )
    fit = steady_speed(run.arrival, run.positions)
    typer.echo(
        f"status: {run.status}; steps {run.n_steps} (dt = {run.dt:.3g}); "
        f"Omega (eq 9) = {omega_lim:.4g}"
    )
    if fit.settled:
        typer.echo(
            f"steady speed: {_fmt(fit.speed)} ± {fit.speed_err:.2g} sqrt(gl) "
            f"(settled from domino {fit.first + 1})"
        )
        return
    typer.echo(f"steady speed: not settled: {unsettled_reason(run.arrival, run.positions)}")
    if normal == "geometric" and damping_ratio == 0 and friction_dominoes == 0:
        typer.echo(NO_LIMIT_HINT)


NO_LIMIT_HINT = (
    "with the face-normal (geometric) contact and neither damping nor friction, each "
    "collision passes on the whole push (f+ -> 1), so the wave has no limit speed "
    "(docs/theory_vs_rods.md); --normal head-on is the theory's collision rule, "
    "--damping-ratio or --friction-dominoes let the wave settle"
)
"""Why the default rods run cannot settle, said beside its 'not settled'."""


def compare_rods_command(
    out: Annotated[Path, typer.Option(help="directory for CSV and PNG output")] = Path(
        "compare-rods"
    ),
    quick: Annotated[
        bool,
        typer.Option(help=f"small grid for CI: d/l {QUICK_D_OVER_L}, k/k* {QUICK_K_RATIO}, n 30"),
    ] = False,
    d_over_l: Annotated[str, typer.Option(help="d/l list or start:stop:count")] = FULL_D_OVER_L,
    stiffness_ratio: Annotated[
        str, typer.Option(help="k/k* list or start:stop:count")
    ] = FULL_K_RATIO,
    normal: Annotated[str, typer.Option(help="comma list of normals")] = "geometric,head-on",
    n: Annotated[int, typer.Option(help="dominoes per run")] = 60,
    gravity_in_contact: Annotated[
        bool, typer.Option(help="gravity acts during contacts (off = theory's assumption)")
    ] = True,
    workers: Annotated[int | None, typer.Option(help="processes (default: all cores)")] = None,
    scheduler: Annotated[
        str | None, typer.Option(help="address of an existing Dask scheduler (tcp://host:port)")
    ] = None,
) -> None:
    """Rod model vs theory over a (d/l, k/k*) grid (a resumable sweep): table, CSV, figures."""
    from dominowave.cli.chain import NOTHING_FINAL, exit_if_incomplete
    from dominowave.cli.workflow import check_cluster_options
    from dominowave.plots.compare_rods import plot_comparisons, plot_omega_profiles
    from dominowave.sweep import compare_rods as study

    ensure_writable_dir(out)  # before the runs, not after them
    check_cluster_options(workers, scheduler)
    notice_if_compiling("rods", by_workers=True)
    if quick:
        d_over_l, stiffness_ratio, n = QUICK_D_OVER_L, QUICK_K_RATIO, 30
    d_values = parse_values(d_over_l, "d_over_l")
    k_values = parse_values(stiffness_ratio, "stiffness_ratio", geometric=True)
    normals = tuple(x.strip() for x in normal.split(","))
    common = {"g": 1.0, "gravity_in_contact": gravity_in_contact}
    grid = study.comparison_points(d_values, k_values, normals, n=n, **common)
    # Fig 1D: Omega_n from pushes below and above the limit, both contact normals
    spacings = (0.6,) if quick else (0.3, 0.6)
    profiles = study.profile_points(
        normals, spacings, (0.5, 1.5), 1e6, 15 if quick else 40, **common
    )
    done = study.run_compare_rods(
        grid, profiles, out, workers=workers, scheduler=scheduler, quiet=False
    )
    header = (
        "normal",
        "k/k*",
        "d/l",
        "Tc/eq31",
        "F/eq37",
        "Om+/Omf",
        "f_+",
        "Omb/Omf",
        "f+/f-",
        "v",
        "v_end",
        "v_eq20",
        "v_P",
        "pair(th)",
        "overlap",
        "|H|/V>mu",
        "regime(th)",
        "status",
    )
    rows = [_table_row(c) for c in done.comparisons]
    typer.echo(UNITS)
    _print_table(header, rows)
    if any(r[9] == "not settled" for r in rows):
        typer.echo(
            "v not settled: the local speed has no settled stretch within the "
            f"{n} dominoes (still accelerating or slowing); v_end is the median local speed "
            "over the last 10 % of the chain"
        )
    typer.echo(done.run.report.line())
    if done.run.report.interrupted:  # a grid short of points would read as complete
        typer.echo(NOTHING_FINAL)
    elif done.comparisons:
        csv_path = study.write_csv(done.comparisons, out / "compare_rods.csv")
        pngs = plot_comparisons(done.comparisons, out)
        written = [str(csv_path)]
        if done.profiles:
            pngs.append(plot_omega_profiles(done.profiles, done.labels, out / "omega_n.png"))
            profile_csv = out / "omega_n.csv"
            written.append(str(study.write_profiles_csv(done.profiles, done.labels, profile_csv)))
        typer.echo(f"wrote {', '.join(written)} and {', '.join(str(p) for p in pngs)}")
    exit_if_incomplete(done.run)


def _table_row(c) -> tuple:
    """One row of the compare-rods table: the comparison's ratios and regimes."""
    return (
        c.normal,
        c.k_over_kstar,
        c.d_over_l,
        c.tc_first / c.tc_theory,
        c.f_first / c.fm_theory,
        c.transfer_first,
        c.f_plus,
        c.rebound_first,
        c.rebound_theory,
        c.speed if math.isfinite(c.speed) else "not settled",
        c.speed_end,
        c.speed_theory,
        c.speed_p_wave,
        c.pair_regime_theory,
        c.overlap_fraction,
        c.slip_fraction,
        c.regime_theory,
        c.status,
    )


def register(app: typer.Typer) -> None:
    """Add ``rods`` and ``compare-rods`` to the ``dominowave`` command line."""
    app.command("rods")(rods_command)
    app.command("compare-rods")(compare_rods_command)
