"""One record of a contact point and one bookkeeping for every table (dem/contact_rows.py).

A scene with a row in every table -- sphere-wall and sphere-sphere rows in the spheres'
Verlet list, box-wall rows and a box-sphere row in the boxes' table -- is dropped and
comes to rest.  Its records, energies and ledger come from the same functions for every
table, and are checked against statics and conservation: the recorded forces on each
body balance its weight, the elastic energy is that of springs carrying the recorded
forces, the energy ledger closes, and the peak force of a pair is at least the force it
carries at rest.
"""

from __future__ import annotations

import numpy as np
import pytest
from dem_scenes import spheres_in_a_box
from older_states import older_state

from dominowave.dem import Material, Scene, Simulation
from dominowave.dem.contact_rows import event_lag

G = 9.81
KN = 2e4  # [N/m], kt = kn (kt_ratio 1)
RHO = 1000.0
R_BALL = 0.004
HALF = np.array([0.01, 0.008, 0.004])
R_BOX = 0.001
LIFT = 5e-4  # [m] every free body dropped from this height above its resting place


def _stack(safety=0.2):
    """A box on the floor with a ball on it (box-wall, box-sphere), a ball on the floor
    (sphere-wall), and a ball resting in the groove of two fixed balls (sphere-sphere)."""
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=RHO, kn=KN, friction=0.4, restitution=0.3))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    top = HALF[2] + R_BOX
    scene.add_sphere((0.0, 0.0, 2.0 * top + R_BALL + LIFT), R_BALL, m)  # on the box
    scene.add_sphere((0.04, 0.0, R_BALL + LIFT), R_BALL, m)  # on the floor
    gap = 1.6 * R_BALL  # (half the distance of the fixed balls' centres)
    for side in (-1.0, 1.0):
        scene.add_sphere((-0.04 + side * gap, 0.0, R_BALL), R_BALL, m, blocked="x y z rx ry rz")
    height = np.sqrt((2.0 * R_BALL) ** 2 - gap**2)
    scene.add_sphere((-0.04, 0.0, R_BALL + height + LIFT), R_BALL, m)  # in the groove
    scene.add_box((0.0, 0.0, top + LIFT), HALF, R_BOX, m)
    return scene.build(safety=safety, track_energy=True, record_peak_force=True)


@pytest.fixture(scope="module")
def settled():
    """The stack after 0.3 s, its last frame of contact forces, and its energies at the
    start."""
    sim = _stack()
    start = sim.energy()
    res = sim.run(until=0.3, trajectory_every=500, record_contact_forces=True)
    return sim, res.contact_frames, start


def _last_frame(frames):
    rows = frames.frame(frames.start.size - 2)
    return frames.first[rows], frames.second[rows], frames.force[rows]


def test_every_table_has_touching_rows(settled):
    sim, frames, _ = settled
    first, second, _ = _last_frame(frames)
    ns = sim.spheres.radius.size
    box = ns  # (shapes: spheres first, then the box)
    pairs = set(zip(first.tolist(), second.tolist(), strict=True))
    assert (-1, 1) in pairs  # sphere-wall, the spheres' table
    assert {(2, 4), (3, 4)} <= pairs  # sphere-sphere, the spheres' table
    assert (box, 0) in pairs  # box-sphere, the boxes' table
    assert np.sum((first == -1) & (second == box)) == 4  # box-wall: a box lying flat, 4 corners


def test_validate_recorded_forces_balance_every_weight(settled):
    """At rest every free body carries its weight through its recorded rows (the force
    acts on ``second``, its opposite on ``first``): to 1e-6 of the weight."""
    sim, frames, _ = settled
    first, second, force = _last_frame(frames)
    ns = sim.spheres.radius.size
    body_of = np.append(sim.spheres.body, sim.boxes.body)  # (shape -> body)
    net = np.zeros((sim.bodies.mass.size, 3))
    for a, b, f in zip(first, second, force, strict=True):
        net[body_of[b]] += f
        if a >= 0:
            net[body_of[a]] -= f
    for shape in (0, 1, 4, ns):  # (the free bodies; 2 and 3 are fixed)
        b = body_of[shape]
        weight = sim.bodies.mass[b] * G
        np.testing.assert_allclose(net[b], [0.0, 0.0, weight], atol=1e-6 * weight)


