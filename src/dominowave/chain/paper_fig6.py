"""The sweeps behind the paper's Fig 6 (B-E): wave speed against spacing d/l.

Each *configuration* is a set of ``ChainParams`` changes from the 2D default chain
(s/l = 0.1, k/k* = 1e4, phi_f = 0.3, phi_d = 0, no damping, held until touched):

====================  ==========================================  ==========
name                  change                                      panels
====================  ==========================================  ==========
2d                    none                                        B C D E
3d                    model="3d" (w/l = 0.5, free in 6 DOF)       B
3d_asym               3d with a seeded random yaw (lateral asym.) B
k1e3, k1e5            stiffness_ratio = 1e3, 1e5                  C
damp_small/large      local damping 0.02 / 0.1                    D E
mu0.6                 floor friction 0.6                          D
====================  ==========================================  ==========

For every (configuration, d/l) an ensemble of seeded, perturbed pushes is run
(``DominoChain.ensemble`` semantics: member ``i`` scales the push by
``1 + jitter N(0,1)`` from ``default_rng([seed, i])``). One CSV row per run is
appended to ``runs.csv`` as soon as the run ends, so an interrupted sweep keeps what
it did and a re-run skips the rows already there (resumable). ``summarise`` turns
the rows into ensemble statistics per (configuration, d/l).
"""

from __future__ import annotations

import csv
import math
import os
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dominowave.chain.build import ChainParams
from dominowave.chain.compare import theory_speed
from dominowave.chain.scenario import DominoChain
from dominowave.chain.wave import ensemble_stats

__all__ = [
    "CONFIGS",
    "FULL",
    "QUICK",
    "Fig6Preset",
    "read_rows",
    "run_sweep",
    "summarise",
    "write_summary",
]

CONFIGS: dict[str, dict] = {
    "2d": {},
    "3d": {"model": "3d"},
    "3d_asym": {"model": "3d", "lateral_asymmetry": 0.02},
    "k1e3": {"stiffness_ratio": 1e3},
    "k1e5": {"stiffness_ratio": 1e5},
    "damp_small": {"damping": 0.02},
    "damp_large": {"damping": 0.1},
    "mu0.6": {"friction_floor": 0.6},
}
"""Configuration name -> ``ChainParams`` changes (see the module docstring)."""


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


QUICK = Fig6Preset("quick", d_over_l=(0.3, 0.6), members=2, n_dominoes=12)
FULL = Fig6Preset(
    "full", d_over_l=(0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8), members=8, n_dominoes=30
)

FIELDS = [
    "config",
    "d_over_l",
    "member",
    "n_dominoes",
    "push_omega",
    "speed",
    "speed_err",
    "settled",
    "first",
    "last",
    "reached",
    "theory_speed",
    "theory_speed_point",
    "theory_speed_rigid",
    "theory_window_speed",
    "multiple_collision_fraction",
    "mean_hits_in_passage",
    "mean_abs_slip",
    "forward_slip_fraction",
    "wall_time",
    "n_steps",
]


def _params(config: str, d_over_l: float, preset: Fig6Preset) -> ChainParams:
    return ChainParams(n_dominoes=preset.n_dominoes, d_over_l=d_over_l, **CONFIGS[config])


def _run_one(task: tuple[str, float, int, Fig6Preset]) -> dict:
    """One ensemble member -> one CSV row (runs in a worker process)."""
    config, d_over_l, member, preset = task
    p = _params(config, d_over_l, preset)
    chain = DominoChain(p)
    base = chain.resolve(None)
    factor = 1.0 + preset.jitter * np.random.default_rng([preset.seed, member]).standard_normal()
    run = chain.run(base.scaled(factor))
    ev = run.events
    interior = slice(1, p.n_dominoes - 2)  # pairs whose passage is defined
    hits = ev.n_hits_in_passage[interior]
    return {
        "config": config,
        "d_over_l": d_over_l,
        "member": member,
        "n_dominoes": p.n_dominoes,
        "push_omega": run.omega_1,
        "speed": run.wave.speed,
        "speed_err": run.wave.speed_err,
        "settled": int(run.wave.settled),
        "first": run.wave.first,
        "last": run.wave.last,
        "reached": run.wave.reached,
        "theory_speed": run.theory_speed,
        "theory_speed_point": theory_speed(p, "point"),
        "theory_speed_rigid": theory_speed(p, rigid=True),
        "theory_window_speed": run.theory_window_speed,
        "multiple_collision_fraction": float(np.mean(hits > 1)),
        "mean_hits_in_passage": float(np.mean(hits)),
        "mean_abs_slip": float(np.mean(np.abs(ev.slip_final[:-1]))),
        "forward_slip_fraction": float(np.mean(ev.mechanism[1:] == 2)),
        "wall_time": run.wall_time,
        "n_steps": run.n_steps,
    }


