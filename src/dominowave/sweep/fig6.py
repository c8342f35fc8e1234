"""The paper's Fig 6 (B-E) as a study: wave speed against spacing d/l, with ensembles.

For every configuration of :data:`dominowave.chain.paper_fig6.CONFIGS` in a preset,
every d/l and every ensemble member, one point of kind ``paper_fig6_member``
(:class:`Fig6Member`) runs :func:`dominowave.chain.paper_fig6.run_member`. The points
are run by the sweep engine (:func:`dominowave.sweep.presets.run_preset`: a Dask
LocalCluster or ``--scheduler``; each point stored as it ends; a re-run skips the
stored points; Ctrl-C or SIGTERM stops cleanly). ``runs.csv`` then holds one row per
stored member, and :func:`summarise` turns the rows into ensemble statistics per
(configuration, d/l), summed in member order: the same members give the same
summary to the last bit, whichever worker ran them when.

A preset's ``shape`` is the shape of its dominoes (``"clump"``, the paper's, or
``"box"``, :data:`QUICK_BOX` and :data:`FULL_BOX`). A box preset's ``runs.csv`` and
summary carry a ``shape`` column after ``config``; a clump preset's have the columns
they always had.
"""

from __future__ import annotations

import csv
import math
import os
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import Field

from dominowave.chain.build import Shape
from dominowave.chain.paper_fig6 import CONFIGS, MEMBER_FIELDS, run_member
from dominowave.chain.wave import ensemble_stats
from dominowave.io.results import RunResult
from dominowave.io.schema import ScenarioModel, quantity
from dominowave.sweep.context import RunContext
from dominowave.sweep.presets import PresetRun, run_preset

__all__ = [
    "FIELDS",
    "FULL",
    "FULL_BOX",
    "QUICK",
    "QUICK_BOX",
    "RUNS_CSV",
    "Fig6Member",
    "Fig6Preset",
    "fig6_points",
    "preset_fields",
    "read_rows",
    "run_fig6",
    "run_fig6_member",
    "summarise",
    "write_summary",
]

RUNS_CSV = "runs.csv"
"""One row per stored member, written into the sweep folder after each sweep."""

FIELDS = ["config", "d_over_l", "member", *MEMBER_FIELDS]
"""The columns of a clump preset's ``runs.csv``."""


@dataclass(frozen=True)
class Fig6Preset:
    """Sweep size: spacings, ensemble members, chain length, configurations."""

    name: str
    d_over_l: tuple[float, ...]
    members: int
    n_dominoes: int
    configs: tuple[str, ...] = (
        "2d",
        "k1e3",
        "k1e5",
        "damp_small",
        "damp_large",
        "mu0.6",
        "3d",
        "3d_asym",
    )
    seed: int = 0
    jitter: float = 1e-3
    shape: Shape = "clump"


QUICK = Fig6Preset("quick", d_over_l=(0.3, 0.6), members=2, n_dominoes=12)
FULL = Fig6Preset(
    "full", d_over_l=(0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8), members=8, n_dominoes=30
)
QUICK_BOX = replace(QUICK, name="quick-box", shape="box")
FULL_BOX = replace(FULL, name="full-box", members=4, shape="box")
"""The full preset with box dominoes, 4 members (members 0-3 of the clump preset's
seeds). A box chain scatters much less than a clump chain (at k/k* = 1e4, d/l = 0.4 its
2D members agree to 1e-5, docs/shape.md), but a 30-box wave does not settle in every
member at every spacing, and the lateral asymmetry scatters 3D members by several per
cent: with 4 members (256 runs) most ensembles have a standard error."""


def preset_fields(preset: Fig6Preset) -> list[str]:
    """The columns of ``preset``'s ``runs.csv``: :data:`FIELDS`, and ``shape`` after
    ``config`` for a box preset."""
    return FIELDS if preset.shape == "clump" else ["config", "shape", *FIELDS[1:]]


class Fig6Member(ScenarioModel):
    """One point of the study: member ``member`` of configuration ``config`` at ``d/l``."""

    kind: Literal["paper_fig6_member"] = "paper_fig6_member"
    config: Literal[tuple(CONFIGS)] = Field("2d", description="configuration (CONFIGS)")
    d_over_l: float = quantity(0.4, "-", "gap d over height l", gt=0.0, lt=1.0)
    member: int = Field(0, ge=0, description="ensemble member")
    n_dominoes: int = Field(30, ge=3, description="dominoes in the chain")
    seed: int = Field(0, ge=0, description="ensemble seed")
    jitter: float = quantity(1e-3, "-", "relative push perturbation", ge=0.0)
    shape: Shape = Field("clump", description="domino shape: clump (the paper's) or box")


