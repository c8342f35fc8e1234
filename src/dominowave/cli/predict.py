"""Command ``dominowave predict``: a real chain's front speed with the band of its materials.

Inputs in SI units (the gap in metres). Bad input raises ``ValueError`` (one line, exit 2).
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from dominowave.chain.fidelity import DEFAULT_TOLERANCE
from dominowave.cli.compiling import notice_if_compiling
from dominowave.io.atomic import ensure_writable_dir

__all__ = ["register"]

PRESETS = ("standard",)
"""Domino presets: ``standard`` is :func:`dominowave.chain.presets.standard_domino`."""


def _fmt(x: float, digits: int = 3) -> str:
    return "-" if not math.isfinite(x) else f"{x:.{digits}g}"


def _contact_line(pred) -> str:
    """The contact springs the chains ran with and the largest estimated speed error."""
    from dominowave.chain.fidelity import MAX_RESTITUTION, tolerance_of

    kn = pred.contact_kn[np.isfinite(pred.contact_kn)]
    springs = f"k_n {_fmt(kn.min())}-{_fmt(kn.max())} N/m" if kn.size else "no chain ran"
    tolerance = tolerance_of(pred.fidelity)
    if tolerance is None:
        return f"contacts: the plastic's (fidelity exact), {springs}"
    softened = int(np.count_nonzero(pred.stiffness_error > 0))
    return (
        f"contacts softened for speed (fidelity {tolerance:g}) in {softened} of"
        f" {pred.speed.size} chains (the others, with a restitution above"
        f" {MAX_RESTITUTION}, keep the plastic's): {springs}; estimated speed error of the"
        f" softening at most {_fmt(100 * pred.stiffness_error_max, 2)} % (--fidelity exact:"
        " the plastic's everywhere)"
    )


def predict_command(
    gap: Annotated[float, typer.Option(help="clear gap d between neighbours [m]")],
    floor: Annotated[str, typer.Option(help="named floor: felt, glass, hardwood, laminate")],
    preset: Annotated[str, typer.Option(help="domino preset (standard: 48 x 24 x 7.5 mm)")] = (
        "standard"
    ),
    samples: Annotated[
        int,
        typer.Option(help="Saltelli base size N (power of 2): N (D + 2) runs, D the inputs varied"),
    ] = 4,
    n: Annotated[int, typer.Option("--n", help="dominoes in each chain")] = 12,
    fit_from: Annotated[int, typer.Option(help="first domino of the front speed's fit")] = 3,
    seed: Annotated[int, typer.Option(help="scramble seed of the Sobol' sequence")] = 0,
    model: Annotated[str, typer.Option(help="3d | 2d")] = "3d",
    fidelity: Annotated[
        str | None,
        typer.Option(
            help="exact (the plastic's contact) or a tolerance of the speed: each chain runs"
            f" with the softest contact within it [default {DEFAULT_TOLERANCE:g}]"
        ),
    ] = None,
    out: Annotated[Path, typer.Option(help="sweep folder (re-run to resume)")] = Path("predict"),
    workers: Annotated[int | None, typer.Option(help="processes (default min(2, cores))")] = None,
    scheduler: Annotated[
        str | None, typer.Option(help="address of an existing Dask scheduler (tcp://host:port)")
    ] = None,
) -> None:
    """Predict the front speed of a real chain with the band of its material data."""
    from dominowave.chain.fidelity import parse_fidelity
    from dominowave.chain.reconcile import reconcile_lines
    from dominowave.cli.chain import exit_if_incomplete
    from dominowave.cli.workflow import check_cluster_options
    from dominowave.sweep.predict import SOBOL_MIN_BASE, predict, predict_points

    if preset not in PRESETS:
        raise ValueError(f"--preset {preset!r} is not one of {', '.join(PRESETS)}")
    if model not in ("2d", "3d"):
        raise ValueError(f"--model {model!r} is not one of '2d', '3d'")
    check_cluster_options(workers, scheduler)
    tolerance = parse_fidelity(fidelity)
    ensure_writable_dir(out)
    console = Console(width=120)
    start = time.perf_counter()
    # the chains checked are the chains run: bad input (samples, fit_from, gap, floor)
    # fails here, before the compile notice
    chains = dict(n_dominoes=n, fit_from=fit_from, seed=seed, model=model, fidelity=tolerance)
    predict_points(gap, floor, samples, **chains)
    if scheduler is None:
        from dominowave.chain.build import ChainParams
        from dominowave.chain.scenario import scene_kind

        notice_if_compiling(scene_kind(ChainParams(shape="box", model=model)), by_workers=True)

    def progress(row):
        console.print(
            f"  sample {row['sample']}: v = {_fmt(row['speed'], 4)} m/s"
            f" ({row['dominoes_toppled']} toppled, {row['wall_time']:.1f} s)"
        )

    pred = predict(
        gap, floor, out, samples, **chains, workers=workers, scheduler=scheduler, progress=progress
    )
    console.print(pred.run.report.line())
    if pred.n_missing:
        console.print(
            f"{pred.n_missing} of {pred.speed.size} points did not run: no prediction written"
            f" (the finished points are kept in {out}; re-run the same command to resume)"
        )
        exit_if_incomplete(pred.run)
        sys.exit(1)  # not interrupted, yet points missing: never report them as a result
    lo, mid, hi = pred.band
    console.print(
        f"predicted front speed ({preset} domino, gap {gap:g} m, {floor}, from domino"
        f" {fit_from} of {n}, pitch-based): median {_fmt(mid, 4)} m/s, 90 % band"
        f" [{_fmt(lo, 4)}, {_fmt(hi, 4)}] m/s, mean {_fmt(pred.mean, 4)} m/s over"
        f" {pred.speed.size - pred.n_died - pred.n_failed} of {pred.speed.size} runs"
        + (f" ({pred.n_died} waves died before the end)" if pred.n_died else "")
        + (f" ({pred.n_failed} runs failed: see failure.json)" if pred.n_failed else "")
    )
    console.print(_contact_line(pred))
    lean_lo, lean_mid, lean_hi = pred.leaning_band
    console.print(
        f"leaning train (inelastic, rigid, theory.leaning) at the same samples' friction:"
        f" median {_fmt(lean_mid, 4)} m/s, 90 % band [{_fmt(lean_lo, 4)}, {_fmt(lean_hi, 4)}]"
        " m/s (milliseconds a sample)"
    )
    for line in reconcile_lines(mid, gap=gap, floor=floor, model=model, label="median"):
        console.print(escape(line))
    table = Table(  # escaped: rich would read "[m/s]" as markup
        title=escape(
            "sensitivity of the speed: change over each value's range [m/s];"
            f" Sobol' indices ± 95 % confidence (from --samples {SOBOL_MIN_BASE} on)"
        )
    )
    for header in ("value", "range", "effect [m/s]", "first order S1", "total ST"):
        table.add_column(escape(header), justify="right")
    for j, name in enumerate(pred.names):
        lo_v, hi_v = pred.bounds[j]
        table.add_row(
            name,
            f"{lo_v:.3g} .. {hi_v:.3g}",
            _fmt(pred.effect[j], 2),
            f"{_fmt(pred.sobol_first[j], 2)} ± {_fmt(pred.sobol_first_conf[j], 2)}",
            f"{_fmt(pred.sobol_total[j], 2)} ± {_fmt(pred.sobol_total_conf[j], 2)}",
        )
    console.print(table)
    console.print(
        "the band is the spread the material ranges allow (several are assumptions:"
        " docs/real_dominoes.md), not a measurement's confidence interval; few samples"
        " give rough indices (see their confidence)"
    )
    console.print(
        f"wrote {out}/samples.csv, samples.nc, prediction.csv in"
        f" {time.perf_counter() - start:.1f} s"
    )
    exit_if_incomplete(pred.run)


def register(app: typer.Typer) -> None:
    """Add ``predict`` to the ``dominowave`` app."""
    app.command("predict")(predict_command)
