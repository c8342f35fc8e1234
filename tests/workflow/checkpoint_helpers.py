"""Shared steps of the checkpoint tests of real runs (rods, DEM chain): kill a CLI run
after a checkpoint, interrupt an in-process run between chunks, compare result files."""

from __future__ import annotations

import os
import signal
import subprocess
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
