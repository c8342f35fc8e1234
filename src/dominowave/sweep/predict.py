"""A-priori prediction of a real chain's front speed, with the band of the material data.

The material values of a standard domino (:mod:`dominowave.chain.presets`) are known only
within ranges (``chain/data/materials.toml``). :func:`predict` propagates those ranges:

1. **Sampling** -- Saltelli's scheme on a scrambled Sobol' (quasi-random) sequence
   (``SALib.sample.sobol``, Saltelli 2002; Saltelli et al. 2010), each of the
   :data:`dominowave.chain.presets.SAMPLED` values uniform over its range (values with a
   zero-width range are fixed). ``samples = N`` gives ``N (D + 2)`` runs for ``D``
   varied values (``D = 6`` for the shipped data).
2. **Runs** -- each sample is one point of kind ``predict_sample`` (:class:`PredictSample`)
   on the sweep engine (a Dask LocalCluster or ``--scheduler``; each point stored as it
   ends; a re-run skips the stored points; Ctrl-C stops cleanly). A run measures the
   front speed as a high-speed camera does: fitted from domino ``fit_from`` on,
   pitch-based (:func:`dominowave.chain.wave.speed_from`).
3. **Band and sensitivity** -- the 5 %, 50 % and 95 % quantiles of the speeds and their
   mean (over the runs whose wave reached the end of the chain); for each varied value
   its *effect*, the change of the speed over the value's whole range, averaged over the
   base samples from the design's one-at-a-time pairs (``A`` and ``AB_i`` differ in value
   ``i`` only: ``(y_ABi - y_A) / (x_Bi - x_Ai) (hi - lo)``, an elementary effect in the
   sense of Morris 1991, defined from one base sample on); and from
   :data:`SOBOL_MIN_BASE` base samples on the first-order and total Sobol' indices
   (``SALib.analyze.sobol``, with bootstrap confidence intervals). If any wave died or
   any run failed, the effects and indices are not defined (NaN); both are counted.

The band is the spread the material data allow, not a confidence interval of a
measurement: it is as wide as the ranges of the data file, several of which are
assumptions.
"""

from __future__ import annotations

import csv
import math
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import Field, field_validator

from dominowave.chain.fidelity import (
    DEFAULT_TOLERANCE,
    EXACT,
    Fidelity,
    check_fidelity,
    choose_contact,
    tolerance_of,
)
from dominowave.chain.materials import load_materials
from dominowave.chain.presets import SAMPLED, standard_domino, standard_entries
from dominowave.chain.scenario import DominoChain
from dominowave.chain.wave import check_fit_from, speed_from
from dominowave.checks import check_memory
from dominowave.io.config import BYTES_PER_POINT
from dominowave.io.results import RunResult
from dominowave.io.schema import ScenarioModel, quantity
from dominowave.sweep.context import RunContext
from dominowave.sweep.presets import PresetRun, run_preset

__all__ = [
    "SAMPLES_CSV",
    "SAMPLES_NC",
    "SUMMARY_CSV",
    "PredictSample",
    "Prediction",
    "predict",
    "predict_points",
    "run_predict_sample",
]

SAMPLES_CSV = "samples.csv"
SAMPLES_NC = "samples.nc"
SUMMARY_CSV = "prediction.csv"
BAND = (0.05, 0.5, 0.95)
"""Quantiles of the predicted speed reported as the band."""
SOBOL_MIN_BASE = 8
"""Fewest base samples N for which Sobol' indices are reported: below it the estimates
and their bootstrap confidence rest on too few values (with N = 1 the bootstrap has one
value and claims a zero confidence interval)."""