def run_fig6_member(cfg: Fig6Member, ctx: RunContext | None = None) -> RunResult:
    """Run one member (the sweep engine's run function of ``paper_fig6_member``)."""
    measured = run_member(
        cfg.config, cfg.d_over_l, cfg.member, cfg.n_dominoes, cfg.seed, cfg.jitter, cfg.shape
    )
    row = {"config": cfg.config, "d_over_l": cfg.d_over_l, "member": cfg.member} | measured
    if cfg.shape != "clump":
        row["shape"] = cfg.shape
    # a wave that does not settle has no speed: NaN is a result here, not a failure
    undefined = tuple(k for k, v in row.items() if isinstance(v, float))
    return RunResult(summary=row, may_be_nan=undefined)


def _cost(config: str, d_over_l: float) -> float:
    """Relative cost of a run: spheres per domino times steps (to start the dearest first)."""
    c = CONFIGS[config]
    spheres = 5.0 if c.get("model") == "3d" else 1.0
    steps = math.sqrt(c.get("stiffness_ratio", 1e4) / 1e4) * (1.0 + 2.0 * d_over_l)
    return spheres * steps


def fig6_points(preset: Fig6Preset) -> list[Fig6Member]:
    """The points of ``preset`` in the order they are started: configuration by
    configuration (an interrupted sweep has whole panels), the dearest spacings of each
    first (a short tail when the last points run)."""
    points = []
    for config in preset.configs:
        for d in sorted(preset.d_over_l, key=lambda d, c=config: -_cost(c, d)):
            for m in range(preset.members):
                points.append(
                    Fig6Member(
                        config=config,
                        d_over_l=d,
                        member=m,
                        n_dominoes=preset.n_dominoes,
                        seed=preset.seed,
                        jitter=preset.jitter,
                        shape=preset.shape,
                    )
                )
    return points


def run_fig6(
    preset: Fig6Preset,
    out_dir: Path,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    client=None,
    progress: Callable[[dict], None] | None = None,
) -> PresetRun:
    """Run (or resume) the study of ``preset`` in the sweep folder ``out_dir``.

    ``workers`` processes (default ``min(2, cores)``; ignored with ``scheduler``, the
    address of a running Dask scheduler, or ``client``); ``progress(row)`` is called
    after each member run now. Writes ``out_dir / runs.csv`` (every stored member, in
    preset order) and returns what the sweep stored.
    """
    out_dir = Path(out_dir)
    done = run_preset(
        fig6_points(preset),
        out_dir,
        workers=workers or min(2, os.cpu_count() or 1),
        scheduler=scheduler,
        client=client,
        progress=progress,
    )
    rows = sorted(
        (s for s in done.summaries if s is not None),
        key=lambda r: (preset.configs.index(r["config"]), r["d_over_l"], r["member"]),
    )
    fields = preset_fields(preset)
    with (out_dir / RUNS_CSV).open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields)
        writer.writeheader()
        writer.writerows({k: r[k] for k in fields} for r in rows)
    return done


def summarise(rows: Iterable[dict]) -> list[dict]:
    """Ensemble statistics per (configuration, d/l) from run rows (CSV dicts or dicts).

    Speeds of members whose wave did not settle are NaN and counted in ``n_failed``.
    Rows of box dominoes (a ``shape`` column) are summarised apart from clump rows, and
    their summary has a ``shape`` column after ``config``.
    """
    groups: dict[tuple[str, float, str], list[dict]] = {}
    for r in rows:
        key = (r["config"], float(r["d_over_l"]), r.get("shape", "clump"))
        groups.setdefault(key, []).append(r)
    out = []
    for (config, dl, shape), unordered in sorted(groups.items()):
        # member order, not the workers' completion order: the sums are then reproducible
        # to the last bit
        rs = sorted(unordered, key=lambda r: int(r["member"]))

        def col(name, rs=rs):
            return np.array([float(r[name]) for r in rs])

        speed = ensemble_stats(col("speed"))
        window = ensemble_stats(col("theory_window_speed"))
        out.append(
            {"config": config}
            | ({} if shape == "clump" else {"shape": shape})
            | {
                "d_over_l": dl,
                "members": len(rs),
                "speed_mean": speed.mean,
                "speed_std": speed.std,
                "speed_stderr": speed.stderr,
                "n_settled": speed.n,
                "theory_speed": float(col("theory_speed")[0]),
                "theory_speed_point": float(col("theory_speed_point")[0]),
                "theory_speed_rigid": float(col("theory_speed_rigid")[0]),
                "theory_window_speed": window.mean,
                "multiple_collision_fraction": float(col("multiple_collision_fraction").mean()),
                "mean_hits_in_passage": float(col("mean_hits_in_passage").mean()),
                "mean_abs_slip": float(col("mean_abs_slip").mean()),
                "forward_slip_fraction": float(col("forward_slip_fraction").mean()),
                "wall_time": float(col("wall_time").sum()),
            }
        )
    return out


def read_rows(path: Path) -> list[dict]:
    """Rows of a ``runs.csv``."""
    with Path(path).open(newline="") as fh:
        return list(csv.DictReader(fh))


def write_summary(summary: list[dict], path: Path) -> Path:
    """Write ``summarise`` output as CSV."""
    path = Path(path)
    with path.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(summary[0]))
        writer.writeheader()
        writer.writerows(summary)
    return path
