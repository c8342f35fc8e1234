"""Gather the points of a sweep folder into one ``xarray.Dataset``.

Every stored point becomes one entry along the dimension ``point`` (coordinate:
its key), with its summary values, its status and every field of its resolved
config (prefixed ``config_``). If the swept values form a complete cartesian
grid, the dataset is reshaped onto one dimension per swept field, so that
``ds.speed.sel(d_over_l=0.4)`` works. A summary value that is also swept (``d_over_l``)
is that coordinate (or ``summary_<name>`` if the run changed it).
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np

from dominowave.io.atomic import atomic_path
from dominowave.io.results import NETCDF_ENGINE, read_summary
from dominowave.sweep.store import SweepStore

__all__ = ["collect", "point_records", "write_collected"]


def point_records(folder: Path) -> list[dict]:
    """One dict per stored point: key, status, swept values, config, summary."""
    store = SweepStore(folder)
    index = store.read_index()
    records = []
    for key, entry in sorted(index["points"].items()):
        point_dir = store.root / entry["folder"]
        try:
            config = tomllib.loads((point_dir / "config.toml").read_text())["scenario"]
        except (OSError, tomllib.TOMLDecodeError, KeyError) as exc:
            raise ValueError(f"{point_dir / 'config.toml'}: unreadable ({exc})") from None
        summary = read_summary(point_dir) if entry["status"] == "ok" else {}
        records.append(
            {
                "key": key,
                "status": entry["status"],
                "swept": entry["swept"],
                "config": config,
                "summary": summary,
                "folder": point_dir,
            }
        )
    return records


def _column(values: list):
    """A NumPy column: float (NaN for missing), or str."""
    present = [v for v in values if v is not None]
    if present and all(isinstance(v, bool) for v in present):
        return np.array([np.nan if v is None else float(v) for v in values])
    if all(isinstance(v, int | float) and not isinstance(v, bool) for v in present):
        return np.array([np.nan if v is None else float(v) for v in values])
    return np.array(["" if v is None else str(v) for v in values], dtype=object)


def _same_where_given(column: np.ndarray, swept: np.ndarray) -> bool:
    """True if ``column`` equals ``swept`` wherever ``column`` has a value (a point that
    failed has no summary: NaN or "")."""
    if column.dtype == object or swept.dtype == object:
        return all(c == "" or c == w for c, w in zip(column, swept, strict=True))
    given = ~np.isnan(column)
    return bool(np.array_equal(column[given], swept[given]))


def collect(folder: str | Path):
    """The sweep in ``folder`` as an ``xarray.Dataset`` (see the module docstring)."""
    import xarray as xr

    records = point_records(Path(folder))
    if not records:
        raise ValueError(f"{folder}: the sweep has no stored points yet")
    keys = [r["key"] for r in records]
    swept = sorted({k for r in records for k in r["swept"]})
    coords = {"point": keys}
    for name in swept:
        coords[name] = ("point", _column([r["swept"].get(name) for r in records]))
    data = {"status": ("point", np.array([r["status"] for r in records], dtype=object))}
    summary_names = sorted({k for r in records for k in r["summary"]})
    for name in summary_names:
        column = _column([r["summary"].get(name) for r in records])
        if name in coords:  # a summary value that is also swept (e.g. d_over_l)
            if _same_where_given(column, coords[name][1]):
                continue  # the coordinate holds it
            name = f"summary_{name}"
        data[name] = ("point", column)
    config_names = sorted({k for r in records for k in r["config"]})
    for name in config_names:
        data[f"config_{name}"] = ("point", _column([r["config"].get(name) for r in records]))
    attrs = {"source": str(folder), "points_missing": _count_missing(Path(folder), keys)}
    ds = xr.Dataset(data, coords=coords, attrs=attrs)
    return _as_grid(ds, swept)


def _count_missing(folder: Path, keys: list[str]) -> int:
    """Points of the folder's study that are not stored (an interrupted sweep)."""
    from dominowave.io.config import load_study
    from dominowave.sweep.hashing import point_key

    study = folder / "study.toml"
    if not study.is_file():
        return 0
    return len({point_key(p) for p in load_study(study).points} - set(keys))


def _as_grid(ds, swept: list[str]):
    """Reshape onto the swept fields if they form a complete grid (else unchanged)."""
    if not swept:
        return ds
    columns = [ds[name].values for name in swept]
    if any(c.dtype == object for c in columns):
        return ds
    combos = {tuple(c[i] for c in columns) for i in range(ds.sizes["point"])}
    full = math.prod(len(np.unique(c)) for c in columns)
    if len(combos) != ds.sizes["point"] or len(combos) != full:
        return ds
    if len(swept) == 1:  # one swept field: its values index the points (no multi-index)
        return ds.swap_dims({"point": swept[0]}).drop_vars("point").sortby(swept[0])
    return ds.set_index(point=swept).unstack("point")


def write_collected(ds, path: str | Path) -> Path:
    """Write the collected dataset to netCDF atomically; return the path."""
    path = Path(path)
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, engine=NETCDF_ENGINE)
    return path
