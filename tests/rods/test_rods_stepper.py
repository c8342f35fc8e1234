"""The resumable run (RodStepper): pieces, saved and restored states, give simulate()'s bits."""

import dataclasses

import numpy as np
import pytest

from dominowave.rods import RodChain, RodRun, RodStepper, block, point_mass, simulate

G = 9.81
K_STAR = G  # m = l = 1

CASES = {
    # the paper's model: head-on first contacts, then geometric ones; dominoes fall flat
    "head-on point mass": (
        RodChain(n=8, l=1.0, d=0.4, mass=point_mass(1, 1), k=1e4 * K_STAR / 2, normal="head-on"),
        {"push": 3.0, "frame_every": 97, "tail_time": 1.0},
    ),
    # every other branch: thick blocks, Hertz law, dashpot, friction, bouncing floor
    "block hertz dashpot friction": (
        RodChain(
            n=8,
            l=1.0,
            d=0.3,
            s=0.1,
            mass=block(1, 1, 0.1),
            k=1e5 * K_STAR,
            law="hertz",
            damping_ratio=0.1,
            mu=0.3,
            floor_restitution=0.4,
        ),
        {"push": 3.0, "frame_every": 61, "tail_time": 1.0},
    ),
}


def _assert_same_run(a: RodRun, b: RodRun) -> None:
    """Every field equal to the last bit (NaNs and signed zeros included)."""
    for field in dataclasses.fields(RodRun):
        x, y = getattr(a, field.name), getattr(b, field.name)
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and x.shape == y.shape, field.name
            assert x.tobytes() == y.tobytes(), field.name
        else:
            assert x == y, field.name


def _stepper(case: str) -> RodStepper:
    chain, options = CASES[case]
    return RodStepper(chain, **options)


@pytest.fixture(scope="module")
def reference() -> dict[str, RodRun]:
    """simulate() of each case, in one piece."""
    return {case: simulate(chain, **options) for case, (chain, options) in CASES.items()}


@pytest.mark.parametrize("case", CASES)
def test_run_in_uneven_pieces_equals_simulate(case, reference):
    """advance(a); advance(b); ... == simulate(): chunk boundaries change no bit."""
    full = reference[case]
    assert full.n_steps > 5000 and full.status == "wave passed"
    assert full.events.shape[0] > 2 * CASES[case][0].n  # re-contacts, not only the wave
    stepper = _stepper(case)
    pieces = [1, 2, 3, 5, 8, 13, 997, 0, 4096]
    k = 0
    while not stepper.advance(pieces[k % len(pieces)]):
        k += 1
    assert k > 5
    _assert_same_run(stepper.result(), full)
    assert stepper.advance(1000) and stepper.steps == full.n_steps  # ended: no more steps


@pytest.mark.parametrize("case", CASES)
def test_restored_state_continues_bit_identically(case, reference, tmp_path):
    """Save the state (through an .npz file) at several points, restore it into a fresh
    stepper, continue: the same bits as the uninterrupted run, whatever the cut."""
    full = reference[case]
    running = _stepper(case)
    for cut in (0, 1, full.n_steps // 3, full.n_steps - 1):
        running.advance(cut - running.steps)
        np.savez(tmp_path / "state.npz", **running.get_state())
        with np.load(tmp_path / "state.npz") as saved:
            state = {name: saved[name] for name in saved.files}
        resumed = _stepper(case)
        resumed.set_state(state)
        assert resumed.steps == cut
        resumed.advance(full.n_steps)
        _assert_same_run(resumed.result(), full)
    running.advance(full.n_steps)  # the saved copies did not disturb the original
    _assert_same_run(running.result(), full)


def test_unfinished_run_reports_the_run_so_far(reference):
    case = "head-on point mass"
    full = reference[case]
    stepper = _stepper(case)
    assert stepper.end_time == 5.0 * 8 * np.sqrt(1.0 / G)  # t_max until the wave passed
    half_wave = int(full.arrival[4] / full.dt)  # the wave has reached domino 3, not 4
    stepper.advance(half_wave)
    part = stepper.result()
    assert part.status == "running"
    assert part.n_steps == stepper.steps == half_wave
    assert part.t_end == stepper.time == stepper.steps * full.dt
    np.testing.assert_array_equal(part.samples, full.samples[: part.samples.shape[0]])
    reached = ~np.isnan(part.arrival)
    assert stepper.toppled == np.count_nonzero(reached)
    assert stepper.toppled == 4
    np.testing.assert_array_equal(part.arrival[reached], full.arrival[reached])
    stepper.advance(full.n_steps)
    assert full.t_end - full.dt < stepper.end_time <= full.t_end  # the wave passed: known


def test_state_of_another_chain_is_refused():
    state = _stepper("head-on point mass").get_state()
    chain, options = CASES["head-on point mass"]
    longer = RodStepper(dataclasses.replace(chain, n=9), **options)
    with pytest.raises(ValueError, match=r"theta has dtype float64 and shape \(8,\)"):
        longer.set_state(state)
    state["events"] = np.zeros((1, 13))  # rows the counter n_events does not account for
    with pytest.raises(ValueError, match=r"events has dtype float64 and shape \(1, 13\)"):
        _stepper("head-on point mass").set_state(state)
    del state["torque"]
    with pytest.raises(ValueError, match=r"missing arrays \['torque'\]"):
        _stepper("head-on point mass").set_state(state)
