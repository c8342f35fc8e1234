"""Box chains (``shape = "box"``) checkpoint and resume as clump chains do: a run killed
with SIGKILL (CLI) or interrupted with Ctrl-C (in process) mid-run keeps what it computed
and, resumed, ends with the bits of an uninterrupted run."""

from __future__ import annotations

import pytest
from checkpoint_helpers import assert_interrupted_chain_run_resumes, assert_killed_chain_run_resumes

from dominowave.io.models import ChainScenario
from dominowave.sweep.run_chain import run_chain

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


def test_sigkilled_box_chain_run_resumes_bit_identically(tmp_path):
    assert_killed_chain_run_resumes(STUDY, tmp_path, EVERY)


@pytest.mark.parametrize("model", ["2d", "3d"])
def test_interrupted_box_chain_run_saves_partial_results_then_resumes(tmp_path, model):
    """Ctrl-C between chunks writes the final checkpoint and the partial results; running
    the same config again resumes and ends with the same bits."""
    cfg = ChainScenario(
        shape="box", model=model, n_dominoes=5, d_over_l=0.5, damping=0.02,
        friction_dominoes=0.3, friction_floor=0.6,
    )  # fmt: skip
    assert_interrupted_chain_run_resumes(run_chain, cfg, tmp_path / "run")
