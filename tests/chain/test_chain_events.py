"""Event analysis on a synthetic record with prescribed motions and contacts."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from dominowave.chain.events import (
    ChainRecord,
    analyse_events,
    contact_intervals,
    critical_tilt,
    forward_tilt,
    neighbour_intervals,
    rotate_vectors,
)
from dominowave.theory import Regime

L = 0.05  # domino height [m]; COM at L/2 above the base point


def _record():
    """Three dominoes: 0 rotates about its fixed base; 1 is hit at 0.3 s and rotates
    forward while its base slides; 2 is hit at 0.5 s, translates 2 cm without tilting
    and stops at 0.7 s."""
    times = np.linspace(0.0, 1.0, 1001)
    n = 3
    theta = np.zeros((times.size, n))
    base_x = np.zeros((times.size, n))
    theta[:, 0] = times
    theta[:, 1] = np.where(times > 0.3, 2.0 * (times - 0.3), 0.0)
    base_x[:, 1] = np.where(times > 0.3, 0.5 * (times - 0.3), 0.0)
    base_x[:, 2] = 0.1 * np.clip(times - 0.5, 0.0, 0.2)  # slides 2 cm, then rests
    rate = np.gradient(theta, times, axis=0)
    base_v = np.gradient(base_x, times, axis=0)
    h = L / 2
    com = np.zeros((times.size, n, 3))
    com[..., 0] = base_x + 0.1 * np.arange(n) + h * np.sin(theta)
    com[..., 2] = h * np.cos(theta)
    vel = np.zeros_like(com)
    vel[..., 0] = base_v + h * np.cos(theta) * rate
    vel[..., 2] = -h * np.sin(theta) * rate
    omega = np.zeros_like(com)
    omega[..., 1] = rate
    quat = np.zeros((times.size, n, 4))
    quat[..., 0] = np.cos(theta / 2)
    quat[..., 2] = np.sin(theta / 2)
    ev = [  # (time, i, j, kind)
        (0.3, 0, 1, 1), (0.32, 0, 1, 0), (0.6, 0, 1, 1),
        (0.5, 1, 2, 1), (0.52, 1, 2, 0), (0.8, 0, 2, 1), (0.9, 0, 2, 0),
        (0.0, 0, -1, 1),
    ]  # fmt: skip
    t, i, j, k = (np.array(c) for c in zip(*ev, strict=True))
    return ChainRecord(
        times=times,
        com=com,
        quat=quat,
        velocity=vel,
        angular_velocity=omega,
        axis=np.tile([0.0, 0.0, 1.0], (n, 1)),
        base_offset=np.tile([0.0, 0.0, -h], (n, 1)),
        top_offset=np.tile([0.0, 0.0, h], (n, 1)),
        ev_time=t.astype(float),
        ev_i=i,
        ev_j=j,
        ev_kind=k,
        end_time=1.0,
    )


def test_tilt_and_contact_intervals():
    rec = _record()
    np.testing.assert_allclose(forward_tilt(rec)[:, 0], rec.times, atol=1e-12)
    on, off = contact_intervals(rec, 1, 0)
    np.testing.assert_allclose(on, [0.3, 0.6])
    np.testing.assert_allclose(off, [0.32, 1.0])  # the open contact ends with the record


@pytest.mark.parametrize("seed", range(5))
def test_neighbour_intervals_are_the_contact_intervals_of_each_pair(seed):
    """The intervals of every domino with the next from one sort of the log
    (neighbour_intervals) are those of a scan per pair (contact_intervals), array for
    array, in a shuffled log of 600 events among 9 bodies and a wall: pairs in both
    orders, pairs two apart, equal times (whose order in the log decides), contacts
    still open at the end."""
    rng = np.random.default_rng(seed)
    n, size = 9, 600
    i = rng.integers(-1, n, size)
    j = np.clip(i + rng.choice([1, 1, 1, 2, -1], size), -1, n - 1)
    t = rng.integers(0, 50, size) / 50.0  # (many equal times)
    rec = dataclasses.replace(
        _record(), ev_time=t, ev_i=i, ev_j=j, ev_kind=rng.integers(0, 2, size).astype(np.int8)
    )
    fast = neighbour_intervals(rec, n)
    assert len(fast) == n - 1 and sum(on.size for on, _ in fast) > 50
    for k, (on, off) in enumerate(fast):
        expected_on, expected_off = contact_intervals(rec, k, k + 1)
        np.testing.assert_array_equal(on, expected_on)
        np.testing.assert_array_equal(off, expected_off)


def test_validate_events_of_prescribed_motion():
    rec = _record()
    ev = analyse_events(rec, critical_angle=critical_tilt(0.0025, L / 2))
    np.testing.assert_allclose(ev.arrival, [0.0, 0.3, 0.5])
    np.testing.assert_array_equal(ev.n_hits_on_next, [2, 1, 0])
    np.testing.assert_array_equal(ev.n_hits_from_prev, [0, 2, 1])
    np.testing.assert_array_equal(ev.touched_two_ahead, [True, False, False])
    np.testing.assert_array_equal(ev.n_hits_in_passage, [1, 0, 0])  # 2nd hit after 0.5 s
    np.testing.assert_allclose(ev.first_hit_end[:2], [0.32, 0.52])
    assert ev.topple_time[0] == pytest.approx(math.atan(0.1), abs=1e-3)
    assert np.isnan(ev.topple_time[2])
    np.testing.assert_allclose(ev.slip_final, [0.0, 0.35, 0.02], atol=1e-12)
    np.testing.assert_allclose(ev.max_forward, [1.0, 1.4, 0.0], atol=1e-12)
    assert ev.max_backward.max() == 0.0 and not np.signbit(ev.max_backward).any()  # (no -0)
    assert ev.rebound_angle[0] == pytest.approx(0.321, abs=1e-9)  # first frame after 0.32 s
    assert ev.mechanism[1] == Regime.FORWARD_ROTATION_SLIP
    assert ev.mechanism[2] == Regime.TRANSLATION
    assert np.isnan(ev.rest_time[:2]).all() and ev.rest_time[2] == pytest.approx(0.7, abs=2e-3)
    assert set(ev.table()) >= {"arrival", "mechanism"}


def test_events_from_the_stored_frames_are_those_of_every_frame():
    """A chain run keeps each domino's frames only where it moves (chain.frames): the
    record with those tracks, and no dense arrays, gives the events of every frame, to
    the bit. Dominoes 1 and 2 stand still before they are hit, domino 2 after 0.7 s."""
    from dataclasses import replace

    from dominowave.chain.frames import SparseFrames

    rec = _record()
    arrays = ("com", "quat", "velocity", "angular_velocity")
    dense = {"times": rec.times}
    dense.update(zip(("positions", "quaternions", "velocities", "angular_velocities"),
                     (getattr(rec, k) for k in arrays), strict=True))  # fmt: skip
    tracks = tuple(SparseFrames.from_dense(dense).tracks())
    assert len(tracks[2].frames) < 0.5 * rec.times.size  # (still outside its motion)
    sparse = replace(rec, tracks=tracks, **dict.fromkeys(arrays))
    angle = critical_tilt(0.0025, L / 2)
    every = analyse_events(rec, critical_angle=angle)
    stored = analyse_events(sparse, critical_angle=angle)
    for name, value in every.table().items():
        np.testing.assert_array_equal(stored.table()[name], value, err_msg=name)
        np.testing.assert_array_equal(np.signbit(stored.table()[name]), np.signbit(value))


def test_validate_pure_rotation_and_backward_mechanisms():
    from dominowave.chain.events import _mechanism

    assert _mechanism(0.0, 1.0, 0.05) == Regime.PURE_ROTATION
    assert _mechanism(0.5, 0.1, 0.05) == Regime.BACKWARD_ROTATION_SLIP


def test_merge_contacts_joins_chatter_into_collisions():
    from dominowave.chain.events import merge_contacts

    on = np.array([0.0, 1.0, 1.05, 3.0])
    off = np.array([0.5, 1.02, 2.0, 3.5])
    m_on, m_off = merge_contacts(on, off, min_gap=0.1)
    np.testing.assert_allclose(m_on, [0.0, 1.0, 3.0])
    np.testing.assert_allclose(m_off, [0.5, 2.0, 3.5])
    np.testing.assert_allclose(merge_contacts(on, off, 0.0)[0], on)


def test_validate_rotate_vectors_against_scipy_rotations():
    """``rotate_vectors`` carries world vectors given at frame 0 with each body's rotation,
    ``R(q_f) R(q_0)^T v``: checked against scipy's rotations of random unit quaternions
    (an independent composition of rotations) for 50 frames of 7 bodies."""
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(3)
    quat = rng.normal(size=(50, 7, 4))
    quat /= np.linalg.norm(quat, axis=-1, keepdims=True)
    vectors = rng.normal(size=(7, 3))
    expected = np.empty((50, 7, 3))
    xyzw = np.roll(quat, -1, axis=-1)  # (scipy's order: scalar last)
    for n in range(7):
        start = Rotation.from_quat(xyzw[0, n])
        for f in range(50):
            turn = Rotation.from_quat(xyzw[f, n]) * start.inv()
            expected[f, n] = turn.apply(vectors[n])
    np.testing.assert_allclose(rotate_vectors(quat, vectors), expected, rtol=0, atol=1e-14)
