"""Held boxes (Scene.add_box(..., held=True)): fixed until a moving body touches them,
as held clumps (engine.py); while held, without rows with other held boxes, and with
wall rows only once a moving box is near (boxes.py)."""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from dominowave.dem import ONSET, Material, Scene, Simulation, StopCondition

G = 9.81
RHO = 1000.0
HALF = np.array([0.0025, 0.0125, 0.025])  # a domino of 5 x 25 x 50 mm [m]
ROUND = HALF[0] / 10


def _row(planar, held=True, mu=0.5):
    """Three boxes standing on a frictional floor 30 mm apart, the last two held (and
    tilted forward by 0.05 rad, so that they would topple if free); box 0 is pushed
    about its front bottom edge and hits box 1.  Their bottom edges just touch the floor
    (no initial overlap)."""
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=RHO, kn=2e4, friction=mu))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    blocked = "y rx rz" if planar else ""
    omega = 8.0  # [rad/s] about +y: the top moves towards +x
    pivot = np.array([HALF[0] - ROUND, 0.0, 0.0])
    centre = np.array([0.0, 0.0, HALF[2]])
    w = np.array([0.0, omega, 0.0])
    scene.add_box(centre, HALF, ROUND, m, blocked=blocked, velocity=np.cross(w, centre - pivot),
                  angular_velocity=w)  # fmt: skip
    tilt = 0.05
    R = Rotation.from_rotvec([0.0, tilt, 0.0]).as_matrix()
    for x in (0.03, 0.06):
        # standing on its front bottom edge, tilted forward by `tilt`
        edge = np.array([x + HALF[0], 0.0, 0.0])
        centre = edge + R @ np.array([-HALF[0], 0.0, HALF[2]])
        scene.add_box(centre, HALF, ROUND, m, orientation=R, blocked=blocked, held=held)
    return scene.build(safety=0.05)


@pytest.mark.parametrize("planar", [True, False])
def test_held_box_stays_put_and_is_released_when_touched(planar):
    """A held box does not move (bit for bit) and has no contact rows with another held
    box (nor with the floor, which these touch without overlap); the moving box's first
    touch releases it at that step, the box behind stays held."""
    sim = _row(planar)
    start = sim.positions()
    quat = sim.bodies.quat.copy()
    sim.run(n_steps=10)
    rows = sim.boxes.rows
    n = rows.n[0]
    assert n > 0 and set(rows.i[:n]) == {0} and set(rows.j[:n]) == {-1}  # box 0 on floor
    res = sim.run(until=1.0, stop=StopCondition(touched_body=1), trajectory_every=1)
    assert res.stop_reason == "touched"
    t_touch = sim.pairs.first_contact[0, 1]
    assert t_touch <= sim.release_time[1] < t_touch + sim.dt
    assert sim.bodies.held[1] == 0 and sim.bodies.held[2] == 1
    before = res.times <= sim.release_time[1]  # (frames at t_n, before that step's drift)
    assert before.sum() > 100
    for frames, first in ((res.positions, start), (res.quaternions, quat)):
        np.testing.assert_array_equal(
            frames[before][:, 1:], np.broadcast_to(first[1:], frames[before][:, 1:].shape)
        )
    ev = sim.run(n_steps=2000).events
    assert np.linalg.norm(sim.positions()[1] - start[1]) > 1e-5  # it moves now
    np.testing.assert_array_equal(sim.positions()[2], start[2])
    np.testing.assert_array_equal(sim.bodies.quat[2], quat[2])
    ev = sim.run(until=sim.time + 0.3).events
    on_floor = (ev.body_i == 1) & (ev.body_j == -1) & (ev.kind == ONSET)
    assert on_floor.any()  # it touches the floor
    assert math.isfinite(sim.release_time[2])  # and topples onto box 2, which it releases


def test_validate_held_boxes_keep_the_energy_ledger_closed():
    """Push, impact, release and the toppling of the released boxes, with friction: the
    total energy (kinetic + gravitational + elastic + dissipated) stays constant to
    < 1e-3 of the energy that moves (the pushed box's kinetic energy plus its fall): a
    held box does no work (it does not move), and its contacts start from zero overlap
    at its release.  (The same scene with free boxes errs by 2.8e-4 of that scale, the
    held one by 4.2e-4, both at the impacts: the time discretisation at safety 0.05.)"""
    sim = _row(planar=True)
    e0 = sim.energy()
    res = sim.run(until=0.4, energy_every=50)
    assert math.isfinite(sim.release_time[1]) and math.isfinite(sim.release_time[2])
    total = res.energy["total"]
    assert total.size > 100
    scale = e0["kinetic_translational"] + e0["kinetic_rotational"]
    scale += sim.bodies.mass[0] * G * HALF[2]
    assert np.max(np.abs(total - e0["total"])) < 1e-3 * scale


