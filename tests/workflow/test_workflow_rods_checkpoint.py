"""A real rods run, killed with SIGKILL mid-run and resumed, ends with the bits of an
uninterrupted run (dominowave.rods.RodStepper through `run --checkpoint` / `resume`)."""

from __future__ import annotations

import json

import numpy as np
from checkpoint_helpers import assert_netcdf_identical, interrupt_then_resume, kill_and_resume

from dominowave.io.models import RodsScenario
from dominowave.sweep.run_rods import run_rods

# thick blocks with dashpot and friction (every branch of the contact code), resolved
# finely enough that the run takes ~850 000 steps (~2 s): long enough to be killed
STUDY = """\
[scenario]
kind = "rods"
n_dominoes = 30
height = 0.048
thickness = 0.0075
d_over_l = 0.5
mass = 0.008
mass_model = "block"
damping_ratio = 0.05
friction_dominoes = 0.2
steps_per_contact = 1000.0
"""
EVERY = 50_000
"""Checkpoint interval [steps]."""


def test_sigkilled_rods_run_resumes_bit_identically(tmp_path):
    ref, out, steps_at_kill = kill_and_resume(STUDY, tmp_path, EVERY, 3)
    summary = (ref / "summary.json").read_text()
    assert (
        steps_at_kill % EVERY == 0 and 3 * EVERY <= steps_at_kill < json.loads(summary)["n_steps"]
    )
    assert (out / "summary.json").read_text() == summary  # every number, to the last digit
    assert (out / "events.csv").read_bytes() == (ref / "events.csv").read_bytes()
    # energies, time and the (E, 13) contact table
    assert_netcdf_identical(ref / "timeseries.nc", out / "timeseries.nc")
    assert not (out / "checkpoint").exists()  # a finished run keeps no checkpoint


def test_interrupted_rods_run_saves_state_and_partial_results_then_resumes(tmp_path):
    """Ctrl-C (here: raised between chunks) writes the final checkpoint and the partial
    results; running the same config again resumes and ends with the same bits."""
    cfg = RodsScenario(n_dominoes=12, mass_model="block", friction_dominoes=0.2)
    reference = run_rods(cfg)
    assert reference.summary["n_steps"] > 5000

    partial, resumed = interrupt_then_resume(run_rods, cfg, tmp_path / "run", at_step=3000)
    assert partial["status"] == "running" and partial["n_steps"] == 3000
    assert json.dumps(resumed.summary) == json.dumps(reference.summary)
    for name in reference.events:
        assert np.array_equal(resumed.events[name], reference.events[name], equal_nan=True)
    assert resumed.timeseries.identical(reference.timeseries)