class PredictSample(ScenarioModel):
    """One sample of the material values: a standard-domino chain run once."""

    kind: Literal["predict_sample"] = "predict_sample"
    sample: int = Field(0, ge=0, description="index of the sample")
    gap: float = quantity(0.00938, "m", "clear gap d between neighbours", gt=0.0)
    floor: str = Field("hardwood", description="named floor of the materials data")
    n_dominoes: int = Field(12, ge=3, le=100_000, description="dominoes in the chain")
    fit_from: int = Field(3, ge=1, description="front speed fitted from this domino on")
    mass: float = quantity(0.008, "kg", "domino mass", gt=0.0)
    young: float = quantity(2.39e9, "Pa", "Young's modulus of the plastic", gt=0.0)
    friction_dominoes: float = quantity(0.525, "", "domino-domino friction", ge=0.0)
    friction_floor: float = quantity(0.375, "", "domino-floor friction", ge=0.0)
    restitution_dominoes: float = quantity(0.5, "", "domino-domino restitution", gt=0.0, le=1.0)
    restitution_floor: float = quantity(0.5, "", "domino-floor restitution", gt=0.0, le=1.0)
    model: Literal["2d", "3d"] = Field("3d", description="DEM model")
    stiffness_ratio: float | None = quantity(
        None, "", "replaces the modulus by the paper's k/k* (cheap test chains)", gt=0.0
    )
    fidelity: float | Literal["exact"] | None = quantity(
        None,
        "",
        "exact (the plastic's contact) or the tolerance of the speed: the softest contact"
        f" whose estimated error stays within it (not set: {DEFAULT_TOLERANCE:g};"
        " chain.fidelity)",
    )

    @field_validator("fidelity")
    @classmethod
    def _fidelity(cls, value):
        return check_fidelity(value)

    def params(self):
        """The chain's :class:`~dominowave.chain.build.ChainParams`."""
        overrides = {"model": self.model}
        if self.stiffness_ratio is not None:
            overrides["stiffness_ratio"] = self.stiffness_ratio
        values = {name: getattr(self, name) for name in SAMPLED}
        return standard_domino(
            gap=self.gap, floor=self.floor, n_dominoes=self.n_dominoes, values=values, **overrides
        )


def run_predict_sample(cfg: PredictSample, ctx: RunContext | None = None) -> RunResult:
    """Run the chain of one sample and measure its front speed from ``fit_from`` on.

    The speed comes from the arrival times alone, so the run stops when the wave touches
    the last domino (``tail_time=0``: no aftermath; the arrivals are those of a run with
    it, to the bit)."""
    run = DominoChain(cfg.params(), fidelity=cfg.fidelity, tail_time=0.0).run()
    fit = speed_from(run.arrival, run.positions, cfg.fit_from)
    reached_all = bool(np.isfinite(run.arrival[-1]) and fit.reached == cfg.n_dominoes)
    # the estimate at the larger of the a-priori speed and this sample's measured one
    error = 0.0 if run.fidelity is None else run.fidelity.error_at(fit.speed)
    summary = {
        "sample": cfg.sample,
        **{name: getattr(cfg, name) for name in SAMPLED},
        "speed": fit.speed if reached_all else math.nan,
        "speed_err": fit.speed_err if reached_all else math.nan,
        "dominoes_toppled": int(fit.reached),
        "contact_kn": run.params.contact_stiffness,
        "stiffness_error": error,
        "wall_time": run.wall_time,
    }
    return RunResult(summary=summary, may_be_nan=("speed", "speed_err"))


@dataclass
class Prediction:
    """What :func:`predict` found.

    ``names`` the varied values, ``bounds`` their ranges, ``samples`` (S, D) their
    values, ``speed`` (S,) [m/s] (NaN: the wave died, or the point is missing),
    ``band`` the speeds at the quantiles :data:`BAND` [m/s], ``mean`` [m/s],
    ``n_died`` waves that did not reach the end, ``n_failed`` runs that failed (their
    ``failure.json`` in the sweep folder says why), ``n_missing`` points not run (an
    interrupted sweep: nothing is written then, and a re-run resumes),
    ``sobol_first``/``sobol_total`` (D,) indices with their 95 % confidence half-widths
    ``*_conf`` (NaN where undefined),
    ``effect`` (D,) [m/s] the change of the speed over each value's range (module
    docstring), ``fixed`` the values not varied, ``run`` what the sweep stored.
    ``leaning_speed`` (S,) [m/s] is the leaning train's steady speed
    (:mod:`dominowave.theory.leaning`) at each sample's friction between dominoes (the
    only material value it depends on) and ``leaning_band`` its quantiles :data:`BAND`.
    ``contact_kn`` (S,) [N/m] is the contact spring each chain ran with and
    ``stiffness_error`` (S,) [1] the estimated relative speed error of that spring
    against the plastic's (:mod:`dominowave.chain.fidelity`; NaN for a missing point),
    ``fidelity`` the setting of the chains (None: not set, the default tolerance).
    """

    gap: float
    floor: str
    names: tuple[str, ...]
    bounds: tuple[tuple[float, float], ...]
    samples: np.ndarray
    speed: np.ndarray
    band: tuple[float, float, float]
    mean: float
    n_died: int
    n_failed: int
    n_missing: int
    sobol_first: np.ndarray
    sobol_first_conf: np.ndarray
    sobol_total: np.ndarray
    sobol_total_conf: np.ndarray
    effect: np.ndarray
    fixed: dict[str, float]
    run: PresetRun
    leaning_speed: np.ndarray
    leaning_band: tuple[float, float, float]
    contact_kn: np.ndarray
    stiffness_error: np.ndarray
    fidelity: Fidelity = None

    @property
    def stiffness_error_max(self) -> float:
        """The largest estimated speed error of a chain's contact [1] (NaN if none ran)."""
        ran = self.stiffness_error[np.isfinite(self.stiffness_error)]
        return float(ran.max()) if ran.size else math.nan