@pytest.mark.parametrize("planar", [True, False])
def test_kept_visited_pairs_follow_releases_and_the_callers_held_flags(planar):
    """The engine keeps the box pairs it visits from step to step (boxes._visit_pairs,
    rebuilt after releases and at the start of every run): the run through both releases
    in one piece equals the same run in pieces of 101 steps to the bit, and a held box
    that the caller frees between two runs gets its floor rows (it does not sink)."""
    whole, pieces = _row(planar), _row(planar)
    whole.run(until=0.4)
    assert math.isfinite(whole.release_time[2])
    steps = int(whole.rec.step[0])
    while pieces.rec.step[0] < steps:
        pieces.run(n_steps=min(101, steps - int(pieces.rec.step[0])))
    for name in ("pos", "quat", "vel", "omega"):
        np.testing.assert_array_equal(getattr(pieces.bodies, name), getattr(whole.bodies, name))
    n = whole.boxes.rows.n[0]
    assert pieces.boxes.rows.n[0] == n
    np.testing.assert_array_equal(pieces.boxes.rows.shear[:n], whole.boxes.rows.shear[:n])

    sim = _row(planar)
    sim.run(n_steps=10)
    sim.bodies.held[2] = 0  # (as engine._release does)
    sim.bodies.fresh[2] = 1
    landed = False  # (within 10 ms: its rounded edge stands 12 um above the floor)
    for _ in range(30):
        sim.run(n_steps=100)
        rows = sim.boxes.rows
        n = rows.n[0]
        landed |= bool(np.any((rows.i[:n] == 2) & (rows.j[:n] == -1)))
    assert landed


def _mixed_scene(planar):
    """A pushed box toppling a row of four held boxes into a held clump and two held boxes
    touching each other, the last touching a second wall; on the other side a free ball
    rolling into two more held boxes (releases by box-box, box-sphere and sphere contacts)."""
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=RHO, kn=2e4, friction=0.4, restitution=0.5))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    scene.add_wall((0.2, 0.0, 0.0), (-1.0, 0.0, 0.0), m)
    blocked = "y rx rz" if planar else ""
    w = np.array([0.0, 8.0, 0.0])
    centre = np.array([0.0, 0.0, HALF[2]])
    scene.add_box(centre, HALF, ROUND, m, blocked=blocked,
                  velocity=np.cross(w, centre - np.array([HALF[0] - ROUND, 0.0, 0.0])),
                  angular_velocity=w)  # fmt: skip
    R = Rotation.from_rotvec([0.0, 0.05, 0.0]).as_matrix()
    for x in (0.03, 0.06, 0.09, 0.12):
        centre = np.array([x + HALF[0], 0.0, 0.0]) + R @ np.array([-HALF[0], 0.0, HALF[2]])
        scene.add_box(centre, HALF, ROUND, m, orientation=R, blocked=blocked, held=True)
    last = 0.2 - HALF[0]
    for x in (last - 2 * HALF[0] - 1e-4, last):
        scene.add_box([x, 0.0, HALF[2]], HALF, ROUND, m, blocked=blocked, held=True)
    scene.add_clump([[0.155, 0.0, 0.004], [0.155, 0.0, 0.012]], 0.004, m, blocked=blocked,
                    held=True)  # fmt: skip
    for x in (-0.1, -0.13):
        scene.add_box([x, 0.0, HALF[2]], HALF, ROUND, m, blocked=blocked, held=True)
    scene.add_sphere([-0.06, 0.0, 0.04], 0.005, m, blocked=blocked, velocity=(-0.6, 0.0, 0.0))
    return scene.build(safety=0.05)


@pytest.mark.parametrize("planar", [True, False])
def test_every_held_body_of_a_mixed_scene_is_released_alike_in_pieces_and_resumed(planar):
    """The box neighbour list leaves out the pairs of held boxes and is built again when a
    box is released (boxes.build_box_candidates): in a scene of boxes, a clump and a ball,
    every held body is released -- by a box, a sphere, a clump, and two touching held
    boxes one after the other -- and the run in one piece, in uneven pieces and resumed
    from a saved state end in the same state to the bit."""
    end = 0.6
    whole = _mixed_scene(planar)
    whole.run(until=end, trajectory_every=50)  # (the trajectory buffers grow: re-entries)
    assert np.isfinite(whole.release_time[1:-1]).all()  # (the ball, last, is not held)
    pieces = _mixed_scene(planar)
    rng = np.random.default_rng(1)
    while pieces.time < end - 0.5 * pieces.dt:
        pieces.run(n_steps=int(rng.integers(1, 400)), until=end)
    first = _mixed_scene(planar)
    first.run(until=end / 3)
    resumed = Simulation.from_state(first.get_state())
    resumed.run(until=end)
    for sim in (pieces, resumed):
        for name in ("pos", "quat", "vel", "omega", "held"):
            np.testing.assert_array_equal(getattr(sim.bodies, name), getattr(whole.bodies, name))
        np.testing.assert_array_equal(sim.release_time, whole.release_time)


def test_a_run_stops_at_rest_once_every_box_is_held_and_at_a_frame():
    """``StopCondition(at_rest=True)``: with a box moving, the run goes on; with every box
    held it stops at the next recorded frame (at once without frames), and nothing has
    moved.  Alone, without ``n_steps`` or ``until``, it is refused: a scene need never
    come to rest."""
    res = _row(planar=True).run(n_steps=200, stop=StopCondition(at_rest=True))
    assert res.stop_reason == "n_steps"  # box 0 moves
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=RHO, kn=2e4, friction=0.5))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    for x in (0.0, 0.03):
        scene.add_box((x, 0.0, HALF[2]), HALF, ROUND, m, held=True)
    sim = scene.build(safety=0.05)
    start = sim.positions()
    res = sim.run(n_steps=200, stop=StopCondition(at_rest=True))
    assert (res.stop_reason, res.n_steps) == ("at_rest", 1)
    res = sim.run(n_steps=200, stop=StopCondition(at_rest=True), trajectory_every=7)
    assert (res.stop_reason, res.n_steps, res.times.size) == ("at_rest", 7, 1)  # (step 7)
    np.testing.assert_array_equal(sim.positions(), start)
    assert not sim.bodies.vel.any() and not sim.bodies.omega.any()
    with pytest.raises(ValueError, match="needs n_steps or until"):
        sim.run(stop=StopCondition(at_rest=True))
