"""The files of one run (a single run or one sweep point).

A result folder holds::

    config.toml       the resolved scenario (every field, defaults filled in)
    provenance.json   versions, git commit, seed, machine, wall time, config key
    summary.json      scalar results (wave speeds, times, ...), SI units
    events.csv        one row per event (e.g. per domino: arrival time, Omega_n)
    timeseries.nc     time series as netCDF (xarray)
    trajectory.nc     per-frame domino angles, for `dominowave animate` (optional)

or, for a point that failed, ``config.toml``, ``provenance.json`` and
``failure.json`` (error and traceback). The folder is built under a temporary
name and renamed into place, so it is either complete or absent.
"""

from __future__ import annotations

import csv
import io
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from dominowave.io.atomic import atomic_dir, atomic_path, write_json, write_text
from dominowave.io.toml_text import dumps
from dominowave.io.trajectory import ChainTrajectory, SphereTrajectory

__all__ = [
    "NETCDF_ENGINE",
    "RunResult",
    "read_events",
    "read_summary",
    "read_trajectory",
    "result_status",
    "unreadable_file",
    "write_events_csv",
    "write_failure_folder",
    "write_result_folder",
]

NETCDF_ENGINE = "netcdf4"
"""xarray engine for every netCDF file the package writes."""


@dataclass
class RunResult:
    """What a scenario returns.

    summary : scalar results, JSON-ready (floats in SI units, ints, strings, bools).
    events : column name -> (E,) array; written as events.csv.
    timeseries : ``xarray.Dataset`` or None.
    trajectory : :class:`ChainTrajectory` or None (drawn by ``dominowave animate``).
    may_be_nan : summary fields whose NaN means "undefined" (e.g. the steady speed
        of a wave that never settled); NaN anywhere else marks a failed run.
    spheres : :class:`SphereTrajectory` or None -- only for VTK output, not stored.
    """

    summary: dict[str, Any]
    events: dict[str, np.ndarray] = field(default_factory=dict)
    timeseries: Any = None
    trajectory: ChainTrajectory | None = None
    may_be_nan: tuple[str, ...] = ()
    spheres: SphereTrajectory | None = None


def write_events_csv(path: Path, events: dict[str, np.ndarray]) -> None:
    """Write equal-length columns as CSV with a header row (floats round-trip)."""
    columns = {k: np.asarray(v) for k, v in events.items()}
    lengths = {v.shape[0] for v in columns.values()} if columns else {0}
    if len(lengths) != 1:
        raise ValueError(f"event columns have different lengths: {sorted(lengths)}")
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(columns)
    for row in zip(*columns.values(), strict=True):
        writer.writerow([repr(float(x)) if isinstance(x, float | np.floating) else x for x in row])
    write_text(path, buf.getvalue())


def _write_netcdf(path: Path, ds) -> None:
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, engine=NETCDF_ENGINE)


def _fill_common(folder: Path, config: dict, prov: dict) -> None:
    write_text(folder / "config.toml", dumps({"scenario": config}))
    write_json(folder / "provenance.json", prov)


def write_result_folder(
    final: Path, config: dict, prov: dict, result: RunResult, keep_trajectory: bool = True
) -> bool:
    """Write a complete result folder at ``final`` atomically.

    Returns False if ``final`` already exists (nothing is overwritten).
    """

    def fill(folder: Path) -> None:
        _fill_common(folder, config, prov)
        write_json(folder / "summary.json", result.summary)
        write_events_csv(folder / "events.csv", result.events)
        if result.timeseries is not None:
            _write_netcdf(folder / "timeseries.nc", result.timeseries)
        if keep_trajectory and result.trajectory is not None:
            _write_netcdf(folder / "trajectory.nc", result.trajectory.to_dataset())

    return atomic_dir(final, fill)


def write_failure_folder(final: Path, config: dict, prov: dict, error: str, tb: str) -> bool:
    """Record a failed run: its config, provenance, error line and traceback."""

    def fill(folder: Path) -> None:
        _fill_common(folder, config, prov)
        write_json(folder / "failure.json", {"error": error, "traceback": tb})

    return atomic_dir(final, fill)


def result_status(folder: Path) -> str | None:
    """``"ok"``, ``"failed"``, or None if ``folder`` holds no complete result."""
    folder = Path(folder)
    if (folder / "summary.json").is_file():
        return "ok"
    if (folder / "failure.json").is_file():
        return "failed"
    return None


def unreadable_file(folder: Path) -> str | None:
    """None if every file a result folder stores parses, else one line naming the first
    that does not and why (a corrupt ``summary.json``, a truncated netCDF, ...).

    Reads each file in full: config.toml, provenance.json, summary.json or failure.json,
    events.csv, timeseries.nc and trajectory.nc where present.
    """
    import tomllib

    import xarray as xr

    folder = Path(folder)
    checks = [
        ("config.toml", lambda p: tomllib.loads(p.read_text(encoding="utf-8"))),
        ("provenance.json", _read_json),
        ("summary.json" if (folder / "summary.json").exists() else "failure.json", _read_json),
    ]
    if (folder / "summary.json").exists():
        checks.append(("events.csv", lambda p: read_events(p.parent)))
    for name in ("timeseries.nc", "trajectory.nc"):
        if (folder / name).exists():
            checks.append((name, lambda p: xr.load_dataset(p, engine=NETCDF_ENGINE)))
    for name, read in checks:
        try:
            read(folder / name)
        except Exception as exc:  # any parse failure: the file is not a stored result
            first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            return f"{name}: {first}"
    return None


def _read_json(path: Path) -> dict:
    try:
        return json.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ValueError(f"{path}: not found (is {Path(path).parent} a result folder?)") from None
    except (OSError, json.JSONDecodeError) as exc:
        raise ValueError(f"{path}: unreadable ({exc})") from None


def read_summary(folder: Path) -> dict:
    """The summary.json of a result folder; a ``null`` value (a non-finite number in
    strict JSON, see :func:`~dominowave.io.atomic.write_json`) reads as NaN."""
    summary = _read_json(Path(folder) / "summary.json")
    return {key: math.nan if value is None else value for key, value in summary.items()}


def read_events(folder: Path) -> dict[str, np.ndarray]:
    """events.csv as column name -> float array (empty dict if there are no events)."""
    path = Path(folder) / "events.csv"
    try:
        rows = list(csv.reader(path.read_text(encoding="utf-8").splitlines()))
    except FileNotFoundError:
        raise ValueError(f"{path}: not found (is {folder} a result folder?)") from None
    if not rows:
        return {}
    header, body = rows[0], rows[1:]
    try:
        data = np.array(body, dtype=float).reshape(len(body), len(header))
    except ValueError as exc:  # a cut or altered file: ragged rows, text for numbers
        raise ValueError(f"{path}: unreadable ({exc})") from None
    return {name: data[:, i] for i, name in enumerate(header)}


def read_trajectory(folder: Path) -> ChainTrajectory:
    """The trajectory.nc of a result folder."""
    import xarray as xr

    path = Path(folder) / "trajectory.nc"
    if not path.is_file():
        raise ValueError(
            f"{path}: not found; the run kept no trajectory (set output.trajectory = true)"
        )
    with xr.open_dataset(path, engine=NETCDF_ENGINE) as ds:
        return ChainTrajectory.from_dataset(ds.load())
