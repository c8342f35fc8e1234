"""Commands ``dominowave chain`` (one DEM domino chain or an ensemble) and ``paper-fig6``.

Physical inputs are SI except where named otherwise: the push is given in units of
``sqrt(g/l)``, the stiffness as the paper's ``k/k*``. Tables show speeds in m/s and
as ``v / sqrt(g l)``. Bad input raises ``ValueError`` (one line, exit code 2).
"""

from __future__ import annotations

import csv
import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from dominowave.chain.build import ChainParams
from dominowave.chain.fidelity import parse_fidelity
from dominowave.chain.scenario import ChainEnsemble, ChainRun, DominoChain, Push, scene_kind
from dominowave.chain.settings import ChainSettings, numerics
from dominowave.chain.wave import check_fit_from, fit_speed, local_speeds, unsettled_reason
from dominowave.cli.compiling import notice_if_compiling
from dominowave.cli.declared import (
    PanelledCommand,
    option_error,
    option_name,
    parameter_options,
    with_options,
)
from dominowave.io.atomic import ensure_writable_dir
from dominowave.params import parameter, parameter_specs, text
from dominowave.theory import Regime
from dominowave.units import speed_scale

__all__ = ["register"]

REGIME_SHORT = {0: "-", 1: "rot", 2: "fwd+slip", 3: "back+slip", 4: "transl"}


def _domino_rows(run: ChainRun) -> list[dict]:
    ev = run.events.table()
    n = run.arrival.size
    v = np.concatenate([[np.nan], local_speeds(run.arrival, run.positions)])
    rows = []
    for k in range(n):
        row = {"domino": k, "x": run.positions[k], "theory_arrival": run.theory_arrival[k]}
        row["local_speed"] = v[k]
        row.update({name: col[k] for name, col in ev.items()})
        rows.append(row)
    return rows


def _write_csv(path: Path, rows: list[dict]) -> None:
    with path.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def _fmt(x, digits=4) -> str:
    if isinstance(x, float | np.floating):
        return "nan" if not math.isfinite(x) else f"{x:.{digits}g}"
    return str(x)


def _cell(x) -> str:
    """A table cell: "-" where the quantity is not defined (NaN), never "nan"."""
    if isinstance(x, float | np.floating) and not math.isfinite(x):
        return "-"
    return _fmt(x)


def _speed_cell(speed: float) -> str:
    """``v=... m/s``, or "not settled" for a member whose wave found no steady speed."""
    return f"v={_fmt(speed)} m/s" if math.isfinite(speed) else "v not settled"


ONE_RUN_ERROR = (
    "(± is the fit's standard error over this one run's dominoes, not the spread of the"
    " speed between runs: a chain is chaotic, --members 8 gives an ensemble's)"
)
SLIP_NOTE = (
    "slip: the base's displacement along the chain at the end of the run (negative:"
    " backwards); domino 0 has no neighbour behind it, so the chain's rebounds push it"
    " back the furthest"
)
COLUMNS_NOTE = (
    "hits on n+1: collisions of domino n with the next (contacts closer than the collision"
    " time merged), in passage: those that begin before the wave reaches n+2 (more than one:"
    " the paper's multiple collisions, Fig 6E); Fig 5A: the motion right after the first"
    " hit, rot (about the base edge, the base at rest), fwd+slip or back+slip (rotation"
    " with the base sliding; the top ahead of or behind the base), transl (translation)"
)
SLIPPING = (Regime.FORWARD_ROTATION_SLIP, Regime.BACKWARD_ROTATION_SLIP, Regime.TRANSLATION)
"""The Fig 5A mechanisms in which the base slides."""


def _percent(value: float, reference: float) -> str:
    """``value`` against ``reference`` as a signed percentage, e.g. ``+6.6 %``."""
    return f"{100.0 * (value / reference - 1.0):+.1f} %"


