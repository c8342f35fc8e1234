"""The neighbour list of the box contacts (boxes.build_box_candidates): the forces do not
depend on when it is built, so a run with a small skin (many builds) gives the trajectory
of a run with a skin so large that every pair is a candidate, bit for bit."""

import numpy as np
import pytest

from dominowave.dem import Material, Scene

G = 9.81
HALF = np.array([0.0025, 0.0125, 0.025])  # a domino of 5 x 25 x 50 mm [m]
ROUND = HALF[0] / 10


def _chain(planar, skin, n=6, spacing=0.03):
    """n standing boxes (free, not held), box 0 pushed about its front bottom edge."""
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=1000.0, kn=2e4, friction=0.4, restitution=0.5))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    blocked = "y rx rz" if planar else ""
    w = np.array([0.0, 8.0, 0.0])
    for k in range(n):
        centre = np.array([k * spacing, 0.0, HALF[2]])
        if k == 0:
            v = np.cross(w, centre - np.array([HALF[0] - ROUND, 0.0, 0.0]))
            scene.add_box(centre, HALF, ROUND, m, blocked=blocked, velocity=v, angular_velocity=w)
        else:
            scene.add_box(centre, HALF, ROUND, m, blocked=blocked)
    return scene.build(safety=0.05, skin=skin)


@pytest.mark.parametrize("planar", [True, False])
def test_box_neighbour_list_does_not_change_the_trajectory(planar):
    small = _chain(planar, skin=2e-4)
    large = _chain(planar, skin=10.0)  # every pair a candidate at every build
    a = small.run(until=0.4, trajectory_every=200)
    b = large.run(until=0.4, trajectory_every=200)
    assert small.bodies.pos[-1, 0] > 5 * 0.03 + 0.02  # the last box fell
    assert small.rec.n_rebuilds[0] > 100 and large.rec.n_rebuilds[0] < 5
    n = large.boxes.n_cand[0]
    assert n == 6 * 5 // 2 + 6  # (all box-box and box-wall pairs)
    assert small.boxes.n_cand[0] < n  # (and fewer with the small skin)
    np.testing.assert_array_equal(a.positions, b.positions)
    np.testing.assert_array_equal(a.quaternions, b.quaternions)
    np.testing.assert_array_equal(a.angular_velocities, b.angular_velocities)
    for name in ("i", "j", "key", "fn", "shear"):
        np.testing.assert_array_equal(
            getattr(small.boxes.rows, name)[: small.boxes.rows.n[0]],
            getattr(large.boxes.rows, name)[: large.boxes.rows.n[0]],
        )
    np.testing.assert_array_equal(a.events.time, b.events.time)


def test_box_neighbour_list_grows_when_full():
    """A list longer than its array: the run hands back, the array grows, the same run."""
    full = _chain(True, skin=10.0)
    short = _chain(True, skin=10.0)
    short.boxes = short.boxes._replace(cand=np.zeros(1, np.int64))
    a = full.run(until=0.05)
    b = short.run(until=0.05)
    assert short.boxes.cand.shape[0] >= short.boxes.n_cand[0] == full.boxes.n_cand[0]
    np.testing.assert_array_equal(short.bodies.pos, full.bodies.pos)
    assert a.n_steps == b.n_steps
