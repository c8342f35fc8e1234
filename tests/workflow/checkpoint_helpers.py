"""Shared steps of the checkpoint tests of real runs (rods, DEM chains of clumps and of
boxes): kill a CLI run after a checkpoint, interrupt an in-process run between chunks,
compare result files."""

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
import xarray as xr

from dominowave.io.checkpoint import load_checkpoint
from dominowave.io.results import read_summary
from dominowave.sweep.registry import RunContext


def kill_after_checkpoint(proc: subprocess.Popen, checkpoint: Path, steps: int) -> int:
    """SIGKILL ``proc`` once ``checkpoint`` holds at least ``steps``; return the step count
    of the checkpoint left behind."""
    end = time.monotonic() + 60
    while time.monotonic() < end and proc.poll() is None:
        if checkpoint.is_file() and load_checkpoint(checkpoint)[1]["steps"] >= steps:
            break
        time.sleep(0.01)
    if proc.poll() is None:  # (else it ended first: the caller's asserts say so)
        os.kill(proc.pid, signal.SIGKILL)
    proc.wait(timeout=30)
    return load_checkpoint(checkpoint)[1]["steps"]


def assert_netcdf_identical(ref: Path, out: Path) -> xr.Dataset:
    """Every variable of the two netCDF files has the same dtype and the same bits."""
    with xr.open_dataset(ref) as a_ds, xr.open_dataset(out) as b_ds:
        a, b = a_ds.load(), b_ds.load()
    assert set(a.variables) == set(b.variables)
    for var in a.variables:
        assert a[var].dtype == b[var].dtype
        assert np.array_equal(a[var].values, b[var].values, equal_nan=True), (out.name, var)
    return a


def interrupt_then_resume(run, cfg, folder: Path, at_step: int = 3000):
    """Run ``run(cfg)`` with a Ctrl-C raised between chunks once ``at_step`` steps are done,
    check the final checkpoint, then resume: return (partial summary, resumed result)."""

    def interrupt(**progress):
        if progress["steps"] >= at_step:
            raise KeyboardInterrupt

    checkpoint = folder / "checkpoint"
    checkpoint.mkdir(parents=True)
    ctx = RunContext(progress=interrupt, checkpoint_dir=checkpoint, checkpoint_every_seconds=3600)
    with pytest.raises(KeyboardInterrupt):
        run(cfg, ctx)
    assert load_checkpoint(checkpoint / "state.npz")[1]["steps"] == at_step
    partial = read_summary(folder / "partial")
    return partial, run(cfg, RunContext(checkpoint_dir=checkpoint))


CLI = [sys.executable, "-m", "dominowave"]


def kill_and_resume(study_text: str, tmp_path: Path, every: int, checkpoints: int):
    """Run the study ``study_text`` from the CLI once uninterrupted (folder ``ref``), once
    with a checkpoint every ``every`` steps, SIGKILLed once ``checkpoints`` of them are
    written (folder ``killed``, which must hold no summary then), and ``resume`` the
    latter.  Returns (ref, killed, the step count of the checkpoint it resumed from)."""
    study = tmp_path / "study.toml"
    study.write_text(study_text)
    ref = tmp_path / "ref"
    subprocess.run([*CLI, "run", str(study), "--out", str(ref), "--quiet"], check=True)
    out = tmp_path / "killed"
    proc = subprocess.Popen(
        [*CLI, "run", str(study), "--out", str(out), "--checkpoint", f"steps={every}", "--quiet"]
    )
    checkpoint = out / "checkpoint" / "state.npz"
    steps_at_kill = kill_after_checkpoint(proc, checkpoint, checkpoints * every)
    assert not (out / "summary.json").exists(), "the run must be killed before it ends"
    subprocess.run([*CLI, "resume", str(out), "--quiet"], check=True)
    return ref, out, steps_at_kill


def chain_summary(folder: Path) -> dict:
    """summary.json of a run folder without the CPU time spent (the one number that may
    differ between two runs)."""
    summary = json.loads((folder / "summary.json").read_text())
    summary.pop("engine_wall_time")
    return summary


def assert_killed_chain_run_resumes(study_text: str, tmp_path: Path, every: int) -> dict:
    """Run the chain study ``study_text`` from the CLI once uninterrupted, once with a
    checkpoint every ``every`` steps, SIGKILLed after the second; ``resume`` it: the
    summary (every number, to the last digit), events and result files have the bits of
    the uninterrupted run, which stopped on "touched", and the finished run keeps no
    checkpoint.  Returns the summary."""
    ref, out, steps_at_kill = kill_and_resume(study_text, tmp_path, every, 2)
    summary = chain_summary(ref)
    assert steps_at_kill % every == 0 and 2 * every <= steps_at_kill < summary["n_steps"]
    assert chain_summary(out) == summary and summary["stop_reason"] == "touched"
    assert json.dumps(chain_summary(out)) == json.dumps(summary)  # to the last digit
    assert (out / "events.csv").read_bytes() == (ref / "events.csv").read_bytes()
    for name in ("timeseries.nc", "trajectory.nc"):  # tilt, omega, base of every domino
        assert assert_netcdf_identical(ref / name, out / name).sizes["time"] > 100
    assert not (out / "checkpoint").exists()  # a finished run keeps no checkpoint
    return summary


def assert_interrupted_chain_run_resumes(run, cfg, folder: Path) -> None:
    """Ctrl-C (raised between chunks) at step 3000 of ``run(cfg)`` writes the final
    checkpoint and the partial results of a running wave; running the same config again
    resumes and ends with the summary, events and time series of an uninterrupted run,
    bit for bit."""
    reference = run(cfg)
    partial, resumed = interrupt_then_resume(run, cfg, folder, at_step=3000)
    assert partial["n_steps"] == 3000 and partial["stop_reason"] == "running"
    assert partial["dominoes_toppled"] < cfg.n_dominoes
    for summary in (resumed.summary, reference.summary):
        summary.pop("engine_wall_time")
    assert json.dumps(resumed.summary) == json.dumps(reference.summary)
    for name in reference.events:
        assert np.array_equal(resumed.events[name], reference.events[name], equal_nan=True)
    assert resumed.timeseries.identical(reference.timeseries)