def _print_unsettled(console: Console, run: ChainRun, scale: float) -> None:
    """Say that no steady speed exists in this chain, and what can be compared instead.

    Near f_+ = 1 (small d/l) the transient lasts longer than a short chain, so the local
    speed is still changing at its end: the limit speed is not measurable here. The
    mean speed over the last third of the reached dominoes, for the simulation and for
    the theory's transient on the same dominoes, is the fair comparison.
    """
    reached = int(np.count_nonzero(np.isfinite(run.arrival)))
    last = reached - 1
    first = max(1, last - max(reached // 3, 2))
    console.print(
        f"steady speed: not settled: {unsettled_reason(run.arrival, run.positions)}; "
        "compare the arrival times with the theory's transient (t_theory)"
    )
    if last - first >= 2:
        sim = fit_speed(run.arrival, run.positions, first, last)
        th = fit_speed(run.theory_arrival, run.positions, first, last)
        console.print(
            f"mean speed over dominoes {first}..{last}: {_fmt(sim.speed)} ± "
            f"{_fmt(sim.speed_err, 2)} m/s (v/sqrt(gl) = {_fmt(sim.speed / scale)}); "
            f"theory transient over the same dominoes: {_fmt(th.speed)} m/s"
            f" ({_percent(sim.speed, th.speed)} from it)"
        )
        console.print(ONE_RUN_ERROR)


def _cut_short_note(run: ChainRun, max_time: float, member: int | None) -> str:
    """Say that a run ended at its ``max_time`` with the wave still on its way."""
    who = "the run" if member is None else f"member {member}"
    return (
        f"[yellow]{who} {run.cut_short_text(max_time)}[/yellow], before it reached the last"
        " domino or went quiet: the speeds above are of the dominoes reached (in Python:"
        " DominoChain(params, max_time=...))"
    )


def _unsettled(ens: ChainEnsemble) -> str:
    """The members an ensemble speed leaves out, said beside it."""
    failed = ens.speed.n_failed
    if not failed:
        return ""
    return f" ({failed} of {failed + ens.speed.n} members did not settle and are left out)"


def _limit_assumes(run: ChainRun) -> str:
    """What eq 34 assumes, and how many bases of this run slid (Fig 5A)."""
    mechanism = run.events.mechanism
    hit = int(np.count_nonzero(mechanism))
    slid = int(np.count_nonzero(np.isin(mechanism, SLIPPING)))
    return (
        "eq 34 is the theory's limit for an infinite chain whose bases turn about their"
        " edge without sliding, each collision lasting T_c at this stiffness (clump"
        f" mapping: docs/chain.md); here {slid} of the {hit} bases hit slid (Fig 5A)"
    )


def _in_transient(run: ChainRun, preset: str | None) -> bool:
    """Whether to say that the wave settled where, by the theory, it is still in its
    transient (ChainRun.settled_in_transient): for a chain of the paper's model, not for
    a preset of real dominoes, whose wave is a leaning train (theory.leaning, compared
    below it) that the paper's transient does not describe."""
    return preset is None and run.settled_in_transient


def _transient_note(run: ChainRun) -> str:
    """Say that by the theory the fitted dominoes are still in the wave's transient."""
    w = run.wave
    gap = 100.0 * run.theory_window_gap
    side = "below" if gap < 0 else "above"
    return (
        f"by the theory the wave is still in its transient over dominoes {w.first}..{w.last}:"
        f" its speed there is {abs(gap):.1f} % {side} the limit (eq 34), more than the fit's"
        " error; the settled stretch may be one plateau of the staircase of an undamped chain"
        ' (docs/chain.md, "Speed jumps"): a longer chain tells'
    )


def _what_to_quote(run: ChainRun, ens: ChainEnsemble | None, in_transient: bool) -> str:
    """One sentence: which of the printed speeds to quote, and why the others differ;
    ``in_transient``: the wave settled where, by the theory, it is still in its transient
    (:func:`_in_transient`)."""
    limit = _limit_assumes(run)
    if ens is not None and ens.speed.n >= 2:
        return (
            "quote the ensemble speed with its standard error: one run's speed depends on "
            f"chaotic details of its collisions; {limit}"
        )
    if in_transient:
        w = run.wave
        return (
            f"quote the steady speed as the speed over dominoes {w.first}..{w.last}, beside"
            " the theory's transient over the same dominoes: by the theory the wave has not"
            f" reached its limit there; {limit}"
        )
    if run.wave.settled:
        return (
            "quote the steady speed: the wave's own speed once it no longer changes along "
            f"the chain; the transient theory is for the same dominoes, {limit}"
        )
    return (
        "quote the mean speed over the last dominoes beside the theory's transient over the "
        f"same dominoes: this chain is too short for the wave to settle; {limit}"
    )


def _quoted_speed(run: ChainRun, fit) -> float:
    """The speed to compare with a measurement [m/s]: ``fit``, the fit from ``--fit-from``
    on, where given (as the films are fitted), else the steady speed; NaN if the wave did
    not settle."""
    chosen = run.wave if fit is None else fit
    return chosen.speed if chosen.settled else math.nan


OPTION_NAMES = {
    "n_dominoes": "n",
    "lateral_asymmetry": "asymmetry",
    "asymmetry_seed": "placement_seed",
}
"""The ChainParams fields whose option is not the field's name (``--n``, ...)."""

PANELS = {
    "shape": "The domino",
    "contact": "Contact law",
    "layout": "The chain",
    "placement": "Placement errors",
}
"""Help panel of each concern (``group``) of the ChainParams fields."""

SET_BY_PRESET = (
    "height",
    "thickness",
    "width",
    "density",
    "d_over_l",
    "stiffness_ratio",
    "kn",
    "young",
    "friction_floor",
    "friction_dominoes",
    "restitution",
    "restitution_dominoes",
    "restitution_floor",
)
"""The ChainParams fields ``--preset standard`` sets itself (with ``--gap``, ``--floor``)."""


def _preset_params(preset, gap, floor, fields: dict) -> ChainParams:
    """``ChainParams`` of ``--preset standard --gap --floor`` and the other ``fields``
    given; a field the preset sets itself may not be given too (one error naming them)."""
    from dominowave.chain.presets import standard_domino

    if preset is None:  # (RunOptions checked its value)
        raise ValueError("--gap and --floor need --preset standard")
    if gap is None or floor is None:
        raise ValueError("--preset standard needs --gap [m] and --floor (felt, glass, ...)")
    # an option given is refused even when it equals the chain's default (the preset
    # would override it)
    clash = [option_name(k, OPTION_NAMES) for k in SET_BY_PRESET if k in fields]
    if clash:
        raise ValueError(
            f"{', '.join(clash)}: set by --preset standard from materials.toml, give not both"
        )
    return standard_domino(gap=gap, floor=floor, **fields)


@dataclass(frozen=True)
class RunOptions(ChainSettings):
    """The options of ``dominowave chain`` besides the chain's own (``ChainParams``): the
    numerics and the preset (those of a study file, ``chain.settings.ChainSettings``), the
    push, the ensemble and the output, declared once (:mod:`dominowave.params`) and
    checked when made; each is an option of the same name
    (:func:`~dominowave.cli.declared.parameter_options`).  ``push`` is in units of
    ``sqrt(g/l)``, where a study file and ``chain_members.csv`` give ``push_omega`` in
    rad/s."""

    push: float = parameter(
        1.0, "sqrt(g/l)", "push: domino 0's angular velocity", gt=0, group="push"
    )
    impulse: float | None = parameter(
        None, "N s", "push as impulse (not set: --push)", gt=0, group="push"
    )
    impulse_height: float | None = parameter(
        None,
        "m",
        "height of the impulse (not set: the top sphere's centre, a box's top - s/2)",
        gt=0,
        group="push",
    )
    members: int = parameter(1, "", "ensemble members (perturbed pushes)", ge=1, group="ensemble")
    seed: int = parameter(0, "", "ensemble seed", ge=0, group="ensemble")
    jitter: float = parameter(1e-3, "", "relative push perturbation", ge=0, group="ensemble")
    vary_placement: bool = parameter(
        False, "", "each member set up anew (own placement errors)", group="ensemble"
    )
    fit_from: int | None = parameter(
        None,
        "",
        "fit the front speed from this domino on (pitch-based, as cameras do; 1 to n - 2,"
        " checked with the chain; not set: over the settled dominoes)",
        group="output",
    )
    out: Path | None = text("directory for CSV + PNG (not set: none written)", group="output")


def chain_command(**fields) -> None:
    """Run one DEM domino chain (or an ensemble): per-domino table, speed vs theory, plot.

    The options of the domino, the contact, the chain and its placement errors are the
    fields of ChainParams (dominowave.chain), with its defaults; those of the numerics,
    the preset, the push, the ensemble and the output are the fields of RunOptions.
    """
    given = {name: value for name, value in fields.items() if value is not None}
    if "fidelity" in given:  # (text on the command line: "exact" or a number)
        given["fidelity"] = parse_fidelity(given["fidelity"])
    try:  # (an error names the option given, not the field it sets)
        options = RunOptions(**{k: given.pop(k) for k in RUN_OPTIONS if k in given})
        preset, gap, floor = options.preset, options.gap, options.floor
        if preset is not None or gap is not None or floor is not None:
            p = _preset_params(preset, gap, floor, given)
        else:
            p = ChainParams(**given)
        fit_from = options.fit_from
        if fit_from is not None:
            check_fit_from(fit_from, p.n_dominoes)
        chain = DominoChain(p, **numerics(options))  # (its checks of sizes and the step)
    except ValueError as exc:
        raise option_error(exc, fields, OPTION_NAMES) from None
    out = options.out
    if out is not None:
        ensure_writable_dir(out)  # before the run, not after it
    n = p.n_dominoes
    d_over_l = p.d_over_l

    if options.impulse is not None:
        push = Push(impulse=options.impulse, height=options.impulse_height)
    else:
        push = Push(omega=options.push * math.sqrt(p.g / p.height))
    compiling = notice_if_compiling(scene_kind(p))
    start = time.perf_counter()
    ens = None
    if options.members > 1:
        ens = chain.ensemble(
            push,
            members=options.members,
            seed=options.seed,
            jitter=options.jitter,
            fit_from=fit_from,
            vary_placement=options.vary_placement,
        )
    run = ens.runs[0] if ens is not None else chain.run(push)
    wall = time.perf_counter() - start
    console = Console(width=140)
    scale = float(speed_scale(p.height, p.g))
    table = Table(
        title=f"domino chain: N={n}, d/l={d_over_l:.4g}, k/k*={p.stiffness_over_kstar:.3g}",
        caption="-: not defined (domino 0 has no local speed, the last domino no rebound)"
        f" or not reached by the wave; {SLIP_NOTE}; {COLUMNS_NOTE}",
    )
    cols = {
        "domino": "n",
        "arrival": "t_arr [s]",
        "theory_arrival": "t_theory [s]",
        "local_speed": "v_local [m/s]",
        "n_hits_on_next": "hits on n+1",
        "n_hits_in_passage": "hits in passage",
        "slip_final": "slip [m]",
        "max_forward": "max tilt [rad]",
        "rebound_angle": "rebound [rad]",
        "mechanism": "Fig 5A",
    }
    for header in cols.values():  # escaped: rich would read "[s]" as strike-through markup
        table.add_column(escape(header), justify="right")
    rows = _domino_rows(run)
    for r in rows:  # (the contact and its error estimate are the run's, on every row)
        r.update(run.contact_columns)
        cells = [_cell(r[c]) for c in cols]
        cells[-1] = REGIME_SHORT[int(r["mechanism"])]
        table.add_row(*cells)
    console.print(table)
    w = run.wave
    if w.settled:
        console.print(
            f"steady speed: {_fmt(w.speed)} ± {_fmt(w.speed_err, 2)} m/s "
            f"(v/sqrt(gl) = {_fmt(w.speed / scale)}; settled over dominoes {w.first}..{w.last})"
        )
        if ens is None:
            console.print(ONE_RUN_ERROR)
    else:
        _print_unsettled(console, run, scale)
    for i, r in enumerate([run] if ens is None else ens.runs):
        if r.cut_short:
            console.print(_cut_short_note(r, chain.max_time, None if ens is None else i))
    fit = None if fit_from is None else chain.speed_from(run, fit_from)
    if fit is not None:
        console.print(
            f"front speed from domino {fit_from} on (pitch-based): {_fmt(fit.speed)} ± "
            f"{_fmt(fit.speed_err, 2)} m/s over dominoes {fit.first}..{fit.last}"
            if fit.settled
            else f"front speed from domino {fit_from} on: the wave reached {fit.reached} dominoes"
        )
    if ens is not None:
        how = "settled-region fit" if fit_from is None else f"fit from domino {fit_from} on"
        console.print(
            f"ensemble ({options.members} members, {how}): {ens.speed} m/s{_unsettled(ens)}"
        )
        for i, r in enumerate(ens.runs):
            if not r.wave.settled:
                reason = unsettled_reason(r.arrival, r.positions)
                console.print(f"  member {i} not settled: {reason}")
    window = (
        f"; transient theory on the same dominoes: {_fmt(run.theory_window_speed)} m/s"
        f" (the steady speed is {_percent(w.speed, run.theory_window_speed)} from it)"
        if w.settled
        else ""
    )
    console.print(
        f"theory: limit speed eq 34 (clump mapping) {_fmt(run.theory_speed)} m/s{window}; "
        f"measured push Omega_1 = {_fmt(run.omega_1)} rad/s"
    )
    in_transient = _in_transient(run, preset)
    if in_transient:
        console.print(_transient_note(run))
    if run.secondary is not None and run.secondary.catching_up:
        merged = run.secondary.merged_pair
        where = "not merged within the chain" if merged is None else f"merged at pair {merged}"
        console.print(f"secondary wave catching up; {where}")
    console.print(_what_to_quote(run, ens, in_transient))
    if preset is not None:
        from dominowave.chain.reconcile import reconcile_lines  # (the leaning train: scipy)

        quoted = ens.speed.mean if ens is not None else _quoted_speed(run, fit)
        lines = reconcile_lines(
            quoted, gap=gap, floor=floor, model=p.model, friction=p.friction_dominoes
        )
        for line in lines:
            console.print(escape(line))
    if run.fidelity is not None:
        console.print(run.fidelity.describe(run.stiffness_error))
    note = " (including compiling the kernels)" if compiling else ""
    console.print(f"dt = {run.dt:.3g} s, {run.n_steps} steps, wall {wall:.2f} s{note}")
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        _write_csv(out / "chain_dominoes.csv", rows)
        if ens is not None:
            _write_csv(
                out / "chain_members.csv",
                [
                    {
                        "member": i,
                        "push_omega": r.omega_1,
                        "speed": f.speed,
                        "speed_err": f.speed_err,
                        "settled": f.settled,
                        **r.contact_columns,
                    }
                    for i, (r, f) in enumerate(zip(ens.runs, ens.fits, strict=True))
                ],
            )
        from dominowave.plots.chain import plot_chain_run

        plot_chain_run(run, ens, out / "chain.png")
        console.print(f"wrote {out}/chain_dominoes.csv, chain.png")


RUN_OPTIONS = tuple(parameter_specs(RunOptions))
"""The options of ``chain`` that are not ChainParams fields."""

with_options(
    chain_command,
    parameter_options(ChainParams, renamed=OPTION_NAMES, panels=PANELS)
    + parameter_options(RunOptions),
)


def paper_fig6_command(
    out: Annotated[Path, typer.Option(help="output directory")] = Path("fig6"),
    quick: Annotated[bool, typer.Option(help="small preset for CI")] = False,
    shape: Annotated[
        str, typer.Option(help="domino shape: clump (of spheres, the paper's) | box")
    ] = "clump",
    workers: Annotated[int | None, typer.Option(help="processes (default min(2, cores))")] = None,
    scheduler: Annotated[
        str | None, typer.Option(help="address of an existing Dask scheduler (tcp://host:port)")
    ] = None,
) -> None:
    """Reproduce the paper's Fig 6 B-E (a resumable DEM sweep): PNG + CSV in --out.

    --shape box runs every configuration with rounded-cuboid dominoes (docs/shape.md).
    """
    from dominowave.chain.paper_fig6 import CONFIGS
    from dominowave.cli.workflow import check_cluster_options
    from dominowave.plots.fig6 import plot_fig6
    from dominowave.sweep.fig6 import (
        FULL,
        FULL_BOX,
        QUICK,
        QUICK_BOX,
        RUNS_CSV,
        read_rows,
        run_fig6,
        summarise,
        write_summary,
    )

    if shape not in ("clump", "box"):
        raise ValueError(f"shape = {shape!r} is not one of 'clump', 'box'")
    ensure_writable_dir(out)
    check_cluster_options(workers, scheduler)
    # each worker process loads (or compiles) them: the kernels of every configuration
    kinds = {scene_kind(ChainParams(shape=shape, **c)) for c in CONFIGS.values()}
    notice_if_compiling(*kinds, by_workers=True)

    if shape == "box":
        preset = QUICK_BOX if quick else FULL_BOX
    else:
        preset = QUICK if quick else FULL
    console = Console()
    start = time.perf_counter()

    def progress(row):
        console.print(
            f"  {row['config']:>10} d/l={row['d_over_l']:.2f} member {row['member']}: "
            f"{_speed_cell(row['speed'])} ({row['wall_time']:.1f} s)"
        )

    done = run_fig6(preset, out, workers=workers, scheduler=scheduler, progress=progress)
    console.print(done.report.line())
    rows = read_rows(out / RUNS_CSV)
    if done.report.interrupted:  # ensembles short of members would read as complete
        console.print(NOTHING_FINAL)
    elif rows:
        summary = summarise(rows)
        write_summary(summary, out / "summary.csv")
        written = plot_fig6(summary, out)
        console.print(
            f"paper-fig6 ({preset.name}): {len(summary)} ensembles in "
            f"{time.perf_counter() - start:.1f} s; wrote {', '.join(p.name for p in written)}"
        )
    exit_if_incomplete(done)


NOTHING_FINAL = (
    "interrupted: no summary or figure written (they would rest on some of the points);"
    " the finished points are kept, re-run the same command to resume and write them"
)


def exit_if_incomplete(done) -> None:
    """Exit 130/143 after a signal (re-run to resume), 1 if points failed."""
    if done.report.interrupted:
        typer.echo("dominowave: interrupted; finished points are kept, re-run to resume", err=True)
        sys.exit(done.report.interrupted)
    if done.failed:
        typer.echo(
            f"{len(done.failed)} point(s) failed: see failure.json in their folders", err=True
        )
        sys.exit(1)


def register(app: typer.Typer) -> None:
    """Add ``chain`` and ``paper-fig6`` to the ``dominowave`` app."""
    app.command("chain", cls=PanelledCommand)(chain_command)
    app.command("paper-fig6")(paper_fig6_command)
