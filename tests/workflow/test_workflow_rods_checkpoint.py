"""A real rods run, killed with SIGKILL mid-run and resumed, ends with the bits of an
uninterrupted run (dominowave.rods.RodStepper through `run --checkpoint` / `resume`)."""

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
from dominowave.io.models import RodsScenario
from dominowave.io.results import read_summary
from dominowave.sweep.registry import RunContext
from dominowave.sweep.run_rods import run_rods

CLI = [sys.executable, "-m", "dominowave"]

# thick blocks with dashpot and friction (every branch of the contact code), resolved
# finely enough that the run takes ~850 000 steps (~2 s): long enough to be killed
STUDY = """\
[scenario]
kind = "rods"
n_dominoes = 30
height = 0.048
thickness = 0.0075
spacing = 0.024
mass = 0.008
mass_model = "block"
damping_ratio = 0.05
contact_friction = 0.2
steps_per_contact = 1000.0
"""
EVERY = 50_000
"""Checkpoint interval [steps]."""


def _timeseries(folder: Path) -> xr.Dataset:
    with xr.open_dataset(folder / "timeseries.nc") as ds:
        return ds.load()


def _kill_after_checkpoint(proc: subprocess.Popen, checkpoint: Path, steps: int) -> None:
    """SIGKILL ``proc`` once ``checkpoint`` holds at least ``steps``."""
    end = time.monotonic() + 60
    while time.monotonic() < end and proc.poll() is None:
        if checkpoint.is_file() and load_checkpoint(checkpoint)[1]["steps"] >= steps:
            break
        time.sleep(0.01)
    if proc.poll() is None:  # (else it ended first: the caller's asserts say so)
        os.kill(proc.pid, signal.SIGKILL)
    proc.wait(timeout=30)


def test_sigkilled_rods_run_resumes_bit_identically(tmp_path):
    study = tmp_path / "rods_study.toml"
    study.write_text(STUDY)
    ref = tmp_path / "ref"
    subprocess.run([*CLI, "run", str(study), "--out", str(ref), "--quiet"], check=True)
    out = tmp_path / "killed"
    proc = subprocess.Popen(
        [*CLI, "run", str(study), "--out", str(out), "--checkpoint", f"steps={EVERY}", "--quiet"]
    )
    checkpoint = out / "checkpoint" / "state.npz"
    _kill_after_checkpoint(proc, checkpoint, 3 * EVERY)
    assert not (out / "summary.json").exists(), "the run must be killed before it ends"
    steps_at_kill = load_checkpoint(checkpoint)[1]["steps"]
    summary = (ref / "summary.json").read_text()
    assert (
        steps_at_kill % EVERY == 0 and 3 * EVERY <= steps_at_kill < json.loads(summary)["n_steps"]
    )
    subprocess.run([*CLI, "resume", str(out), "--quiet"], check=True)

    assert (out / "summary.json").read_text() == summary  # every number, to the last digit
    assert (out / "events.csv").read_bytes() == (ref / "events.csv").read_bytes()
    a, b = _timeseries(ref), _timeseries(out)
    assert set(a.variables) == set(b.variables)
    for name in a.variables:  # energies, time and the (E, 13) contact table
        assert a[name].dtype == b[name].dtype
        assert np.array_equal(a[name].values, b[name].values, equal_nan=True), name
    assert not (out / "checkpoint").exists()  # a finished run keeps no checkpoint


def test_interrupted_rods_run_saves_state_and_partial_results_then_resumes(tmp_path):
    """Ctrl-C (here: raised between chunks) writes the final checkpoint and the partial
    results; running the same config again resumes and ends with the same bits."""
    cfg = RodsScenario(n_dominoes=12, mass_model="block", contact_friction=0.2)
    reference = run_rods(cfg)
    assert reference.summary["n_steps"] > 5000

    def interrupt(**progress):
        if progress["steps"] >= 3000:
            raise KeyboardInterrupt

    checkpoint = tmp_path / "run" / "checkpoint"
    checkpoint.mkdir(parents=True)
    ctx = RunContext(progress=interrupt, checkpoint_dir=checkpoint, checkpoint_every_seconds=3600)
    with pytest.raises(KeyboardInterrupt):
        run_rods(cfg, ctx)
    assert load_checkpoint(checkpoint / "state.npz")[1]["steps"] == 3000
    partial = read_summary(tmp_path / "run" / "partial")
    assert partial["status"] == "running" and partial["n_steps"] == 3000
    resumed = run_rods(cfg, RunContext(checkpoint_dir=checkpoint))
    assert json.dumps(resumed.summary) == json.dumps(reference.summary)
    for name in reference.events:
        assert np.array_equal(resumed.events[name], reference.events[name], equal_nan=True)
    assert resumed.timeseries.identical(reference.timeseries)
