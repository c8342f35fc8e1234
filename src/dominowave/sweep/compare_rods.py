"""The rod model against the theory over a (d/l, k/k*) grid, as a study (``compare-rods``).

Two kinds of points, run by the sweep engine (:func:`dominowave.sweep.presets.run_preset`:
a Dask LocalCluster or ``--scheduler``; each point stored as it ends; a re-run skips the
stored points; Ctrl-C or SIGTERM stops cleanly):

* ``rods_comparison`` (:class:`RodsComparison`): one grid point (contact normal, k/k*,
  d/l), :func:`dominowave.chain.theory_vs_rods.compare_point` -- the measured collisions
  and wave speed beside the theory's;
* ``rods_omega_profile`` (:class:`OmegaProfilePoint`): ``Omega_n`` of a push below or
  above the limit against eq 8 (Fig 1D), :func:`dominowave.chain.theory_vs_rods.omega_profile`.

The results are read back in grid order and written as ``compare_rods.csv`` (one row
per grid point, columns = :class:`~dominowave.chain.theory_vs_rods.Comparison` fields)
and ``omega_n.csv``; the figures are drawn by :mod:`dominowave.plots.compare_rods`.
"""

from __future__ import annotations

import csv
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import Field

from dominowave.chain.theory_vs_rods import (
    Comparison,
    OmegaProfile,
    compare_point,
    omega_profile,
    paper_chain,
)
from dominowave.io.results import RunResult
from dominowave.io.schema import ScenarioModel, quantity
from dominowave.sweep.context import RunContext
from dominowave.sweep.presets import PresetRun, run_preset
from dominowave.units import G_STANDARD

__all__ = [
    "CompareRodsResult",
    "OmegaProfilePoint",
    "RodsComparison",
    "comparison_points",
    "profile_label",
    "profile_points",
    "read_csv",
    "run_compare_rods",
    "run_comparison",
    "run_omega_profile",
    "write_csv",
    "write_profiles_csv",
]


class _RodsPoint(ScenarioModel):
    """What every point of the study shares: the chain and where gravity acts.

    The ranges are those of :func:`~dominowave.chain.theory_vs_rods.paper_chain`, which
    :func:`comparison_points` and :func:`profile_points` call first (one-line errors).
    """

    d_over_l: float = quantity(0.4, "-", "gap d over height l")
    k_over_kstar: float = quantity(1e4, "-", "the paper's stiffness k/k*")
    normal: str = Field("geometric", description="contact normal: geometric or head-on")
    n: int = Field(60, description="dominoes in the chain")
    g: float = quantity(G_STANDARD, "m/s^2", "gravity")
    gravity_in_contact: bool = Field(True, description="gravity acts during contacts")


class RodsComparison(_RodsPoint):
    """One grid point: the rod model at (d/l, k/k*) beside the theory."""

    kind: Literal["rods_comparison"] = "rods_comparison"


class OmegaProfilePoint(_RodsPoint):
    """``Omega_n`` after a push of ``push_factor`` times the limit ``Omega`` (eq 9)."""

    kind: Literal["rods_omega_profile"] = "rods_omega_profile"
    push_factor: float = quantity(1.0, "-", "push over the limit Omega (eq 9)", gt=0.0)


def _chain_keywords(point: _RodsPoint) -> dict:
    """The keywords that build a point's chain beside (d/l, k/k*): the same in the check
    and in both kinds of run."""
    return {
        "n": point.n,
        "normal": point.normal,
        "g": point.g,
        "gravity_in_contact": point.gravity_in_contact,
    }


def run_comparison(cfg: RodsComparison, ctx: RunContext | None = None) -> RunResult:
    """The sweep engine's run function of ``rods_comparison``."""
    c = compare_point(cfg.d_over_l, cfg.k_over_kstar, **_chain_keywords(cfg))
    summary = asdict(c)
    # a collision that never ended or a wave that never settled has no value: NaN is a
    # result here, not a failure
    undefined = tuple(k for k, v in summary.items() if isinstance(v, float))
    return RunResult(summary=summary, may_be_nan=undefined)


