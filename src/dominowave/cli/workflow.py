"""Research workflow commands: config, run, sweep, collect, plot, animate, resume.

Every command validates all of its input before it runs anything; bad input is
one line on stderr and exit code 2 (``ValueError``, see ``cli/__init__.py``).
Heavy libraries (dask, xarray, matplotlib, imageio) are imported inside the
commands, so ``dominowave theory ...`` starts fast.
"""

from __future__ import annotations

import functools
import os
import re
import sys
from pathlib import Path
from typing import Annotated

import typer

from dominowave import signals
from dominowave.cli.compiling import notice_if_compiling, study_kernels
from dominowave.io.atomic import os_error_line

__all__ = ["register"]

_QUIET = typer.Option("--quiet", "-q", help="No progress bar (also off when not on a terminal).")
_SCHEDULER = typer.Option(help="Address of an existing Dask scheduler (tcp://host:port).")
_WORKERS = typer.Option(help="Workers of the LocalCluster (default: all cores).")
_RETRY_FAILED = typer.Option(help="Run failed points again.")


_ADDRESS = re.compile(r"((tcp|tls|ucx|ws|wss|inproc)://)?[\w.\-\[\]:]+:\d{1,5}")
"""A Dask scheduler address: ``[protocol://]host:port``."""


def _errors_as_values(command):
    """Turn errors of user-given paths into one-line ``ValueError``, and Ctrl-C
    (SIGTERM) into a line and exit code 130 (143)."""

    @functools.wraps(command)
    def wrapper(*args, **kwargs):
        try:
            return command(*args, **kwargs)
        except BrokenPipeError:  # e.g. `dominowave config --example chain | head`
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            sys.exit(0)
        except KeyboardInterrupt as exc:
            typer.echo(
                "dominowave: interrupted; finished results are kept, re-run to resume", err=True
            )
            sys.exit(signals.exit_code(exc))
        except (FileNotFoundError, PermissionError, NotADirectoryError, IsADirectoryError) as exc:
            raise ValueError(os_error_line(exc)) from None  # a path given by the user: exit 2
        # any other OSError (a full disk, an I/O error) reaches main: one line, exit 1

    return wrapper


def parse_every(option: str | None, name: str, units: dict[str, str]) -> dict[str, float]:
    """Parse ``"every=10"`` / ``"steps=1000,minutes=5"`` style options.

    ``units`` maps each allowed key to ``"int"`` or ``"float"``; values must be > 0.
    """
    if option is None:
        return {}
    out: dict[str, float] = {}
    for part in option.split(","):
        m = re.fullmatch(r"\s*([a-z_]+)\s*=\s*([^\s]+)\s*", part)
        if not m or m.group(1) not in units:
            keys = ", ".join(f"{k}=N" for k in units)
            raise ValueError(f"{name} {option!r}: expected {keys}")
        key, raw = m.groups()
        try:
            value = int(raw) if units[key] == "int" else float(raw)
        except ValueError:
            kind = "an integer" if units[key] == "int" else "a number"
            raise ValueError(f"{name} {key} = {raw!r} is not {kind}") from None
        if not 0 < value < float("inf"):
            raise ValueError(f"{name} {key} = {raw} is outside the valid range (0, inf)")
        out[key] = value
    return out


def config_cmd(
    study: Annotated[Path | None, typer.Argument(help="Study file to check.")] = None,
    example: Annotated[
        str | None, typer.Option(help="Print a documented example: theory, chain, rods or sweep.")
    ] = None,
) -> None:
    """Print an example study file, or check one and list its points."""
    from dominowave.io.config import example_toml, load_study

    if example is not None:
        typer.echo(example_toml(example), nl=False)
        return
    if study is None:
        raise ValueError("give a study file to check, or --example theory|chain|rods|sweep")
    loaded = load_study(study)
    from dominowave.sweep.hashing import point_key

    typer.echo(f"{study}: ok, scenario {loaded.scenario.kind}, {len(loaded.points)} point(s)")
    for override, point in zip(loaded.overrides, loaded.points, strict=True):
        label = ", ".join(f"{k} = {v!r}" for k, v in override.items()) or "(base scenario)"
        typer.echo(f"  {point_key(point)}  {label}")


def run_cmd(
    study: Annotated[Path, typer.Argument(help="Study file (TOML).")],
    out: Annotated[Path | None, typer.Option(help="Result folder (default: output.dir).")] = None,
    force: Annotated[bool, typer.Option(help="Replace a result of another config.")] = False,
    vtk: Annotated[
        str | None, typer.Option(help="Write VTK frames for ParaView: every=N frames.")
    ] = None,
    checkpoint: Annotated[
        str | None,
        typer.Option(help="Checkpoint long runs: steps=N and/or minutes=M (resume: re-run)."),
    ] = None,
    quiet: Annotated[bool, _QUIET] = False,
) -> None:
    """Run the study's scenario once (a sweep table is ignored; use `sweep`)."""
    from dominowave.io.config import load_study

    loaded = load_study(study)
    vtk_every = int(parse_every(vtk, "--vtk", {"every": "int"}).get("every", 0))
    every = parse_every(checkpoint, "--checkpoint", {"steps": "int", "minutes": "float"})
    folder = Path(out) if out is not None else Path(loaded.output.dir)
    policy = None
    if checkpoint is not None:
        policy = {"steps": int(every.get("steps", 0)), "seconds": 60.0 * every.get("minutes", 0)}
    _run(loaded, folder, force, policy, vtk_every, quiet)


