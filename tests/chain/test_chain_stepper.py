"""ChainStepper: a chain run advanced in pieces, or restored from its state mid-run, ends
with the bits of ``DominoChain.run()`` (which is itself one uninterrupted advance)."""

from __future__ import annotations

import numpy as np
import pytest

from dominowave import dem
from dominowave.chain.build import ChainParams
from dominowave.chain.scenario import DominoChain
from dominowave.chain.stepper import STATE_FORMAT, steps_until_quiet

SMALL = ChainParams(n_dominoes=6, d_over_l=0.5, damping=0.02, friction_dominoes=0.1)
"""Six dominoes with damping and friction: the wave reaches the end (both phases run)."""
DYING = ChainParams(n_dominoes=4, d_over_l=0.9)
"""Wide spacing: domino 0 hits domino 1, which does not fall; the quiet-time stop ends it."""


def _arrays(run) -> dict[str, np.ndarray]:
    """Every array and number of a ChainRun (record included) except the wall time."""
    rec = run.record
    out = {
        f"record.{k}": np.asarray(v)
        for k, v in vars(rec).items()
        if isinstance(v, np.ndarray | float)
    }
    out.update({f"events.{k}": np.asarray(v) for k, v in run.events.table().items()})
    out["arrival"] = run.arrival
    out["theory_arrival"] = run.theory_arrival
    for name in ("n_steps", "dt", "omega_1", "theory_window_speed", "stop_reason"):
        out[name] = np.asarray(getattr(run, name))
    out["wave"] = np.array([run.wave.speed, run.wave.speed_err, run.wave.first, run.wave.last])
    return out


def assert_same_bits(a, b):
    x, y = _arrays(a), _arrays(b)
    assert x.keys() == y.keys()
    for name in x:
        assert x[name].dtype == y[name].dtype, name
        assert np.array_equal(x[name], y[name], equal_nan=x[name].dtype.kind == "f"), name


@pytest.fixture(scope="module")
def one_shot():
    return DominoChain(SMALL).run(keep_record=True)


def test_one_shot_run_reaches_the_end_through_both_phases(one_shot):
    assert one_shot.stop_reason == "touched" and one_shot.reached_all
    assert one_shot.record.end_time > one_shot.arrival[-1]  # the tail was run


