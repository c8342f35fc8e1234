"""Box chains (``shape = "box"``) checkpoint and resume as clump chains do: a run killed
with SIGKILL (CLI) or interrupted with Ctrl-C (in process) mid-run keeps what it computed
and, resumed, ends with the bits of an uninterrupted run."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from checkpoint_helpers import assert_netcdf_identical, interrupt_then_resume, kill_after_checkpoint

from dominowave.io.models import ChainScenario
from dominowave.sweep.run_chain import run_chain

CLI = [sys.executable, "-m", "dominowave"]

# 12 box dominoes in 3D with damping and friction: ~40 000 steps, the wave running when
# killed after two checkpoints
STUDY = """\
[scenario]
kind = "chain"
shape = "box"
model = "3d"
n_dominoes = 12
d_over_l = 0.5
damping = 0.02
friction_dominoes = 0.3
friction_floor = 0.6
"""
EVERY = 5_000
"""Checkpoint interval [steps]."""


def _summary(folder: Path) -> dict:
    summary = json.loads((folder / "summary.json").read_text())
    summary.pop("engine_wall_time")  # CPU time spent, the one number that may differ
    return summary


def test_sigkilled_box_chain_run_resumes_bit_identically(tmp_path):
    study = tmp_path / "box_study.toml"
    study.write_text(STUDY)
    ref = tmp_path / "ref"
    subprocess.run([*CLI, "run", str(study), "--out", str(ref), "--quiet"], check=True)
    out = tmp_path / "killed"
    proc = subprocess.Popen(
        [*CLI, "run", str(study), "--out", str(out), "--checkpoint", f"steps={EVERY}", "--quiet"]
    )
    steps_at_kill = kill_after_checkpoint(proc, out / "checkpoint" / "state.npz", 2 * EVERY)
    assert not (out / "summary.json").exists(), "the run must be killed before it ends"
    summary = _summary(ref)
    assert steps_at_kill % EVERY == 0 and 2 * EVERY <= steps_at_kill < summary["n_steps"]
    subprocess.run([*CLI, "resume", str(out), "--quiet"], check=True)

    assert json.dumps(_summary(out)) == json.dumps(summary)  # every number, to the last digit
    assert summary["stop_reason"] == "touched"
    assert (out / "events.csv").read_bytes() == (ref / "events.csv").read_bytes()
    for name in ("timeseries.nc", "trajectory.nc"):
        assert assert_netcdf_identical(ref / name, out / name).sizes["time"] > 100
    assert not (out / "checkpoint").exists()


@pytest.mark.parametrize("model", ["2d", "3d"])
def test_interrupted_box_chain_run_saves_partial_results_then_resumes(tmp_path, model):
    """Ctrl-C between chunks writes the final checkpoint and the partial results; running
    the same config again resumes and ends with the same bits."""
    cfg = ChainScenario(
        shape="box", model=model, n_dominoes=5, d_over_l=0.5, damping=0.02,
        friction_dominoes=0.3, friction_floor=0.6,
    )  # fmt: skip
    reference = run_chain(cfg)
    partial, resumed = interrupt_then_resume(run_chain, cfg, tmp_path / "run", at_step=3000)
    assert partial["n_steps"] == 3000 and partial["stop_reason"] == "running"
    assert partial["dominoes_toppled"] < cfg.n_dominoes
    for summary in (resumed.summary, reference.summary):
        summary.pop("engine_wall_time")
    assert json.dumps(resumed.summary) == json.dumps(reference.summary)
    for name in reference.events:
        assert np.array_equal(resumed.events[name], reference.events[name], equal_nan=True)
    assert resumed.timeseries.identical(reference.timeseries)
