"""Study presets: a fixed list of points run by the sweep engine, read back in order.

A preset (the paper's Fig 6, the rods-vs-theory comparison) is a study like any other:
its points are scenario models, :func:`run_preset` hands them to
:func:`dominowave.sweep.runner.run_sweep` -- a Dask LocalCluster, or the cluster of
``scheduler`` -- which stores each point's folder the moment it is done, skips the
points already stored (a re-run resumes) and stops cleanly on Ctrl-C or SIGTERM. The
preset then reads the stored summaries back in its own point order, so what it writes
from them does not depend on the order the workers finished in.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from dominowave.io.config import OutputSpec, Study, SweepSpec
from dominowave.io.results import read_events, read_summary
from dominowave.io.schema import ScenarioModel
from dominowave.sweep.hashing import config_dict, point_key
from dominowave.sweep.runner import SweepReport, run_sweep
from dominowave.sweep.store import SweepStore

__all__ = ["PresetRun", "preset_study", "run_preset"]


@dataclass
class PresetRun:
    """What :func:`run_preset` found stored after the sweep.

    ``summaries[i]`` / ``events[i]``: summary and event columns of point ``i`` (None if
    the point failed or was not run, e.g. after an interruption); ``failed``: indices of
    the points whose folder records a failure.
    """

    report: SweepReport
    summaries: list[dict | None]
    events: list[dict | None]
    failed: list[int]


def preset_study(points: Sequence[ScenarioModel], out: Path) -> Study:
    """The study of ``points`` (its ``study.toml`` lists every point in full; the
    sweep index names each point by its fields)."""
    overrides = tuple({k: v for k, v in config_dict(p).items() if k != "kind"} for p in points)
    return Study(
        path=None,
        scenario=points[0],
        points=tuple(points),
        overrides=overrides,
        sweep=SweepSpec(points=[config_dict(p) for p in points]),
        output=OutputSpec(dir=str(out), trajectory=False),
    )


def run_preset(
    points: Sequence[ScenarioModel],
    out: Path,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    client=None,
    quiet: bool = True,
    progress: Callable[[dict], None] | None = None,
    with_events: bool = False,
) -> PresetRun:
    """Run (or resume) the points in the sweep folder ``out``; read them back in order.

    ``workers``: processes of the LocalCluster (ignored with ``scheduler`` or
    ``client``); ``progress(summary)`` is called with the summary of each point that
    ran now without failing; ``with_events`` also reads each point's ``events.csv``.
    """
    if not points:
        raise ValueError("the preset has no points")

    def on_point(config, outcome):
        if progress is not None and outcome.status == "ok":
            progress(outcome.result.summary)

    report = run_sweep(
        preset_study(points, out),
        out,
        client=client,
        scheduler=scheduler,
        n_workers=workers,
        quiet=quiet,
        on_point=on_point,
    )
    store = SweepStore(out)
    status = store.status()
    summaries: list[dict | None] = []
    events: list[dict | None] = []
    failed = []
    for i, point in enumerate(points):
        key = point_key(point)
        ok = status.get(key) == "ok"
        failed += [i] if status.get(key) == "failed" else []
        summaries.append(read_summary(store.folder(key)) if ok else None)
        events.append(read_events(store.folder(key)) if ok and with_events else None)
    return PresetRun(report, summaries, events, failed)