def run_omega_profile(cfg: OmegaProfilePoint, ctx: RunContext | None = None) -> RunResult:
    """The sweep engine's run function of ``rods_omega_profile``: ``Omega_n`` [rad/s]
    measured and from eq 8, one event row per domino."""
    p = omega_profile(cfg.d_over_l, cfg.k_over_kstar, cfg.push_factor, **_chain_keywords(cfg))
    return RunResult(
        summary={"push": p.push, "omega_limit": p.omega_limit},
        events={"n": np.arange(1, p.measured.size + 1), "measured": p.measured, "theory": p.theory},
    )


def _checked(point: _RodsPoint) -> _RodsPoint:
    """``point``, once its chain is known to build (a bad value is one clear error now,
    not a failed point later)."""
    paper_chain(point.d_over_l, point.k_over_kstar, **_chain_keywords(point))
    return point


def comparison_points(d_over_l_values, k_over_kstar_values, normals, **common) -> list:
    """The grid: contact normal, then k/k*, then d/l (the order of the CSV rows)."""
    return [
        _checked(RodsComparison(d_over_l=float(d), k_over_kstar=float(k), normal=normal, **common))
        for normal in normals
        for k in k_over_kstar_values
        for d in d_over_l_values
    ]


def profile_points(normals, d_over_l_values, push_factors, k_over_kstar, n, **common) -> list:
    """Fig 1D: ``Omega_n`` for each normal, d/l and push (below and above the limit)."""
    return [
        _checked(
            OmegaProfilePoint(
                d_over_l=d,
                k_over_kstar=k_over_kstar,
                push_factor=factor,
                normal=normal,
                n=n,
                **common,
            )
        )
        for normal in normals
        for d in d_over_l_values
        for factor in push_factors
    ]


def profile_label(point: OmegaProfilePoint) -> str:
    """The legend and CSV label of a profile point."""
    return f"{point.normal}, d/l={point.d_over_l}, Omega_1={point.push_factor} Omega"


@dataclass
class CompareRodsResult:
    """What :func:`run_compare_rods` found stored: comparisons and profiles in study order
    (points that failed or did not run are left out), and the sweep's run."""

    comparisons: list[Comparison]
    profiles: list[OmegaProfile]
    labels: list[str]
    run: PresetRun


def run_compare_rods(
    grid: list[RodsComparison],
    profiles: list[OmegaProfilePoint],
    out: Path,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    client=None,
    quiet: bool = True,
) -> CompareRodsResult:
    """Run (or resume) the grid and the profiles in the sweep folder ``out``."""
    points = [*grid, *profiles]
    done = run_preset(
        points,
        out,
        workers=workers,
        scheduler=scheduler,
        client=client,
        quiet=quiet,
        with_events=True,
    )
    comparisons = [
        Comparison(**{f.name: s[f.name] for f in fields(Comparison)})
        for s in done.summaries[: len(grid)]
        if s is not None
    ]
    found, labels = [], []
    stored = zip(profiles, done.summaries[len(grid) :], done.events[len(grid) :], strict=True)
    for point, s, ev in stored:
        if s is not None:
            found.append(OmegaProfile(s["push"], s["omega_limit"], ev["measured"], ev["theory"]))
            labels.append(profile_label(point))
    return CompareRodsResult(comparisons, found, labels, done)


def write_profiles_csv(profiles, labels, path) -> Path:
    """Write Omega_n profiles as CSV: ``label, n, omega_measured, omega_eq8`` [rad/s]."""
    path = Path(path)
    with path.open("w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["label", "n", "omega_measured", "omega_eq8", "omega_limit"])
        for profile, label in zip(profiles, labels, strict=True):
            for i, (meas, pred) in enumerate(zip(profile.measured, profile.theory, strict=True)):
                writer.writerow([label, i + 1, meas, pred, profile.omega_limit])
    return path


def read_csv(path) -> list[Comparison]:
    """Read comparisons written by :func:`write_csv` (e.g. to re-plot a grid)."""
    types = {f.name: f.type for f in fields(Comparison)}
    convert = {"str": str, "int": int, "float": float, "bool": lambda v: v == "True"}
    with Path(path).open(newline="") as fh:
        return [
            Comparison(**{k: convert[types[k]](v) for k, v in row.items()})
            for row in csv.DictReader(fh)
        ]


def write_csv(comparisons, path) -> Path:
    """Write comparisons as CSV (one row each, columns = :class:`Comparison` fields)."""
    path = Path(path)
    rows = [asdict(c) for c in comparisons]
    if not rows:
        raise ValueError("no comparisons to write")
    with path.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    return path