def _problem(floor: str, materials=None) -> tuple[dict, dict[str, float]]:
    """SALib's problem of the varied values, and the fixed ones (zero-width ranges)."""
    entries = standard_entries(floor, materials)
    varied = {n: e.range for n, e in entries.items() if e.hi > e.lo}
    fixed = {n: e.value for n, e in entries.items() if not e.hi > e.lo}
    problem = {
        "num_vars": len(varied),
        "names": list(varied),
        "bounds": [list(b) for b in varied.values()],
    }
    return problem, fixed


def predict_points(
    gap: float,
    floor: str,
    samples: int = 4,
    *,
    n_dominoes: int = 12,
    fit_from: int = 3,
    seed: int = 0,
    model: str = "3d",
    stiffness_ratio: float | None = None,
    fidelity: Fidelity = None,
) -> tuple[list[PredictSample], dict, np.ndarray, dict[str, float]]:
    """The points of a prediction: ``(points, problem, X, fixed)`` with ``X`` (S, D).

    ``samples`` is Saltelli's base size ``N`` (a power of 2: the Sobol' sequence's balance
    needs it), giving ``N (D + 2)`` points; ``seed`` scrambles the sequence; ``fidelity``
    that of every chain (:mod:`dominowave.chain.fidelity`: not set, the softest contact
    within 2 % of the plastic's speed; ``"exact"``, the plastic's own).
    """
    check_fidelity(fidelity)
    from SALib.sample import sobol as sobol_sample

    if isinstance(samples, bool) or not isinstance(samples, int) or samples < 1:
        raise ValueError(f"samples = {samples!r} must be a power of 2 (1, 2, 4, 8, ...)")
    if samples & (samples - 1):
        raise ValueError(f"samples = {samples} is not a power of 2 (1, 2, 4, 8, ...)")
    check_fit_from(fit_from, n_dominoes)
    materials = load_materials()
    problem, fixed = _problem(floor, materials)
    n_points = samples * (problem["num_vars"] + 2)  # Saltelli without second order
    check_memory(
        BYTES_PER_POINT * n_points,
        f"the {n_points} chains of its design",
        f"samples = {samples} ({n_points} chains)",
    )
    # bad input now, not in the workers: the chain, and a tolerance for a chain without
    # the plastic's modulus (stiffness_ratio replaces it)
    stiffness = {} if stiffness_ratio is None else {"stiffness_ratio": stiffness_ratio}
    nominal = standard_domino(gap=gap, floor=floor, n_dominoes=n_dominoes, model=model, **stiffness)
    choose_contact(nominal, fidelity)
    x = sobol_sample.sample(problem, samples, calc_second_order=False, seed=seed)
    points = []
    for i, row in enumerate(x):
        values = dict(fixed) | dict(zip(problem["names"], (float(v) for v in row), strict=True))
        points.append(
            PredictSample(
                sample=i,
                gap=gap,
                floor=floor,
                n_dominoes=n_dominoes,
                fit_from=fit_from,
                model=model,
                stiffness_ratio=stiffness_ratio,
                fidelity=fidelity,
                **values,
            )
        )
    return points, problem, x, fixed


