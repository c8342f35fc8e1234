"""Checkpoints of box chains: a run of ``ChainParams(shape="box")`` advanced in pieces,
or restored from its saved state mid-run, ends with the bits of the uninterrupted run,
in 2D and 3D, as for the clump chain (test_chain_stepper.py)."""

from __future__ import annotations

import numpy as np
import pytest
from test_chain_stepper import assert_same_bits

from dominowave import dem
from dominowave.chain.build import ChainParams
from dominowave.chain.scenario import DominoChain
from dominowave.io.checkpoint import load_checkpoint, save_checkpoint


def _params(model: str) -> ChainParams:
    """Five boxes with damping and friction: the wave reaches the end (both phases)."""
    return ChainParams(
        shape="box", model=model, n_dominoes=5, d_over_l=0.5, damping=0.02,
        friction_dominoes=0.3, friction_floor=0.6,
    )  # fmt: skip


@pytest.fixture(scope="module", params=["2d", "3d"])
def one_shot(request):
    params = _params(request.param)
    return params, DominoChain(params).run(keep_record=True)


def test_box_run_reaches_the_end_through_both_phases(one_shot):
    _, run = one_shot
    assert run.stop_reason == "touched" and run.reached_all
    assert run.record.end_time > run.arrival[-1]


def test_stepped_box_run_equals_one_shot_run(one_shot):
    params, run = one_shot
    stepper = DominoChain(params).stepper()
    while not stepper.advance(1777):
        pass
    assert_same_bits(stepper.result(keep_record=True), run)


@pytest.mark.parametrize("phase", [1, 2])  # the wave running, or the tail
def test_box_run_restored_from_a_checkpoint_file_ends_bit_identically(one_shot, phase, tmp_path):
    """Saved through io.checkpoint (the file a CLI run writes), restored into a fresh
    stepper: the box contact rows (keys, shear histories) come back, the run retraces."""
    params, run = one_shot
    first = DominoChain(params).stepper()
    first.advance(4000 if phase == 1 else 8000)
    while not _loaded(first.sim.boxes.rows, box_box=phase == 2):
        first.advance(123)
    assert first.phase == phase and not first.done
    at = first.steps
    path = tmp_path / "state.npz"
    save_checkpoint(path, first.get_state(), {"key": "box"}, history=first.history_keys)
    first.advance(10)  # the saved state is a copy
    state, _ = load_checkpoint(path, key="box")
    resumed = DominoChain(params).stepper()
    resumed.set_state(state)
    assert resumed.steps == at
    while not resumed.advance(2345):
        pass
    assert_same_bits(resumed.result(keep_record=True), run)


def _loaded(rows, box_box: bool) -> bool:
    """True if the contact rows hold shear histories to keep (and a box-box row)."""
    n = rows.n[0]
    return np.any(rows.shear[:n] != 0.0) and (not box_box or np.any(rows.j[:n] >= 0))


def test_box_simulation_state_round_trip(tmp_path):
    """Simulation.save / load of a scene of boxes (no chain): the resumed run has the bits
    of the uninterrupted one, contact rows included."""
    params = _params("3d")
    chain = DominoChain(params)
    sim, _ = chain.build(chain.resolve(None))
    sim.run(n_steps=2500)
    sim.save(tmp_path / "sim.npz")
    sim.run(n_steps=1500)
    reference = sim.get_state()
    restored = dem.Simulation.load(tmp_path / "sim.npz")
    restored.run(n_steps=1500)
    again = restored.get_state()
    assert again.keys() == reference.keys() and "boxes.rows.shear" in again
    for key, value in reference.items():
        np.testing.assert_array_equal(again[key], value, err_msg=key)


def test_box_state_refused_by_another_scene():
    """A state without the box arrays, or of another chain, is refused with the name of
    what does not fit (no silent resume without the contact histories)."""
    a = DominoChain(_params("2d")).stepper()
    a.advance(10)
    state = a.get_state()
    fresh = DominoChain(_params("2d")).stepper()
    with pytest.raises(ValueError, match=r"state is missing 'boxes\.body'"):
        fresh.set_state({k: v for k, v in state.items() if not k.startswith("sim.boxes.")})
    with pytest.raises(ValueError, match=r"bodies.pos.*\(5, 3\).*\(3, 3\)"):
        DominoChain(ChainParams(shape="box", n_dominoes=3)).stepper().set_state(state)


def test_box_chain_contact_records_survive_a_restore():
    """With ``contact_forces=True`` a box chain records its contact points per frame
    (floor rows: first = -(wall + 1); box pairs: the shape ids of the boxes), and a run
    restored mid-way ends with the same records, bit for bit."""
    params = _params("2d")
    whole = DominoChain(params).stepper(contact_forces=True)
    while not whole.advance(10**9):
        pass
    first = DominoChain(params).stepper(contact_forces=True)
    first.advance(5000)
    resumed = DominoChain(params).stepper(contact_forces=True)
    resumed.set_state(first.get_state())
    while not resumed.advance(3333):
        pass
    a, b = whole.contact_frames(), resumed.contact_frames()
    for name in ("start", "first", "second", "point", "force"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert np.any(a.first < 0) and np.any(a.first >= 0)  # floor rows and box-box rows
    assert a.second.max() < params.n_dominoes  # no spheres: box x is shape x