def _run(loaded, folder: Path, force: bool, policy: dict | None, vtk_every: int, quiet: bool):
    from dominowave.io.progress import RunProgress
    from dominowave.sweep.context import RunContext
    from dominowave.sweep.runner import run_one

    if vtk_every and not getattr(type(loaded.scenario), "RECORDS_FRAMES", False):
        raise ValueError(f"--vtk: scenario {loaded.scenario.kind!r} records no frames to draw")
    notice_if_compiling(*study_kernels(loaded.scenario.kind, loaded.points))
    with RunProgress(quiet) as progress:
        ctx = RunContext(progress=progress if progress.enabled else None, vtk_every=vtk_every)
        if policy is not None:
            ctx.checkpoint_dir = folder / "checkpoint"
            ctx.checkpoint_every_steps = policy["steps"]
            ctx.checkpoint_every_seconds = policy["seconds"]
        status = run_one(loaded, folder, ctx, force=force)
    if vtk_every and status == "up to date":  # redraw from the stored trajectory
        from dominowave.io.results import read_trajectory
        from dominowave.io.vtk import write_trajectory_vtk

        write_trajectory_vtk(folder / "vtk", read_trajectory(folder), every=vtk_every)
    if vtk_every:
        n = len(list((folder / "vtk").glob("dominoes_*.vtu")))
        typer.echo(f"VTK: {n} frames in {folder / 'vtk'} (open the .pvd files in ParaView)")
    typer.echo(f"{status}: {folder}")
    if (folder / "summary.json").is_file():
        typer.echo(_speed_line(folder))


def _speed_line(folder: Path) -> str:
    """The run's wave speed in one line (with the note of a run cut short at its
    ``max_time``), or "not settled" with the reason."""
    import math

    from dominowave.io.results import read_summary

    summary = read_summary(folder)
    speed = summary.get("speed", math.nan)
    if math.isfinite(speed):
        err = summary.get("speed_err", math.nan)
        spread = f" ± {err:.2g}" if math.isfinite(err) else ""
        note = summary.get("speed_note") or ""  # (of a settled speed: a run cut short)
        return f"speed: {speed:.4g}{spread} m/s" + (f" ({note})" if note else "")
    return f"speed: not settled ({summary.get('speed_note') or 'no reason recorded'})"


def sweep_cmd(
    study: Annotated[Path, typer.Argument(help="Study file with a [sweep] table.")],
    out: Annotated[Path | None, typer.Option(help="Sweep folder (default: output.dir).")] = None,
    scheduler: Annotated[str | None, _SCHEDULER] = None,
    workers: Annotated[int | None, _WORKERS] = None,
    retry_failed: Annotated[bool, _RETRY_FAILED] = False,
    force: Annotated[
        bool, typer.Option(help="Add the points to a folder that holds another study.")
    ] = False,
    quiet: Annotated[bool, _QUIET] = False,
) -> None:
    """Run every point of a sweep on dask.distributed; stored points are skipped."""
    from dominowave.io.config import load_study

    loaded = load_study(study)
    if loaded.sweep is None:
        raise ValueError(f"{study}: no [sweep] table (use `dominowave run` for a single run)")
    _sweep(
        loaded,
        Path(out) if out is not None else Path(loaded.output.dir),
        scheduler,
        workers,
        retry_failed,
        quiet,
        force,
    )


def check_cluster_options(workers: int | None, scheduler: str | None) -> None:
    """One-line errors for ``--workers`` below 1 and a ``--scheduler`` that is no address."""
    if workers is not None and workers < 1:
        raise ValueError(f"--workers = {workers} is outside the valid range [1, inf)")
    if scheduler is not None and not _ADDRESS.fullmatch(scheduler):
        raise ValueError(
            f"--scheduler {scheduler!r} is not a scheduler address (e.g. tcp://10.0.0.5:8786)"
        )


def _sweep(loaded, folder, scheduler, workers, retry_failed, quiet, force=False) -> None:
    from dominowave.sweep.runner import run_sweep

    check_cluster_options(workers, scheduler)
    if scheduler is None:  # the local workers share this machine's kernel cache
        notice_if_compiling(*study_kernels(loaded.scenario.kind, loaded.points), by_workers=True)
    report = run_sweep(
        loaded,
        folder,
        scheduler=scheduler,
        n_workers=workers,
        quiet=quiet,
        retry_failed=retry_failed,
        force=force,
    )
    typer.echo(report.line())
    if report.interrupted:
        sys.exit(report.interrupted)
    if report.failed:
        typer.echo(f"{report.failed} point(s) failed: see failure.json in their folders", err=True)
        sys.exit(1)