def predict(
    gap: float,
    floor: str,
    out_dir: Path,
    samples: int = 4,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    client=None,
    progress: Callable[[dict], None] | None = None,
    **design,
) -> Prediction:
    """Predict the front speed [m/s] of standard dominoes at ``gap`` [m] on ``floor``.

    Runs (or resumes) the points of :func:`predict_points` (``gap``, ``floor``,
    ``samples`` and the keywords ``design`` of its chains: ``n_dominoes``, ``fit_from``,
    ``seed``, ``model``, ``stiffness_ratio``, ``fidelity``) in the sweep folder
    ``out_dir`` and writes there ``samples.csv`` and ``samples.nc`` (every sample's
    values and speed) and ``prediction.csv`` (the band, the mean and the Sobol' indices).
    ``workers`` processes (default ``min(2, cores)``), or ``scheduler``/``client``.
    """
    points, problem, x, fixed = predict_points(gap, floor, samples, **design)
    out_dir = Path(out_dir)
    done = run_preset(
        points,
        out_dir,
        workers=workers or min(2, os.cpu_count() or 1),
        scheduler=scheduler,
        client=client,
        progress=progress,
    )
    speed = _summary_column(done.summaries, "speed")
    prediction = _analyse(gap, floor, problem, x, speed, fixed, done)
    prediction.fidelity = points[0].fidelity
    if prediction.n_missing == 0:  # a point that did not run is never written as a result
        write_prediction(prediction, out_dir)
    return prediction


def _analyse(gap, floor, problem, x, speed, fixed, done) -> Prediction:
    """Band, mean and Sobol' indices of ``speed`` (S,) over the samples ``x`` (S, D)."""
    from SALib.analyze import sobol as sobol_analyze

    d = problem["num_vars"]
    finite = speed[np.isfinite(speed)]
    n_failed = len(done.failed) if done is not None else 0
    n_missing = 0 if done is None else _count_missing(done)
    band = tuple(float(q) for q in np.quantile(finite, BAND)) if finite.size else (math.nan,) * 3
    nan = np.full(d, math.nan)
    first, first_conf, total, total_conf, effect = nan, nan, nan, nan, nan
    complete = finite.size == speed.size and d > 0
    if complete:
        effect = _effects(problem, x, speed)
    if complete and speed.size // (d + 2) >= SOBOL_MIN_BASE and np.ptp(speed) > 0:
        si = sobol_analyze.analyze(problem, speed, calc_second_order=False, seed=0)
        first, first_conf = np.asarray(si["S1"]), np.asarray(si["S1_conf"])
        total, total_conf = np.asarray(si["ST"]), np.asarray(si["ST_conf"])
    leaning_speed = _leaning_speeds(gap, problem, x, fixed)
    lean_ok = leaning_speed[np.isfinite(leaning_speed)]
    lean_band = tuple(float(q) for q in np.quantile(lean_ok, BAND)) if lean_ok.size else band
    summaries = [None] * speed.size if done is None else done.summaries
    return Prediction(
        contact_kn=_summary_column(summaries, "contact_kn"),
        stiffness_error=_summary_column(summaries, "stiffness_error"),
        gap=gap,
        floor=floor,
        names=tuple(problem["names"]),
        bounds=tuple((float(lo), float(hi)) for lo, hi in problem["bounds"]),
        samples=x,
        speed=speed,
        band=band,
        mean=float(finite.mean()) if finite.size else math.nan,
        n_died=int(speed.size - finite.size) - n_failed - n_missing,
        n_failed=n_failed,
        n_missing=n_missing,
        sobol_first=first,
        sobol_first_conf=first_conf,
        sobol_total=total,
        sobol_total_conf=total_conf,
        effect=effect,
        fixed=fixed,
        run=done,
        leaning_speed=leaning_speed,
        leaning_band=lean_band if lean_ok.size else (math.nan,) * 3,
    )


def _summary_column(summaries, name: str) -> np.ndarray:
    """``name`` of every point's summary, (S,); NaN where a point has none."""
    return np.array([math.nan if s is None else float(s.get(name, math.nan)) for s in summaries])


def _leaning_speeds(gap, problem, x, fixed) -> np.ndarray:
    """The leaning train's speed [m/s] at each sample's friction between dominoes, (S,)."""
    from dominowave.chain.materials import load_materials
    from dominowave.theory import leaning

    domino = load_materials().domino
    names = list(problem["names"])
    if "friction_dominoes" in names:
        friction = x[:, names.index("friction_dominoes")]
    else:
        friction = np.full(len(x), fixed["friction_dominoes"])
    return np.asarray(
        leaning.limit_speed(
            height=domino.height.value, thickness=domino.thickness.value, gap=gap, friction=friction
        ),
        dtype=float,
    ).reshape(-1)


def _count_missing(done) -> int:
    """Points the sweep did not run (interrupted): no summary and no recorded failure."""
    failed = set(done.failed)
    return sum(s is None and i not in failed for i, s in enumerate(done.summaries))