def test_validate_wall_box_and_sphere_points_are_rows_of_one_table_under_one_law():
    """A box lying on the floor, a box lying on it and a ball on that: the points of the
    box-wall, box-box and box-sphere pairs are rows of the one table of the boxes
    (``Boxes.rows``, one narrow phase: boxes.box_forces), each under the one point law
    (laws.point.point_law): at rest its normal force less the dashpot's is ``k_n delta``
    with the row's own ``k_n``, and the rows of each kind carry the weight above them --
    the floor's all three bodies', the box-box rows the top box's and the ball's, the
    box-sphere row the ball's -- to 1e-6 of it."""
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=RHO, kn=KN, friction=0.4, restitution=0.3))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    top = HALF[2] + R_BOX
    lower = scene.add_box((0.0, 0.0, top + LIFT), HALF, R_BOX, m)
    upper = scene.add_box((0.001, 0.0, 3.0 * top + 2.0 * LIFT), HALF, R_BOX, m)
    ball = scene.add_sphere((0.0, 0.0, 4.0 * top + R_BALL + 3.0 * LIFT), R_BALL, m)
    sim = scene.build(safety=0.2)
    sim.run(until=0.5)
    rows = sim.boxes.rows
    n = rows.n[0]
    i, j = rows.i[:n], rows.j[:n]
    weight = sim.bodies.mass * G
    kinds = {
        "box-wall": (j < 0, weight[[lower, upper, ball]].sum()),
        "box-box": ((j >= 0) & (j < 2), weight[[upper, ball]].sum()),
        "box-sphere": (j >= 2, weight[ball]),
    }
    for name, (rows_of_kind, carried) in kinds.items():
        assert rows_of_kind.any(), name
        elastic = rows.fn[:n] - rows.fn_viscous[:n]
        np.testing.assert_allclose(
            elastic[rows_of_kind], (rows.kn[:n] * rows.overlap[:n])[rows_of_kind], rtol=1e-12
        )
        # (the normal points from box i into its partner: the force on the body above,
        # the box on a wall, the partner above a box)
        above = np.where(j < 0, -1.0, 1.0)
        lift = (above * rows.mult[:n] * rows.fn[:n] * rows.normal[:n, 2])[rows_of_kind].sum()
        assert lift == pytest.approx(carried, rel=1e-6), name
    # (a sphere partner is j = n_boxes + sphere, here the ball: sphere 0, on box 1)
    assert i[j >= 2].tolist() == [1] and sim.boxes.partner_body[j[j >= 2]].tolist() == [ball]


def test_validate_elastic_energy_is_that_of_the_recorded_forces(settled):
    """At rest each row's force is its springs' (no dashpot): with ``k_t = k_n`` the
    elastic energy of a row is ``|F|^2 / (2 k_n)`` whatever the split into normal and
    shear; summed over the rows of all tables it is the energy of the ledger, to 1e-6."""
    sim, frames, _ = settled
    _, _, force = _last_frame(frames)
    springs = float(np.sum(force**2) / (2.0 * KN))
    stored = sim.energy()["elastic_normal"] + sim.energy()["elastic_tangential"]
    assert stored == pytest.approx(springs, rel=1e-6)


def test_validate_the_ledger_closes_over_every_table(settled):
    """The drop dissipates energy through the dashpots and friction of every table
    (contact_rows.rows_power, integrated with the trapezoidal rule): the total of the
    ledger drifts only by the integration error, which vanishes with the step -- under
    1 % of what is dissipated at the scene's step (measured 0.42 %), and more than 8 times
    less at a quarter of it (measured 11x; second order would give 16x).  Leaving out the
    power of any one table breaks the balance by several per cent."""
    sim, _, start = settled
    end = sim.energy()
    dissipated = sum(end[k] for k in ("dissipated_viscous", "dissipated_friction"))
    assert dissipated > 0.5 * sim.bodies.mass[sim.bodies.held == 0].sum() * G * LIFT
    drift = abs(end["total"] - start["total"]) / dissipated
    assert drift < 1e-2
    fine = _stack(safety=0.05)
    start = fine.energy()
    fine.run(until=0.3)
    end = fine.energy()
    dissipated = sum(end[k] for k in ("dissipated_viscous", "dissipated_friction"))
    assert abs(end["total"] - start["total"]) / dissipated < drift / 8.0