@pytest.mark.parametrize("chunk", [997, 10_000])
def test_stepped_run_equals_one_shot_run(one_shot, chunk):
    """advance(a); advance(b); ... == run(): chunk boundaries fall in both phases."""
    stepper = DominoChain(SMALL).stepper()
    calls = 1
    while not stepper.advance(chunk):
        calls += 1
    assert calls == -(-one_shot.n_steps // chunk)
    assert_same_bits(stepper.result(keep_record=True), one_shot)


def test_single_steps_equal_one_advance():
    one, single = DominoChain(SMALL).stepper(), DominoChain(SMALL).stepper()
    one.advance(300)
    for _ in range(300):
        single.advance(1)
    _assert_states_equal(single.get_state(), one.get_state())


def _assert_states_equal(a: dict, b: dict):
    assert a.keys() == b.keys()
    # reset by every engine call (Simulation._start_run): the per-call record counters,
    # the touched flags, the references of the energy-runaway check; and the wall time
    per_call = {f"sim.rec.{k}" for k in ("traj_n", "ev_n", "energy_n", "touched")}
    per_call |= {"sim.rec.energy_ref", "sim.rec.energy_now", "sim.rec.clock", "wall_time"}
    for name in a.keys() - per_call:
        assert a[name].dtype == b[name].dtype, name
        assert np.array_equal(a[name], b[name], equal_nan=a[name].dtype.kind == "f"), name
    assert a["sim.rec.clock"][0] == b["sim.rec.clock"][0]  # the simulated time


@pytest.mark.parametrize("phase", [1, 2])  # the wave running, or the tail
def test_run_restored_from_its_state_ends_bit_identically(one_shot, phase):
    first = DominoChain(SMALL).stepper()
    first.advance(2000)
    while first.phase < phase:
        first.advance(1000)
    first.advance(321)
    assert first.phase == phase and not first.done
    at = first.steps
    state = first.get_state()
    first.advance(10)  # the saved state is a copy: the run going on does not change it
    resumed = DominoChain(SMALL).stepper()
    resumed.set_state(state)
    assert resumed.steps == at and resumed.time == state["sim.rec.clock"][0]
    while not resumed.advance(1234):
        pass
    assert_same_bits(resumed.result(keep_record=True), one_shot)


def test_a_state_of_the_first_format_resumes_and_a_newer_one_is_refused(one_shot):
    """Format 1 (no ``stepper_format``, no ``record_end``): a run that did not stop at
    rest, whose record ends at its time; it resumes to the bits of the run."""
    first = DominoChain(SMALL).stepper()
    first.advance(2500)
    state = first.get_state()
    assert int(state["stepper_format"]) == STATE_FORMAT
    older = {k: v for k, v in state.items() if k not in ("stepper_format", "record_end")}
    resumed = DominoChain(SMALL).stepper()
    resumed.set_state(older)
    while not resumed.advance(1234):
        pass
    assert_same_bits(resumed.result(keep_record=True), one_shot)
    # (states saved with record_end but before the key: their record_end is kept)
    with_end = {**older, "record_end": np.array(1.5)}
    kept = DominoChain(SMALL).stepper()
    kept.set_state(with_end)
    assert kept.record_end == 1.5
    newer = {**state, "stepper_format": np.array(STATE_FORMAT + 1)}
    refused = f"stepper_format = {STATE_FORMAT + 1}: .* formats 1 to {STATE_FORMAT} "
    with pytest.raises(ValueError, match=refused):
        DominoChain(SMALL).stepper().set_state(newer)


def test_quiet_stop_is_independent_of_chunks():
    """The engine counts its quiet time from the last onset or the start of each call;
    split into calls it would stop late. The stepper stops where one call stops."""
    chain = DominoChain(DYING, quiet_time=0.1)
    one = chain.run(keep_record=True)
    rec = one.record
    onsets = rec.ev_time[(rec.ev_kind == dem.ONSET) & (rec.ev_j >= 0)]
    assert one.stop_reason == "no_onset" and onsets.size == 1  # 0 hits 1, then nothing
    stepper = chain.stepper()
    while not stepper.advance(37):  # pieces before and after the onset
        pass
    assert_same_bits(stepper.result(keep_record=True), one)
    # the engine's own stop, called in the same pieces, would end later
    sim, _ = chain.build(one.push)
    stop = dem.StopCondition(no_onset_for=0.1, touched_body=DYING.n_dominoes - 1)
    naive = 0
    while (res := sim.run(n_steps=37, until=chain.max_time, stop=stop)).stop_reason == "n_steps":
        naive += res.n_steps
    assert naive + res.n_steps > one.n_steps + 1000


def test_validate_steps_until_quiet_against_a_step_by_step_clock():
    dt, since, quiet = 2.9307803481334362e-05, 0.0123, 0.05
    t, n = 0.0137, 0
    while True:  # the engine's clock and test, one step at a time
        n += 1
        if (t + dt) - since >= quiet:
            break
        t = t + dt
    assert steps_until_quiet(0.0137, dt, since, quiet, 10**9) == n
    assert steps_until_quiet(0.0137, dt, since, quiet, n) == n
    assert steps_until_quiet(0.0137, dt, since, quiet, n - 1) is None


def test_unfinished_run_gives_partial_results():
    stepper = DominoChain(SMALL).stepper()
    assert not stepper.advance(3000)
    partial = stepper.result()
    assert partial.n_steps == stepper.steps == 3000 and partial.stop_reason == "running"
    assert stepper.end_time == stepper.chain.max_time and 0 < stepper.time < stepper.end_time
    assert np.isnan(partial.arrival[-1])  # the wave has not got there yet
