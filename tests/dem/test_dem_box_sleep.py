"""Sleeping boxes (``Scene.build(sleep_speed=..., sleep_time=...)``): a box at rest is held
again, its rows with the floor and other resting boxes are put aside as they were, and a
moving body wakes it (engine._sleep_and_wake, boxes.box_forces)."""

import dataclasses
import math

import numpy as np
import pytest

from dominowave.dem import ONSET, Material, Scene, Simulation

G = 9.81
HALF = np.array([0.0025, 0.0125, 0.025])  # a domino of 5 x 25 x 50 mm [m]
ROUND = HALF[0] / 10
V_SLEEP, T_SLEEP = 1e-3, 0.02


def _lying_boxes(striker_speed=0.0, sleep=True):
    """Two boxes lying flat on a frictional floor (their long sides along x), 100 mm apart,
    dropped from 1 mm; box 1 slides towards box 0 at ``striker_speed`` [m/s] along -x."""
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=1000.0, kn=2e4, friction=0.4, restitution=0.5))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    flat = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # z -> -x
    for x, v in ((0.0, 0.0), (0.1, -striker_speed)):
        scene.add_box((x, 0.0, HALF[0] + 1e-3), HALF, ROUND, m, orientation=flat,
                      velocity=(v, 0.0, 0.0))  # fmt: skip
    options = {"sleep_speed": V_SLEEP, "sleep_time": T_SLEEP} if sleep else {}
    return scene.build(safety=0.1, **options)


def _total_energy(sim):
    return float(sim.energy()["total"])


def test_validate_a_box_at_rest_sleeps_and_the_energy_ledger_stays_closed():
    """A dropped box settles and is put to sleep: held again, at rest, its floor rows put
    aside with their springs. Kinetic + gravitational + elastic + dissipated energy (the
    kinetic energy left at sleep booked as damping) ends where it ends without sleeping:
    sleep adds nothing to the integration's own error (2e-7 J of the drop's 1.2e-4 J)."""
    awake = _lying_boxes(sleep=False)
    start = _total_energy(awake)
    awake.run(until=0.3)
    drift = _total_energy(awake) - start
    sim = _lying_boxes()
    sim.run(until=0.3)
    assert sim.bodies.held.tolist() == [1, 1]
    assert np.isfinite(sim.bodies.calm_since).all()
    np.testing.assert_array_equal(sim.bodies.vel, 0.0)
    rows, dormant = sim.boxes.rows, sim.boxes.dormant
    assert rows.n[0] == 0 and dormant.n[0] >= 4 and set(dormant.j[: dormant.n[0]]) == {-1}
    drop = 2 * sim.bodies.mass[0] * G * 1e-3
    assert abs(_total_energy(sim) - start - drift) < 1e-12 * drop
    # asleep: nothing moves, nothing changes, the rows put aside keep their springs
    pos, kept = sim.positions(), dormant.shear[: dormant.n[0]].copy()
    sim.run(n_steps=2000)
    np.testing.assert_array_equal(sim.positions(), pos)
    np.testing.assert_array_equal(sim.boxes.dormant.shear[: sim.boxes.dormant.n[0]], kept)


def test_a_sleeping_box_wakes_when_touched_and_its_floor_contact_goes_on():
    """Box 1 slides into box 0, asleep since it settled: box 0 keeps its floor rows while
    box 1 is near (a held box next to a moving one), their onset wakes box 0, and its
    floor contact goes on through sleep and wake (one onset, at the start). Then both
    come to rest and sleep, their rows put aside."""
    sim = _lying_boxes(striker_speed=0.75)
    sim.run(until=0.08)
    assert sim.bodies.held.tolist() == [1, 0]  # 0 asleep, 1 sliding
    assert math.isfinite(sim.bodies.calm_since[0]) and sim.boxes.dormant.n[0] == 0
    ev = sim.run(until=0.3).events
    touch = (ev.body_i == 0) & (ev.body_j == 1) & (ev.kind == ONSET)
    t_touch = ev.time[touch][0]
    assert t_touch <= sim.release_time[0] < t_touch + sim.dt
    assert not ((ev.body_i == 0) & (ev.body_j == -1) & (ev.kind == ONSET)).any()
    assert sim.positions()[0, 0] < -1e-3  # pushed
    assert sim.bodies.held.tolist() == [1, 1] and sim.boxes.dormant.n[0] > 0


def test_a_sleeping_scene_resumes_bit_identically_from_its_state():
    sim = _lying_boxes(striker_speed=0.75)
    sim.run(until=0.25)
    assert sim.boxes.dormant.n[0] > 0
    restored = Simulation.from_state(sim.get_state())
    for s in (sim, restored):
        s.run(n_steps=20000)
    for name in ("pos", "quat", "vel", "omega", "held", "calm_since"):
        np.testing.assert_array_equal(getattr(restored.bodies, name), getattr(sim.bodies, name))


