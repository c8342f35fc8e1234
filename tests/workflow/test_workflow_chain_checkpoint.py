"""A real DEM chain run, killed with SIGKILL mid-run and resumed, ends with the bits of an
uninterrupted run (dominowave.chain.stepper.ChainStepper through `run --checkpoint` /
`resume`)."""

from __future__ import annotations

from checkpoint_helpers import assert_interrupted_chain_run_resumes, assert_killed_chain_run_resumes

from dominowave.io.models import ChainScenario
from dominowave.sweep.registry import is_steppable
from dominowave.sweep.run_chain import run_chain

# 30 dominoes with damping and friction, collisions resolved by 200 steps: ~180 000 steps
# (~3 s), long enough to be killed after a few checkpoints, in phase 1 (the wave running)
STUDY = """\
[scenario]
kind = "chain"
n_dominoes = 30
d_over_l = 0.5
damping = 0.02
friction_dominoes = 0.1
steps_per_collision = 200
"""
EVERY = 20_000
"""Checkpoint interval [steps]."""


def test_sigkilled_chain_run_resumes_bit_identically(tmp_path):
    assert_killed_chain_run_resumes(STUDY, tmp_path, EVERY)


def test_interrupted_chain_run_saves_state_and_partial_results_then_resumes(tmp_path):
    """Ctrl-C (here: raised between chunks) writes the final checkpoint and the partial
    results; running the same config again resumes and ends with the same bits."""
    assert is_steppable("chain")
    cfg = ChainScenario(n_dominoes=6, d_over_l=0.5, damping=0.02)
    assert_interrupted_chain_run_resumes(run_chain, cfg, tmp_path / "run")