def _done_keys(path: Path) -> set[tuple[str, float, int]]:
    if not path.exists():
        return set()
    with path.open(newline="") as fh:
        return {(r["config"], float(r["d_over_l"]), int(r["member"])) for r in csv.DictReader(fh)}


def run_sweep(preset: Fig6Preset, out_dir: Path, workers: int | None = None, progress=None) -> Path:
    """Run (or resume) the sweep of ``preset``; rows go to ``out_dir / runs.csv``.

    ``workers`` processes (default: ``min(2, cpu count)``); ``progress(row)`` is called
    after each finished run. Returns the CSV path.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / "runs.csv"
    done = _done_keys(path)
    tasks = [
        (c, d, m, preset)
        for c in preset.configs
        for d in preset.d_over_l
        for m in range(preset.members)
        if (c, d, m) not in done
    ]
    # configuration by configuration in the preset's order (an interrupted sweep has
    # whole panels), the expensive spacings of each first (a short tail in the pool)
    order = {c: i for i, c in enumerate(preset.configs)}
    tasks.sort(key=lambda t: (order[t[0]], -_cost(t[0], t[1])))
    new_file = not path.exists()
    workers = workers or min(2, os.cpu_count() or 1)
    with path.open("a", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=FIELDS)
        if new_file:
            writer.writeheader()
        for row in _map(tasks, workers):
            writer.writerow(row)
            fh.flush()
            if progress is not None:
                progress(row)
    return path


def _cost(config: str, d_over_l: float) -> float:
    c = CONFIGS[config]
    spheres = 5.0 if c.get("model") == "3d" else 1.0
    steps = math.sqrt(c.get("stiffness_ratio", 1e4) / 1e4) * (1.0 + 2.0 * d_over_l)
    return spheres * steps


def _map(tasks: list, workers: int) -> Iterable[dict]:
    if workers <= 1 or len(tasks) <= 1:
        yield from map(_run_one, tasks)
        return
    import multiprocessing as mp
    import signal

    # SIGTERM must end the workers too (the pool's context manager terminates them)
    previous = signal.signal(signal.SIGTERM, _raise_exit)
    try:
        with mp.get_context("spawn").Pool(workers) as pool:
            yield from pool.imap_unordered(_run_one, tasks)
    finally:
        signal.signal(signal.SIGTERM, previous)


def _raise_exit(signum, frame):
    raise SystemExit(128 + signum)


def summarise(rows: Iterable[dict]) -> list[dict]:
    """Ensemble statistics per (configuration, d/l) from run rows (CSV dicts or dicts).

    Speeds of members whose wave did not settle are NaN and counted in ``n_failed``.
    """
    groups: dict[tuple[str, float], list[dict]] = {}
    for r in rows:
        groups.setdefault((r["config"], float(r["d_over_l"])), []).append(r)
    out = []
    for (config, dl), unordered in sorted(groups.items()):
        # member order, not the workers' completion order: the sums are then reproducible
        # to the last bit
        rs = sorted(unordered, key=lambda r: int(r["member"]))

        def col(name, rs=rs):
            return np.array([float(r[name]) for r in rs])

        speed = ensemble_stats(col("speed"))
        window = ensemble_stats(col("theory_window_speed"))
        out.append(
            {
                "config": config,
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