def collect_cmd(
    folder: Annotated[Path, typer.Argument(help="Sweep folder.")],
    out: Annotated[
        Path | None, typer.Option(help="netCDF file (default: FOLDER/collected.nc).")
    ] = None,
) -> None:
    """Gather a sweep's points into one xarray Dataset (netCDF)."""
    from dominowave.sweep.collect import collect, write_collected

    ds = collect(folder)
    missing = ds.attrs["points_missing"]
    name = "collected.partial.nc" if missing else "collected.nc"  # partial says so
    path = write_collected(ds, out or Path(folder) / name)
    dims = ", ".join(f"{k}: {v}" for k, v in ds.sizes.items())
    typer.echo(f"collected {dims} -> {path}")
    if missing:
        typer.echo(
            f"partial: {missing} point(s) of the study are not stored (attribute"
            f" points_missing); `dominowave resume {folder}` runs them"
        )


def plot_cmd(
    folder: Annotated[Path, typer.Argument(help="Sweep or run folder.")],
    out: Annotated[Path | None, typer.Option(help="Figure folder (default FOLDER/figures)")] = None,
) -> None:
    """Speed vs d/l with the theory curves, arrival-time diagram, local speed profile."""
    from dominowave.plots.folder import plot_folder

    for path in plot_folder(folder, out):
        typer.echo(f"wrote {path}")


def animate_cmd(
    folder: Annotated[Path, typer.Argument(help="Run folder, or a sweep folder with --point.")],
    out: Annotated[Path, typer.Option(help="Movie file: .mp4 or .gif.")] = Path("chain.mp4"),
    point: Annotated[str | None, typer.Option(help="Key of the sweep point to draw.")] = None,
    fps: Annotated[int, typer.Option(help="Frames per second of the movie, 1 to 120.")] = 25,
    slowdown: Annotated[
        float | None,
        typer.Option(help="Movie seconds per simulated second (default: movie lasts ~6 s)."),
    ] = None,
) -> None:
    """Draw the chain toppling (side view, coloured by angular velocity) to mp4 or gif."""
    from dominowave.checks import check_in_range
    from dominowave.io.animation import animate
    from dominowave.io.results import read_trajectory

    check_in_range("--fps", fps, 1, 120, lo_inclusive=True, hi_inclusive=True)
    if slowdown is not None:
        check_in_range("--slowdown", slowdown, 0.0, float("inf"))

    folder = Path(folder)
    if point is None and (folder / "points").is_dir():
        raise ValueError(_which_point(folder))
    if point is not None:
        folder = folder / "points" / point
        if not folder.is_dir():
            raise ValueError(f"--point {point}: no such point in {folder.parent.parent}")
    n = animate(read_trajectory(folder), out, fps=fps, slowdown=slowdown)
    typer.echo(f"wrote {n} frames to {out}")


def _which_point(sweep: Path) -> str:
    """The message for a sweep folder given to ``animate`` without ``--point``."""
    keys = sorted(p.name for p in (sweep / "points").iterdir() if p.is_dir())
    shown = ", ".join(keys[:4]) + (f" ... ({len(keys)} points)" if len(keys) > 4 else "")
    return (
        f"{sweep} is a sweep folder: name the point to draw with --point KEY "
        f"(stored points: {shown or 'none yet'}; `dominowave config STUDY` lists each "
        "point with its key and values)"
    )


def resume_cmd(
    folder: Annotated[Path, typer.Argument(help="Sweep folder (or run folder with a checkpoint).")],
    scheduler: Annotated[str | None, _SCHEDULER] = None,
    workers: Annotated[int | None, _WORKERS] = None,
    retry_failed: Annotated[bool, _RETRY_FAILED] = False,
    quiet: Annotated[bool, _QUIET] = False,
) -> None:
    """Continue a killed sweep or checkpointed run (finished work is kept, the rest runs)."""
    import json

    from dominowave.io.config import load_study

    folder = Path(folder)
    if (folder / "checkpoint" / "study.toml").is_file():
        ck = folder / "checkpoint"
        try:
            policy = json.loads((ck / "policy.json").read_text())
        except (OSError, ValueError) as exc:
            raise ValueError(f"{ck / 'policy.json'}: unreadable ({exc})") from None
        _run(load_study(ck / "study.toml"), folder, False, policy, 0, quiet)
        return
    study = folder / "study.toml"
    if not study.is_file():
        raise ValueError(
            f"{folder}: nothing to resume (neither a sweep folder nor a run with a checkpoint)"
        )
    _sweep(load_study(study), folder, scheduler, workers, retry_failed, quiet)


def register(app: typer.Typer) -> None:
    """Add the workflow commands to the ``dominowave`` app."""
    for name, command in [
        ("config", config_cmd),
        ("run", run_cmd),
        ("sweep", sweep_cmd),
        ("collect", collect_cmd),
        ("plot", plot_cmd),
        ("animate", animate_cmd),
        ("resume", resume_cmd),
    ]:
        app.command(name)(_errors_as_values(command))