def test_validate_peak_forces_are_the_largest_recorded_normal_forces():
    """Recorded at every step, the largest normal force of the box-sphere pair and of a
    sphere-sphere pair of the groove is the pair's peak normal force (to 1e-9): the normal
    of a point of a sphere runs through the sphere's centre, so ``F . n`` of a recorded row
    is its normal force (its shear lies in the tangent plane)."""
    sim = _stack()
    res = sim.run(until=0.05, trajectory_every=1, record_contact_forces=True)
    frames, pos = res.contact_frames, res.positions
    body = sim.spheres.body
    box = sim.spheres.radius.size  # (the box's shape id)
    for first, second, centre, sphere in ((box, 0, None, 0), (2, 4, 2, 4)):
        largest = 0.0
        for f in range(frames.start.size - 1):
            rows = frames.frame(f)
            mine = (frames.first[rows] == first) & (frames.second[rows] == second)
            points, forces = frames.point[rows][mine], frames.force[rows][mine]
            for point, force in zip(points, forces, strict=True):
                # (the normal from the first shape to the sphere: through its centre)
                n = pos[f, body[sphere]] - (point if centre is None else pos[f, body[centre]])
                largest = max(largest, float(force @ n) / np.linalg.norm(n))
        a, b = sorted((body[sphere], sim.boxes.body[0] if centre is None else body[centre]))
        peak = sim.pairs.peak_normal_force[a, b]
        assert largest > sim.bodies.mass[body[sphere]] * G  # (the drop's impact)
        assert peak == pytest.approx(largest, rel=1e-9)


def test_an_event_lag_is_the_time_since_a_linear_overlap_began():
    """An overlap growing at ``speed`` over the last drift that is ``depth`` at its end
    began ``depth / speed`` before (an onset; an end the same with the gap): the lag of
    every driver's events, at most the step, none for the initial configuration or
    without approach."""
    dt, speed = 1e-5, 0.3
    for before in (0.0, 0.25 * dt, 0.5 * dt, 0.999 * dt):
        for depth in (speed * before, -speed * before):  # (an onset, an end)
            assert event_lag(depth, speed, dt, False) == pytest.approx(before, rel=1e-12)
    assert event_lag(2.0 * speed * dt, speed, dt, False) == dt  # (before the drift: clipped)
    assert event_lag(1e-7, 0.0, dt, False) == 0.0
    assert event_lag(1e-7, -speed, dt, False) == 0.0  # (moving apart at an onset)
    assert event_lag(1e-7, speed, dt, True) == 0.0


def test_a_listed_pair_touches_exactly_while_its_contact_is_open():
    """The spheres' table marks its touching rows by a positive overlap, the predicate of
    the bookkeeping: after every run the touching rows of each body pair and each body and
    wall are exactly the contacts the event bookkeeping counts open (its onsets less its
    ends) -- also across the Verlet rebuilds of 27 spheres tumbling into a box, which move
    pairs to other rows and give new pairs the rows of old ones."""
    sim = spheres_in_a_box()
    body = sim.sphere_body
    most = np.zeros(2, int)  # (most touching rows with walls, between bodies)
    for _ in range(30):
        sim.run(n_steps=200)
        c, n = sim.contacts, int(sim.contacts.n[0])
        pairs, walls = np.zeros_like(sim.rec.pair_count), np.zeros_like(sim.rec.wall_count)
        for i, j in zip(c.i[:n][c.overlap[:n] > 0.0], c.j[:n][c.overlap[:n] > 0.0], strict=True):
            if j >= 0:
                a, b = sorted((body[i], body[j]))
                pairs[a, b] += 1
            else:
                walls[body[i], -j - 1] += 1
        np.testing.assert_array_equal(pairs, sim.rec.pair_count)
        np.testing.assert_array_equal(walls, sim.rec.wall_count)
        most = np.maximum(most, (walls.sum(), pairs.sum()))
    assert np.all(most > 5)


def test_a_format_4_state_loses_its_stale_overlaps():
    """A state written before the sphere contacts' rows had points and normals may hold a
    stale positive overlap in an idle row (nothing read it then); read, the row is idle
    with no overlap, and the elastic energies are those of the active rows."""
    sim = _stack()
    sim.run(n_steps=2000)
    state = older_state(sim.get_state(), 4)
    n = int(state["contacts.n"][0])
    idle = np.flatnonzero(state["contacts.overlap"][:n] <= 0.0)
    assert idle.size
    state["contacts.overlap"] = state["contacts.overlap"].copy()
    state["contacts.overlap"][idle] = 1e-4  # (an overlap no active contact has here)
    restored = Simulation.from_state(state)
    assert np.all(restored.contacts.overlap[idle] <= 0.0)
    restored._refresh_energy()  # (from the contact rows, as a resumed run does)
    sim._refresh_energy()
    assert restored.energy() == sim.energy()
