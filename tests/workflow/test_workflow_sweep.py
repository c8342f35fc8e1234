"""Sweeps on a real LocalCluster: every point exactly once, failures recorded, kill + resume."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from dominowave.io.atomic import TMP_PREFIX
from dominowave.io.config import load_study
from dominowave.io.results import read_summary
from dominowave.sweep.collect import collect, write_collected
from dominowave.sweep.hashing import point_key
from dominowave.sweep.runner import run_sweep

HERE = Path(__file__).parent
EXAMPLE = HERE.parents[1] / "examples" / "fig4_theory_sweep.toml"
CLI = [sys.executable, str(HERE / "cli_with_helpers.py")]


def write_study(tmp_path: Path, body: str) -> Path:
    path = tmp_path / "study.toml"
    path.write_text(body)
    return path


def expected_keys(study_path: Path) -> set[str]:
    return {point_key(p) for p in load_study(study_path).points}


def stored(folder: Path, leftovers_allowed: bool = False) -> dict[str, str]:
    """key -> status of the complete point folders (half-written ones only if allowed)."""
    names = [p.name for p in (folder / "points").iterdir()]
    if not leftovers_allowed:
        assert not [n for n in names if n.startswith(TMP_PREFIX)], names
    out = {}
    for name in names:
        if name.startswith(TMP_PREFIX):  # being written when the client was killed
            continue
        if (folder / "points" / name / "summary.json").is_file():
            out[name] = "ok"
        elif (folder / "points" / name / "failure.json").is_file():
            out[name] = "failed"
    return out


def test_sweep_stores_each_point_once_and_skips_them_next_time(dask_client, tmp_path):
    path = write_study(
        tmp_path,
        '[scenario]\nkind = "theory"\nn_dominoes = 10\nn_frames = 20\n'
        "[sweep.grid]\nd_over_l = [0.25, 0.5, 0.75]\nstiffness_ratio = [100.0, 1e4]\n",
    )
    out = tmp_path / "sweep"
    report = run_sweep(load_study(path), out, client=dask_client, quiet=True)
    assert (report.total, report.skipped, report.ran, report.failed) == (6, 0, 6, 0)
    assert stored(out) == dict.fromkeys(expected_keys(path), "ok")
    index = json.loads((out / "index.json").read_text())
    assert set(index["points"]) == expected_keys(path)
    assert {tuple(e["swept"].values()) for e in index["points"].values()} == {
        (s, k) for s in (0.25, 0.5, 0.75) for k in (100.0, 1e4)
    }
    mtimes = {p: p.stat().st_mtime_ns for p in (out / "points").rglob("*")}
    again = run_sweep(load_study(path), out, client=dask_client, quiet=True)
    assert (again.skipped, again.ran) == (6, 0)
    assert {p: p.stat().st_mtime_ns for p in (out / "points").rglob("*")} == mtimes


def test_failed_points_are_recorded_and_the_sweep_goes_on(dask_client, tmp_path):
    path = write_study(
        tmp_path,
        '[scenario]\nkind = "slow_theory"\nn_dominoes = 8\nn_frames = 10\nfail_above = 0.02\n'
        "[sweep.grid]\nd_over_l = [0.2, 0.3, 0.5, 0.6]\n",
    )
    out = tmp_path / "sweep"
    report = run_sweep(load_study(path), out, client=dask_client, quiet=True)
    assert (report.ran, report.failed) == (4, 2)
    status = stored(out)
    assert sorted(status.values()) == ["failed", "failed", "ok", "ok"]
    for key, s in status.items():
        if s == "failed":
            failure = json.loads((out / "points" / key / "failure.json").read_text())
            assert failure["error"].startswith("RuntimeError: deliberate failure at spacing 0.0")
            assert "run_slow_theory" in failure["traceback"]
    # failed points are kept (not retried) unless asked
    assert run_sweep(load_study(path), out, client=dask_client, quiet=True).ran == 0
    retry = run_sweep(load_study(path), out, client=dask_client, quiet=True, retry_failed=True)
    assert (retry.ran, retry.failed) == (2, 2)
    assert len(stored(out)) == 4


def test_collect_puts_a_grid_on_its_axes(dask_client, tmp_path):
    import xarray as xr

    path = write_study(
        tmp_path,
        '[scenario]\nkind = "theory"\nn_dominoes = 6\nn_frames = 10\n'
        "[sweep.grid]\nd_over_l = [0.25, 0.5]\nstiffness_ratio = [10.0, 100.0, 1e3]\n",
    )
    out = tmp_path / "sweep"
    run_sweep(load_study(path), out, client=dask_client, quiet=True)
    ds = collect(out)
    assert dict(ds.sizes) == {"d_over_l": 2, "stiffness_ratio": 3}
    for key in expected_keys(path):
        summary = read_summary(out / "points" / key)
        cell = ds.sel(
            d_over_l=summary["d_over_l"],
            stiffness_ratio=round(summary["stiffness_over_kstar"], 6),
            method="nearest",
        )
        assert float(cell.speed) == summary["speed"]
    nc = write_collected(ds, out / "collected.nc")
    with xr.open_dataset(nc) as back:
        np.testing.assert_array_equal(back.speed.values, ds.speed.values)
    assert ds.attrs["points_missing"] == 0


def test_collect_of_an_incomplete_sweep_says_it_is_partial(dask_client, tmp_path):
    """A sweep that lost points (interrupted, or a crash) collects into a file named and
    marked partial, with the count of the points missing and how to run them."""
    path = write_study(
        tmp_path,
        '[scenario]\nkind = "theory"\nn_dominoes = 6\nn_frames = 10\n'
        "[sweep.grid]\nd_over_l = [0.25, 0.5, 0.75]\n",
    )
    out = tmp_path / "sweep"
    run_sweep(load_study(path), out, client=dask_client, quiet=True)
    import shutil

    from dominowave.sweep.store import SweepStore

    shutil.rmtree(sorted((out / "points").iterdir())[0])  # a point the sweep never stored
    SweepStore(out).write_index({})
    proc = subprocess.run([*CLI, "collect", str(out)], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "partial: 1 point(s) of the study are not stored" in proc.stdout
    assert (out / "collected.partial.nc").is_file() and not (out / "collected.nc").exists()
    partial = collect(out)
    assert partial.attrs["points_missing"] == 1
    assert dict(partial.sizes) == {"d_over_l": 2}  # one swept field: on its axis


def _wait_for(predicate, timeout: float, what: str):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return
        time.sleep(0.01)
    raise AssertionError(f"timed out waiting for {what}")


@pytest.mark.slow
def test_killed_sweep_resumes_with_every_point_exactly_once(dask_client, tmp_path):
    """SIGKILL the sweep client of the example study part-way (and a worker), then resume."""
    out = tmp_path / "fig4"
    keys = expected_keys(EXAMPLE)
    cmd = [*CLI, "sweep", str(EXAMPLE), "--out", str(out), "--workers", "2", "--quiet"]
    proc = subprocess.Popen(cmd, start_new_session=True)
    try:
        points = out / "points"
        count = lambda: sum(1 for p in points.glob("*") if not p.name.startswith(TMP_PREFIX))  # noqa: E731
        _wait_for(lambda: points.is_dir() and count() >= 8, 120, "8 stored points")
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)  # the LocalCluster's worker processes too
    before = stored(out, leftovers_allowed=True)  # a point may have been half-written
    assert 8 <= len(before) < len(keys), "the sweep must be killed part-way"
    assert set(before.values()) == {"ok"}
    before_mtimes = {k: (out / "points" / k / "summary.json").stat().st_mtime_ns for k in before}
    # resume on an existing cluster; one of its workers is killed while the points run
    addr = dask_client.scheduler.address
    resume = subprocess.Popen(
        [*CLI, "resume", str(out), "--scheduler", addr, "--quiet"],
        stdout=subprocess.PIPE,
        text=True,
    )
    _wait_for(
        lambda: len(stored(out, True)) > len(before) or resume.poll() is not None, 60, "resume"
    )
    pid = next(iter(dask_client.run(os.getpid).values()))
    os.kill(pid, signal.SIGKILL)
    stdout, _ = resume.communicate(timeout=120)
    assert resume.returncode == 0, stdout
    n_keys, n_before = len(keys), len(before)
    assert f"{n_keys} points, {n_before} already stored, {n_keys - n_before} run now" in stdout
    assert "(0 failed)" in stdout
    after = stored(out)
    assert after == dict.fromkeys(keys, "ok")  # every point, once, none failed
    for key, mtime in before_mtimes.items():  # points stored before the kill were kept as is
        assert (out / "points" / key / "summary.json").stat().st_mtime_ns == mtime
    index = json.loads((out / "index.json").read_text())
    assert set(index["points"]) == keys and index["n_points"] == len(keys)
    dask_client.wait_for_workers(2, timeout=60)
