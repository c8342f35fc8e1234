"""What a real-domino prediction rests on: the measurement it meets, and what reconciles them.

For a chain of standard dominoes at a gap and on a floor this module finds the shipped
measurements of the same kind (:mod:`dominowave.chain.measurements`: asymptotic speeds of
7.5 mm thick dominoes, gap within 0.05 mm, same floor), gives a model speed's difference
from their mean, and *infers* the friction between dominoes at which

* the leaning train (:mod:`dominowave.theory.leaning`) runs at the measured speed, and
* the box DEM would, by interpolation in the shipped friction scan
  (``chain/data/dem_friction_scan.csv``: the standard-domino chain of
  ``docs/real_dominoes/friction_scan.py``, every other value nominal), where that scan
  was run (its gap, floor and model).

An inferred friction is what the model needs to meet the measurement; it is not a
material value (``docs/real_dominoes.md``).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from importlib import resources

import numpy as np
from scipy.optimize import brentq

from dominowave.chain.measurements import Measurement, load_measurements
from dominowave.theory import leaning
from dominowave.units import G_STANDARD

__all__ = [
    "FilmComparison",
    "compare_with_measurements",
    "dem_friction_for_speed",
    "leaning_friction_for_speed",
    "reconcile_lines",
]

GAP_TOLERANCE = 5e-5
"""Largest difference [m] between a measurement's gap and the chain's to compare them."""
FRICTION_SEARCH = 3.0
"""Largest friction between dominoes searched when inferring one."""


@dataclass(frozen=True)
class FilmComparison:
    """The shipped measurements that match a chain: asymptotic speeds [m/s]."""

    gap: float  # [m]
    floor: str
    rows: tuple[Measurement, ...]

    @property
    def mean(self) -> float:
        """Mean measured speed [m/s]."""
        return float(np.mean([m.speed for m in self.rows]))

    @property
    def spread(self) -> float:
        """Standard deviation of the measured speeds [m/s] (0 for one row)."""
        return float(np.std([m.speed for m in self.rows], ddof=1)) if len(self.rows) > 1 else 0.0

    def difference_percent(self, speed: float) -> float:
        """``100 (speed / mean - 1)``: a model speed's difference from the measurements."""
        return 100.0 * (speed / self.mean - 1.0)


def compare_with_measurements(gap: float, floor: str, thickness: float = 0.0075):
    """The :class:`FilmComparison` for a chain, or ``None`` if nothing was measured there."""
    rows = tuple(
        m
        for m in load_measurements()
        if m.speed_kind == "asymptotic"
        and m.floor == floor
        and m.thickness is not None
        and abs(m.thickness - thickness) < 1e-4
        and m.gap is not None
        and abs(m.gap - gap) <= GAP_TOLERANCE
    )
    return FilmComparison(gap, floor, rows) if rows else None


def leaning_friction_for_speed(speed, *, height, thickness, gap, g=G_STANDARD):
    """Friction between dominoes at which the leaning train runs at ``speed`` [m/s].

    Returns ``(friction, note)``: ``friction`` is ``None`` with a note where no friction
    in ``[0, FRICTION_SEARCH]`` gives that speed (faster than the frictionless train,
    slower than any steady train, or no steady train at this gap). The speed falls with
    the friction; a scan of 61 frictions brackets the root, ``brentq`` finds it.
    """

    def train_speed(mu):
        return leaning.limit_speed(height=height, thickness=thickness, gap=gap, friction=mu, g=g)

    grid = np.linspace(0.0, FRICTION_SEARCH, 61)
    speeds = train_speed(grid)
    runs = np.isfinite(speeds)
    if not runs[0]:
        return None, "no steady leaning train at this gap"
    if speed > speeds[0]:
        return None, f"faster than the frictionless leaning train ({speeds[0]:.3g} m/s)"
    last = len(grid) - 1 if runs.all() else int(np.argmin(runs)) - 1
    if speed < speeds[last]:
        return None, f"slower than any steady leaning train (>= {speeds[last]:.3g} m/s)"
    k = int(np.searchsorted(-speeds[: last + 1], -speed))  # first grid speed <= speed
    if k == 0:
        return 0.0, ""
    mu = brentq(lambda m: train_speed(m) - speed, grid[k - 1], grid[k], xtol=1e-6)
    return mu, ""


def _dem_scan():
    path = resources.files("dominowave.chain").joinpath("data", "dem_friction_scan.csv")
    with path.open() as f:
        return list(csv.DictReader(f))


def dem_friction_for_speed(speed, *, gap, floor, model="3d"):
    """Friction at which the box DEM's scan runs at ``speed`` [m/s] (linear interpolation).

    Returns ``(friction, note)``; ``friction`` is ``None`` where the scan was not run at
    this gap, floor and model, or where ``speed`` is outside its speeds.
    """
    rows = [
        r
        for r in _dem_scan()
        if r["model"] == model
        and r["floor"] == floor
        and abs(float(r["gap_m"]) - gap) <= GAP_TOLERANCE
    ]
    if not rows:
        return None, "the DEM friction scan was not run at this gap, floor and model"
    mu = np.array([float(r["friction_dominoes"]) for r in rows])
    v = np.array([float(r["speed_m_s"]) for r in rows])
    order = np.argsort(v)  # the speed falls with the friction
    if not v.min() <= speed <= v.max():
        return None, f"outside the scan's speeds ({v.min():.3g}-{v.max():.3g} m/s)"
    return float(np.interp(speed, v[order], mu[order])), ""


def reconcile_lines(
    model_speed,
    *,
    gap,
    floor,
    height=0.048,
    thickness=0.0075,
    model="3d",
    label="this run",
    friction=None,
):
    """Lines saying what was measured at this gap and floor and what would reconcile it.

    ``model_speed`` [m/s] is the prediction to compare (NaN: no comparison of it);
    ``friction`` between dominoes, if given, adds the leaning train's speed at it.
    """
    lines = []
    if friction is not None:
        st = leaning.steady_state(height, thickness, gap, friction)
        lines.append(
            f"leaning train (rigid, inelastic; theory.leaning) at friction {friction:g}:"
            + (f" {st.speed:.3f} m/s" if st.exists else f" no steady train ({st.reason})")
        )
    films = compare_with_measurements(gap, floor, thickness)
    if films is None:
        return [
            *lines,
            f"no shipped measurement at gap {1e3 * gap:.4g} mm on {floor}"
            " (docs/real_dominoes.md lists what was measured)",
        ]
    lines += [
        f"measured (high-speed films, {floor}, gap {1e3 * gap:.4g} mm,"
        f" {len(films.rows)} row{'s' if len(films.rows) > 1 else ''}): {films.mean:.3f} m/s"
        + (f" (sd {films.spread:.3f})" if len(films.rows) > 1 else "")
        + (
            f"; {label}: {model_speed:.3f} m/s, {films.difference_percent(model_speed):+.0f} %"
            if math.isfinite(model_speed)
            else ""
        )
    ]
    mu_lean, why_lean = leaning_friction_for_speed(
        films.mean, height=height, thickness=thickness, gap=gap
    )
    mu_dem, why_dem = dem_friction_for_speed(films.mean, gap=gap, floor=floor, model=model)
    lean = f"{mu_lean:.2f}" if mu_lean is not None else f"none ({why_lean})"
    dem = f"{mu_dem:.2f}" if mu_dem is not None else f"none ({why_dem})"
    lines.append(
        "friction between dominoes at which the models meet the films, inferred from the"
        f" measurement (not a material value): leaning train {lean}; box DEM ({model}) {dem}"
    )
    return lines
