"""Box chains whose resting dominoes sleep (``DominoChain(sleep=True)``, the default of box
chains) against the same chains with every domino awake.

The criterion is not exact: a domino put to sleep below ``1e-2 sqrt(g l)`` drops the last
of its motion. docs/shape/sleep_vs_awake.csv measures what that changes on seven chains:
the front speed by at most 4e-4 and the arrival times by at most 4e-4 over 100 and 300
dominoes; the tolerance here is two and a half times that.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from dominowave.chain import DominoChain, Push, analyse_events
from dominowave.chain.frames import FIELDS
from dominowave.chain.presets import standard_domino


def _run(sleep: bool):
    """The 60-domino standard chain run to its end, and the most dominoes asleep while
    the wave ran (before it reached the last domino)."""
    p = standard_domino(
        gap=0.00938, floor="felt", n_dominoes=60, friction_dominoes=0.3, friction_floor=0.3
    )
    stepper = DominoChain(p, sleep=sleep).stepper(Push(omega=math.sqrt(p.g / p.height)))
    most_asleep = 0
    while not stepper.advance(5000):  # (in pieces: the same bits as in one)
        if stepper.phase == 1:
            bodies = stepper.sim.bodies
            asleep = np.sum((bodies.held == 1) & np.isfinite(bodies.calm_since))
            most_asleep = max(most_asleep, int(asleep))
    return stepper, most_asleep


@pytest.fixture(scope="module")
def asleep():
    return _run(True)


def test_validate_sleeping_dominoes_leave_the_wave_as_it_was(asleep):
    """The 60-domino standard chain: dominoes fall asleep behind the front while the wave
    runs, and every arrival time stays within 1e-3 (relative) of the chain with every
    domino awake."""
    awake = np.asarray(_run(False)[0].result().arrival)
    stepper, most_asleep = asleep
    arrival = np.asarray(stepper.result().arrival)
    assert most_asleep >= 10
    assert np.all(np.isfinite(awake[1:]))
    np.testing.assert_allclose(arrival[1:], awake[1:], rtol=1e-3, atol=0)


def test_the_events_of_a_sleeping_chain_come_from_its_moving_frames_alone(asleep):
    """The run keeps each domino's frames only where it moves (chain.frames): less than a
    third of the frames of every domino, here, and the events analysed from them are those
    of every frame, to the bit."""
    stepper, _ = asleep
    chain, record = stepper.chain, stepper.record()
    stored = sum(track.frames.size for track in stepper.frames.tracks())
    assert stored < record.com.shape[0] * record.com.shape[1] / 3
    every = analyse_events(
        record, critical_angle=chain.critical_angle, min_gap=chain.collision_time()
    )
    for name, value in stepper.result().events.table().items():
        np.testing.assert_array_equal(value, every.table()[name], err_msg=name)
        np.testing.assert_array_equal(np.signbit(value), np.signbit(every.table()[name]))


def test_validate_the_aftermath_ends_at_rest_where_a_longer_one_repeats_its_last_frame(asleep):
    """The tail after the last touch ends once every domino is held (asleep), before
    ``tail_time``, at a recorded frame: run on from there to the end of the tail, no
    body moves, no contact starts or ends, and every frame repeats the last one; the
    record ends where that run ends."""
    stepper, _ = asleep
    assert stepper.done and stepper.stop_reason == "touched"
    assert stepper.time < stepper.tail_end - 0.1 * stepper.chain.tail_time
    assert np.all(stepper.sim.bodies.held == 1)
    last = stepper.frames.dense()
    assert stepper.time - last["times"][-1] == pytest.approx(stepper.sim.dt)  # (its step)

    rerun = DominoChain(stepper.chain.params).stepper(stepper.push)
    rerun.set_state(stepper.get_state())
    before = rerun.sim.get_state()
    res = rerun.sim.run(until=stepper.tail_end, trajectory_every=stepper.every)
    assert res.n_steps * rerun.sim.dt > 0.1 * stepper.chain.tail_time  # (hundreds of steps)
    after = rerun.sim.get_state()
    for key in ("pos", "quat", "vel", "omega", "angmom", "held"):
        np.testing.assert_array_equal(after[f"bodies.{key}"], before[f"bodies.{key}"], key)
    assert res.events.time.size == 0
    assert stepper.record(dense=False).end_time == rerun.sim.time  # (where the tail ends)
    for key in FIELDS:
        frames = getattr(res, key)
        np.testing.assert_array_equal(frames, np.broadcast_to(last[key][-1], frames.shape))


def test_clump_chains_do_not_sleep():
    """Sleeping is for boxes: a clump chain builds without it (the engine refuses it in
    scenes with spheres)."""
    from dominowave.chain import ChainParams

    sim, _ = DominoChain(ChainParams(n_dominoes=4)).build(Push(omega=10.0))
    assert sim.settings.sleep_speed == 0.0


def test_sleep_criterion_is_set_in_units_of_the_domino():
    """``sleep_speed`` and ``sleep_time`` are in units of ``sqrt(g l)`` and ``sqrt(l/g)``,
    reach the engine in SI, and are refused unless positive, naming the parameter."""

    from dominowave.chain import ChainParams

    p = ChainParams(shape="box", n_dominoes=4)
    sim, _ = DominoChain(p, sleep_speed=0.02, sleep_time=0.25).build(Push(omega=1.0))
    assert sim.settings.sleep_speed == pytest.approx(0.02 * math.sqrt(p.g * p.height))
    assert sim.settings.sleep_time == pytest.approx(0.25 * math.sqrt(p.height / p.g))
    for bad in ({"sleep_speed": 0.0}, {"sleep_time": -1.0}, {"sleep_speed": math.nan}):
        with pytest.raises(ValueError, match=next(iter(bad))):
            DominoChain(p, **bad)
