"""A stored point whose files do not parse is no result: it is set aside and runs again."""

from __future__ import annotations

import tomllib

import pytest

from dominowave.io.config import load_study
from dominowave.io.results import read_summary, unreadable_file
from dominowave.sweep.runner import run_sweep

THEORY = (
    '[scenario]\nkind = "theory"\nn_dominoes = 6\nn_frames = 12\n'
    "[sweep.grid]\nd_over_l = [0.3, 0.5]\n[output]\ntrajectory = true\n"
)
RODS = (  # the kind that stores time series
    '[scenario]\nkind = "rods"\nn_dominoes = 5\nstiffness_ratio = 1e3\n'
    "[sweep.grid]\nd_over_l = [0.3, 0.5]\n"
)


def _truncate(path):
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])


def _garble(path):
    path.write_text(path.read_text()[:-7] + "\x00{oops")


DAMAGE = {  # every file a point stores, spoiled the way a crash or a full disk spoils it
    "summary.json": _truncate,
    "provenance.json": _garble,
    "config.toml": _garble,
    "events.csv": lambda p: p.write_text(p.read_text() + "1.0,abc\n"),
    "timeseries.nc": _truncate,
    "trajectory.nc": _truncate,
}


@pytest.mark.parametrize("name", sorted(DAMAGE))
def test_a_point_with_an_unreadable_file_runs_again(dask_client, tmp_path, name):
    path = tmp_path / "study.toml"
    path.write_text(RODS if name == "timeseries.nc" else THEORY)
    out = tmp_path / "sweep"
    run_sweep(load_study(path), out, client=dask_client, quiet=True)
    key = sorted(p.name for p in (out / "points").iterdir())[0]
    spoiled = out / "points" / key / name
    assert spoiled.is_file(), f"a point of this study stores {name}"
    assert unreadable_file(spoiled.parent) is None
    DAMAGE[name](spoiled)
    assert unreadable_file(spoiled.parent).startswith(f"{name}: ")
    report = run_sweep(load_study(path), out, client=dask_client, quiet=True)
    assert (report.skipped, report.ran, report.failed) == (1, 1, 0)
    (line,) = report.set_aside
    assert line.startswith(f"point {key}: {name}: ") and "it runs again" in line
    assert line in report.line()
    kept = out / "unreadable" / key / name  # set aside, not deleted
    assert kept.read_bytes() != b"" and unreadable_file(kept.parent) is not None
    assert unreadable_file(out / "points" / key) is None
    config = tomllib.loads((out / "points" / key / "config.toml").read_text())
    assert read_summary(out / "points" / key)["d_over_l"] == config["scenario"]["d_over_l"]