def _effects(problem: dict, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Mean change of ``y`` over each input's whole range [units of y], shape (D,), from
    the one-at-a-time pairs of Saltelli's design: blocks of ``D + 2`` rows
    ``A, AB_1, ..., AB_D, B`` per base sample (SALib's layout without second order)."""
    d = problem["num_vars"]
    width = np.ptp(np.asarray(problem["bounds"], dtype=float), axis=1)
    blocks = x.reshape(-1, d + 2, d)
    values = y.reshape(-1, d + 2)
    out = np.empty(d)
    for i in range(d):
        step = blocks[:, i + 1, i] - blocks[:, 0, i]
        ok = step != 0.0
        slopes = (values[ok, i + 1] - values[ok, 0]) / step[ok]
        out[i] = float(slopes.mean()) * width[i] if slopes.size else math.nan
    return out


def _fidelity_text(fidelity: Fidelity) -> str:
    """The fidelity as stored: ``exact`` or the tolerance (not set: the default's)."""
    tolerance = tolerance_of(fidelity)
    return EXACT if tolerance is None else f"{tolerance:g}"


def write_prediction(pred: Prediction, out_dir: Path) -> list[Path]:
    """``samples.csv``, ``samples.nc`` and ``prediction.csv`` of ``pred`` in ``out_dir``."""
    import xarray as xr

    out_dir = Path(out_dir)
    rows = [
        {
            "sample": i,
            **dict(zip(pred.names, map(float, row), strict=True)),
            "speed": v,
            "leaning_speed": lean,
            "contact_kn": kn,
            "stiffness_error": err,
        }
        for i, (row, v, lean, kn, err) in enumerate(
            zip(
                pred.samples,
                pred.speed,
                pred.leaning_speed,
                pred.contact_kn,
                pred.stiffness_error,
                strict=True,
            )
        )
    ]
    columns = ["sample", *pred.names, "speed", "leaning_speed", "contact_kn", "stiffness_error"]
    with (out_dir / SAMPLES_CSV).open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=columns)
        writer.writeheader()
        writer.writerows(rows)
    units = {"mass": "kg", "young": "Pa"}
    data = {
        name: ("sample", pred.samples[:, j], {"units": units.get(name, "1")})
        for j, name in enumerate(pred.names)
    }
    data["speed"] = ("sample", pred.speed, {"units": "m/s", "long_name": "front speed"})
    data["leaning_speed"] = (
        "sample",
        pred.leaning_speed,
        {"units": "m/s", "long_name": "steady speed of the leaning train"},
    )
    data["contact_kn"] = (
        "sample",
        pred.contact_kn,
        {"units": "N/m", "long_name": "contact spring per point the chain ran with"},
    )
    data["stiffness_error"] = (
        "sample",
        pred.stiffness_error,
        {"units": "1", "long_name": "estimated relative speed error of that spring"},
    )
    ds = xr.Dataset(
        data,
        coords={"sample": np.arange(pred.speed.size)},
        attrs={
            "gap_m": pred.gap,
            "floor": pred.floor,
            "band_quantiles": list(BAND),
            "band_m_s": list(pred.band),
            **{f"fixed_{k}": v for k, v in pred.fixed.items()},
            "fidelity": _fidelity_text(pred.fidelity),
        },
    )
    ds.to_netcdf(out_dir / SAMPLES_NC)
    with (out_dir / SUMMARY_CSV).open("w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["quantity", "value", "conf95", "unit"])
        for q, v in zip(BAND, pred.band, strict=True):
            writer.writerow([f"speed_q{round(100 * q):02d}", v, "", "m/s"])
        writer.writerow(["speed_mean", pred.mean, "", "m/s"])
        for q, v in zip(BAND, pred.leaning_band, strict=True):
            writer.writerow([f"leaning_speed_q{round(100 * q):02d}", v, "", "m/s"])
        writer.writerow(["stiffness_error_max", pred.stiffness_error_max, "", "1"])
        writer.writerow(["waves_died", pred.n_died, "", "1"])
        writer.writerow(["runs_failed", pred.n_failed, "", "1"])
        for j, name in enumerate(pred.names):
            writer.writerow([f"effect_{name}", pred.effect[j], "", "m/s"])
            writer.writerow([f"S1_{name}", pred.sobol_first[j], pred.sobol_first_conf[j], "1"])
            writer.writerow([f"ST_{name}", pred.sobol_total[j], pred.sobol_total_conf[j], "1"])
    return [out_dir / SAMPLES_CSV, out_dir / SAMPLES_NC, out_dir / SUMMARY_CSV]