def test_without_sleep_nothing_sleeps():
    sim = _lying_boxes(sleep=False)
    sim.run(until=0.3)
    assert sim.bodies.held.tolist() == [0, 0] and sim.boxes.dormant.n[0] == 0
    assert np.isnan(sim.bodies.calm_since).all()


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"sleep_speed": -1.0}, "sleep_speed = -1"),
        ({"sleep_speed": 1e-3, "sleep_time": -0.1}, "sleep_time = -0.1"),
    ],
)
def test_bad_sleep_settings_are_refused(options, message):
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=1000.0, kn=2e4))
    scene.add_box((0.0, 0.0, 0.1), HALF, ROUND, m)
    with pytest.raises(ValueError, match=message):
        scene.build(**options)


def test_sleep_is_refused_in_a_scene_with_spheres():
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=1000.0, kn=2e4))
    scene.add_box((0.0, 0.0, 0.1), HALF, ROUND, m)
    scene.add_sphere((0.1, 0.0, 0.1), 0.005, m)
    with pytest.raises(ValueError, match=r"sleep_speed = 0.001 .* boxes only"):
        scene.build(sleep_speed=1e-3)


def test_the_contact_force_recorder_keeps_the_rows_of_sleeping_boxes():
    """A box asleep on the floor still stands on it in the recorded contact forces: its
    rows put aside appear in every frame with the force they had when it fell asleep,
    whose vertical sum is its weight, on the box (``second``) from the floor (``first =
    -1``)."""
    sim = _lying_boxes()
    sim.run(until=0.3)  # both asleep (the first test)
    frames = sim.run(n_steps=400, trajectory_every=100, record_contact_forces=True)
    cf = frames.contact_frames
    weight = sim.bodies.mass[0] * G
    assert len(cf.start) - 1 >= 4
    for f in range(len(cf.start) - 1):
        rows = slice(cf.start[f], cf.start[f + 1])
        assert set(cf.first[rows]) == {-1}
        for box in (0, 1):
            on_box = cf.second[rows] == box
            assert on_box.sum() >= 4
            np.testing.assert_allclose(cf.force[rows][on_box, 2].sum(), weight, rtol=1e-3)


def test_a_run_in_pieces_sleeps_as_the_run_in_one():
    """Two boxes that slide, sleep and wake, run in one piece and in pieces of 7 steps:
    the same states to the bit.  A run checks its last step, and a piece of 7 steps
    ends between the check steps (``check_every`` 100); a sleep decision is taken only
    at those, so where the pieces end changes none."""
    whole, pieces = _lying_boxes(striker_speed=0.75), _lying_boxes(striker_speed=0.75)
    whole.run(until=0.3)
    while pieces.rec.step[0] < whole.rec.step[0]:
        pieces.run(n_steps=min(7, int(whole.rec.step[0] - pieces.rec.step[0])))
    assert whole.bodies.held.tolist() == [1, 1]  # (both asleep)
    for name in ("pos", "quat", "vel", "omega", "held", "calm_since"):
        np.testing.assert_array_equal(getattr(pieces.bodies, name), getattr(whole.bodies, name))


def test_frames_record_the_moving_boxes_and_rebuild_every_state():
    """A run's frames record the boxes that may have moved since the frame before
    (engine._record_frame): box 0 asleep while box 1 slides has no row, and none is
    left once both sleep.  Rebuilt (``RunResult.positions``, ...), they are to the bit
    the states of the same run in pieces of 7 steps, each piece's one frame recorded
    whole."""
    whole, pieces = _lying_boxes(striker_speed=0.75), _lying_boxes(striker_speed=0.75)
    res = whole.run(until=0.3, trajectory_every=7)
    parts = []
    while pieces.rec.step[0] < whole.rec.step[0]:
        left = int(whole.rec.step[0] - pieces.rec.step[0])
        parts.append(pieces.run(n_steps=min(7, left), trajectory_every=7))
    assert all(part.times.size == 1 for part in parts)
    for name in ("times", "positions", "quaternions", "velocities", "angular_velocities"):
        expected = np.concatenate([getattr(part, name) for part in parts])
        np.testing.assert_array_equal(getattr(res, name), expected, err_msg=name)
    rows = np.diff(res.frames.start)
    assert rows[0] == 2 and 1 in rows and rows[-1] == 0
    assert 1 in res.frames.first[rows == 1]  # (box 1 alone, box 0 asleep)
    # in pieces of 10 steps, most of whose frames are not their first step's
    tens = _lying_boxes(striker_speed=0.75)
    parts = []
    while tens.rec.step[0] < whole.rec.step[0]:
        left = int(whole.rec.step[0] - tens.rec.step[0])
        parts.append(tens.run(n_steps=min(10, left), trajectory_every=7))
    for name in ("times", "positions", "quaternions", "velocities", "angular_velocities"):
        expected = np.concatenate([getattr(part, name) for part in parts])
        np.testing.assert_array_equal(getattr(res, name), expected, err_msg=name)


def test_frames_without_every_body_at_the_first_are_refused():
    """A run's frames rebuild every body from its first frame: rows that start without
    some body are refused with the bodies they have."""
    res = _lying_boxes().run(n_steps=20, trajectory_every=10)
    with pytest.raises(ValueError, match="the first frame has the rows of 2 bodies from body 1"):
        dataclasses.replace(res.frames, first=res.frames.first + 1)
