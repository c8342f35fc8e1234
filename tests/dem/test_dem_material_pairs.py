"""Friction and restitution per material pair (Scene.set_pair,
material_pairs.pair_friction_restitution):
each contact -- floor or another body, sphere or box -- has the value set for its own pair,
measured against closed forms (sliding deceleration, the velocity ratio of an impact)."""

import math

import numpy as np
import pytest
from older_states import older_state
from scipy.spatial.transform import Rotation

from dominowave.dem import Material, Scene, Simulation
from dominowave.dem.contact import pair_properties

G = 9.81
RHO = 1000.0


def _corners(half, r):
    """The 8 core corners (8, 3) of a box of outer half-extents ``half`` and rounding r."""
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    return signs * (np.asarray(half) - r)


def _point_velocity(sim, b, point):
    """Full-step velocity (3,) of the material point ``point`` of body b [m/s]."""
    bodies = sim.bodies
    return bodies.vel_full[b] + np.cross(bodies.omega_full[b], point - bodies.pos[b])


def _touching(contacts):
    """The number of touching sphere contacts (rows of positive overlap)."""
    return int(np.sum(contacts.overlap[: contacts.n[0]] > 0.0))


def _run_impact(sim, relative_normal_velocity, max_points):
    """Step until one impact is over; returns the normal relative velocity before and
    after it (as ``relative_normal_velocity()``)."""
    before = relative_normal_velocity()
    touched = False
    while not touched or sim.boxes.rows.n[0] + _touching(sim.contacts):
        sim.run(n_steps=1)
        assert sim.boxes.rows.n[0] <= max_points
        touched = touched or sim.boxes.rows.n[0] + _touching(sim.contacts)
    return before, relative_normal_velocity()


# ----------------------------------------------------------------------- restitution


def _pair_scene(e_body_floor, e_body_body):
    """Bodies of material 0 (e = 0.9), a floor of material 1 (e = 0.95): min rule 0.9;
    the pairs set apart.  No gravity: only the impacts act; frictionless (friction at an
    eccentric impact couples the tangential and normal motion of the contact point)."""
    scene = Scene(gravity=(0.0, 0.0, 0.0))
    body = scene.add_material(Material(density=RHO, kn=1e6, restitution=0.9))
    floor = scene.add_material(Material(density=RHO, kn=1e6, restitution=0.95))
    scene.set_pair(body, floor, restitution=e_body_floor)
    scene.set_pair(body, body, restitution=e_body_body)
    return scene, body, floor


@pytest.mark.parametrize("e_floor, e_body", [(0.4, 0.8), (0.8, 0.4)])
def test_validate_box_floor_and_box_box_impacts_have_their_pair_restitution(e_floor, e_body):
    """A tilted cuboid falls corner-first on the floor, and another hits the middle of a
    resting cuboid's face corner-first: the normal velocity of the contact point after
    each impact is -e times the one before, e the value set for that pair (within 1 %)."""
    half = np.array([0.01, 0.006, 0.02])
    r = 0.0005
    core = _corners(half, r)
    R = Rotation.from_rotvec([0.35, -0.5, 0.0]).as_matrix()
    world = core @ R.T

    scene, body, floor = _pair_scene(e_floor, e_body)
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), floor)
    low = np.argmin(world[:, 2])
    centre = np.array([0.0, 0.0, r + 1e-4]) - world[low]
    scene.add_box(centre, half, r, body, orientation=R, velocity=(0.0, 0.0, -0.5))
    sim = scene.build(safety=0.02)
    corner = lambda: _point_velocity(sim, 0, sim.bodies.pos[0] + sim.bodies.rot[0] @ core[low])  # noqa: E731
    before, after = _run_impact(sim, lambda: corner()[2], 1)
    assert np.abs(sim.bodies.omega_full[0]).max() > 1.0  # eccentric: the impact spun it
    assert -after / before == pytest.approx(e_floor, rel=1e-2)

    # box 1 at rest, its +x face at x = hb; box 0 hits the face's middle with a corner
    scene, body, floor = _pair_scene(e_floor, e_body)
    hb = 0.015
    lead = np.argmin(world[:, 0])
    centre = np.array([hb + r + 1e-4, 0.0, 0.0]) - world[lead]
    scene.add_box(centre, half, r, body, orientation=R, velocity=(-0.5, 0.0, 0.0))
    scene.add_box((0.0, 0.0, 0.0), (hb, hb, hb), r, body)
    sim = scene.build(safety=0.02)

    def relative():
        b = sim.bodies
        p = b.pos[0] + b.rot[0] @ core[lead]
        return (_point_velocity(sim, 0, p) - _point_velocity(sim, 1, p))[0]

    before, after = _run_impact(sim, relative, 1)
    assert np.abs(sim.bodies.omega_full[0]).max() > 1.0
    assert -after / before == pytest.approx(e_body, rel=1e-2)


@pytest.mark.parametrize("e_floor, e_body", [(0.4, 0.8), (0.8, 0.4)])
def test_validate_sphere_floor_and_sphere_sphere_impacts_have_their_pair_restitution(
    e_floor, e_body
):
    """A sphere hits the floor and two spheres collide head-on: each velocity ratio is
    the restitution set for its pair (within 1 %), not the min rule's 0.9."""
    scene, body, floor = _pair_scene(e_floor, e_body)
    R = 0.005
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), floor)
    scene.add_sphere((0.0, 0.0, R + 1e-4), R, body, velocity=(0.0, 0.0, -0.5))
    sim = scene.build(safety=0.02)
    before, after = _run_impact(sim, lambda: sim.bodies.vel_full[0, 2], 0)
    assert -after / before == pytest.approx(e_floor, rel=1e-2)

    scene, body, floor = _pair_scene(e_floor, e_body)
    scene.add_sphere((0.0, 0.0, 0.0), R, body, velocity=(0.5, 0.0, 0.0))
    scene.add_sphere((2.5 * R + 1e-4, 0.0, 0.0), 1.5 * R, body)
    sim = scene.build(safety=0.02)
    before, after = _run_impact(sim, lambda: np.diff(sim.bodies.vel_full[:, 0])[0], 0)
    assert -after / before == pytest.approx(e_body, rel=1e-2)


# ----------------------------------------------------------------------- friction


@pytest.mark.parametrize("partner, mu", [("floor", 0.2), ("box", 0.35)])
def test_validate_box_slides_with_the_friction_of_its_pair(partner, mu):
    """A flat cuboid on a plane inclined by 30 degrees (gravity turned), on the floor or
    on a fixed larger cuboid: both materials have mu = 0.9 (min rule: it sticks), the
    pair mu set below tan 30: it slides with a = g (sin t - mu cos t)."""
    t = math.radians(30.0)
    scene = Scene(gravity=(G * math.sin(t), 0.0, -G * math.cos(t)))
    kn = 1e5
    body = scene.add_material(Material(density=RHO, kn=kn, friction=0.9, restitution=0.2))
    floor = scene.add_material(Material(density=RHO, kn=kn, friction=0.9, restitution=0.2))
    scene.set_pair(body, floor, friction=0.2)
    scene.set_pair(body, body, friction=0.35)
    half = np.array([0.02, 0.02, 0.005])
    r = 0.001
    if partner == "floor":
        scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), floor)
    else:  # top face at z = 0, long enough for the slide
        scene.add_box((0.0, 0.0, -0.01), (0.2, 0.05, 0.01), r, body, blocked="x y z rx ry rz")
    mass = 8 * half.prod() * RHO
    sink = mass * G * math.cos(t) / (4 * kn)
    scene.add_box((0.0, 0.0, half[2] - sink), half, r, body)
    sim = scene.build(safety=0.05)
    top = sim.bodies.mass.shape[0] - 1
    sim.run(until=0.05)  # the normal contacts settle (dashpot)
    t1, v1 = sim.time, sim.bodies.vel_full[top, 0]
    sim.run(until=0.25)
    t2, v2 = sim.time, sim.bodies.vel_full[top, 0]
    assert np.all(sim.boxes.rows.mu[: sim.boxes.rows.n[0]] == mu)
    assert (v2 - v1) / (t2 - t1) == pytest.approx(G * (math.sin(t) - mu * math.cos(t)), rel=1e-4)


def test_validate_sphere_slides_on_the_floor_with_the_friction_of_its_pair():
    """A sphere launched without spin on the floor slides, decelerating at mu g with the
    pair's mu (0.1, not the min rule's 0.5), until it rolls at 5/7 of its speed at
    ``t = 2 v0 / (7 mu g)``."""
    mu = 0.1
    kn = 1e5
    scene = Scene(gravity=(0.0, 0.0, -G))
    body = scene.add_material(Material(density=RHO, kn=kn, friction=0.5, restitution=0.5))
    floor = scene.add_material(Material(density=RHO, kn=kn, friction=0.7, restitution=0.5))
    scene.set_pair(floor, body, friction=mu)  # (either order)
    R = 0.005
    mass = RHO * 4 / 3 * math.pi * R**3
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), floor)
    v0 = 1.0
    scene.add_sphere((0.0, 0.0, R - mass * G / kn), R, body, velocity=(v0, 0.0, 0.0))
    sim = scene.build(safety=0.05, overlap_tolerance=1e-4)
    sim.run(until=0.02)
    t1, v1 = sim.time, sim.bodies.vel_full[0, 0]
    sim.run(until=0.2)
    t2, v2 = sim.time, sim.bodies.vel_full[0, 0]
    assert (v2 - v1) / (t2 - t1) == pytest.approx(-mu * G, rel=1e-3)
    sim.run(until=2 * v0 / (7 * mu * G) + 0.05)
    assert sim.bodies.vel_full[0, 0] == pytest.approx(5 / 7 * v0, rel=1e-3)


def test_validate_sphere_slides_over_a_sphere_with_the_friction_of_its_pair():
    """A small sphere launched without spin from the top of a fixed sphere of 1 m slides
    down it under the pair's mu (0.1; the min rule would give 0.6): its polar angle
    follows ``(R + r) theta'' = g sin theta - mu (g cos theta - (R + r) theta'^2)``
    (solve_ivp) while it slides, to 1e-4."""
    from scipy.integrate import solve_ivp

    mu, kn, big, r, v0 = 0.1, 1e5, 1.0, 0.005, 0.5
    scene = Scene(gravity=(0.0, 0.0, -G))
    ball = scene.add_material(Material(density=RHO, kn=kn, friction=0.6, restitution=0.5))
    hill = scene.add_material(Material(density=RHO, kn=kn, friction=0.8, restitution=0.5))
    scene.set_pair(ball, hill, friction=mu)
    scene.add_sphere((0.0, 0.0, 0.0), big, hill, blocked="x y z rx ry rz")
    mass = RHO * 4 / 3 * math.pi * r**3
    top = big + r - mass * G / kn  # resting on its static overlap
    scene.add_sphere((0.0, 0.0, top), r, ball, velocity=(v0, 0.0, 0.0))
    sim = scene.build(safety=0.05, overlap_tolerance=1e-4)
    t_end = 0.1  # (it rolls from about 2 v0 / (7 mu g) = 0.146 s on)
    sim.run(until=t_end)
    x, z = sim.bodies.pos[1, 0], sim.bodies.pos[1, 2]
    theta = math.atan2(x, z)
    rate = (sim.bodies.vel_full[1, 0] * z - sim.bodies.vel_full[1, 2] * x) / (x * x + z * z)
    arm = big + r

    def rhs(_, y):
        return [y[1], (G * math.sin(y[0]) - mu * (G * math.cos(y[0]) - arm * y[1] ** 2)) / arm]

    ref = solve_ivp(rhs, (0.0, sim.time), [0.0, v0 / arm], rtol=1e-12, atol=1e-14)
    assert sim.bodies.omega_full[1, 1] * r < rate * arm  # still sliding
    assert theta == pytest.approx(ref.y[0, -1], rel=1e-4)
    assert rate == pytest.approx(ref.y[1, -1], rel=1e-4)


def test_sphere_pair_properties_take_the_pair_values_and_the_min_rule_elsewhere():
    """pair_properties: the set pair's mu, the min rule for the pairs not set, and the
    dashpot of the set restitution (laws.linear.viscous_coefficient with the reduced mass)."""
    scene = Scene()
    a = scene.add_material(Material(density=RHO, kn=1e5, friction=0.5, restitution=0.9))
    b = scene.add_material(Material(density=RHO, kn=1e5, friction=0.3, restitution=0.8))
    scene.set_pair(a, a, friction=0.05, restitution=0.5)
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), b)
    scene.add_sphere((0.0, 0.0, 0.01), 0.005, a)
    scene.add_sphere((0.0, 0.0, 0.0201), 0.005, a)
    sim = scene.build()
    out = np.zeros(4)
    m_eff = sim.bodies.mass[0] / 2
    zeta = -math.log(0.5) / math.sqrt(math.pi**2 + math.log(0.5) ** 2)
    pair_properties(0, 1, sim.spheres, sim.walls, sim.bodies, sim.mats, out)
    np.testing.assert_allclose(out, [1e5, 1e5, 0.05, 2 * zeta * math.sqrt(m_eff * 1e5)])
    pair_properties(0, -1, sim.spheres, sim.walls, sim.bodies, sim.mats, out)
    zeta = -math.log(0.8) / math.sqrt(math.pi**2 + math.log(0.8) ** 2)
    m = sim.bodies.mass[0]
    np.testing.assert_allclose(out, [1e5, 1e5, 0.3, 2 * zeta * math.sqrt(m * 1e5)])


# ----------------------------------------------------------------------- defaults, files


def _chain_of_boxes(set_to_min_rule):
    scene = Scene(gravity=(0.0, 0.0, -G))
    body = scene.add_material(Material(density=RHO, kn=2e4, friction=0.4, restitution=0.6))
    floor = scene.add_material(Material(density=RHO, kn=2e4, friction=0.7, restitution=0.3))
    if set_to_min_rule:
        scene.set_pair(body, floor, friction=0.4, restitution=0.3)
        scene.set_pair(body, body, friction=0.4, restitution=0.6)
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), floor)
    half = np.array([0.004, 0.01, 0.02])
    tilt = Rotation.from_rotvec([0.0, 0.3, 0.0]).as_matrix()
    for k in range(3):
        R, spin = (tilt, 5.0) if k == 0 else (np.eye(3), 0.0)
        z = 0.0225 if k == 0 else 0.0205
        scene.add_box((0.025 * k, 0.0, z), half, 0.001, body, orientation=R,
                      angular_velocity=(0.0, spin, 0.0))  # fmt: skip
    return scene.build(safety=0.05)


def test_pairs_set_to_the_min_rule_values_change_nothing():
    """Setting every pair to its min-rule values gives a bit-identical run (the pair
    table replaces the rule's values, nothing else)."""
    a, b = _chain_of_boxes(False), _chain_of_boxes(True)
    a.run(until=0.15)
    b.run(until=0.15)
    assert a.boxes.rows.n[0] > 0
    np.testing.assert_array_equal(a.bodies.pos, b.bodies.pos)
    np.testing.assert_array_equal(a.bodies.quat, b.bodies.quat)


def test_pair_tables_survive_a_state_round_trip_and_older_files_load_with_the_min_rule():
    scene = Scene()
    a = scene.add_material(Material(density=RHO, kn=1e5, friction=0.5, restitution=0.9))
    b = scene.add_material(Material(density=RHO, kn=1e5, friction=0.3))
    scene.set_pair(a, b, friction=0.1)
    scene.set_pair(b, a, restitution=0.4)  # keeps the friction set before
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), b)
    scene.add_sphere((0.0, 0.0, 0.01), 0.005, a)
    sim = scene.build()
    expected = np.full((2, 2), np.nan)
    expected[0, 1] = expected[1, 0] = 0.1
    np.testing.assert_array_equal(sim.mats.pair_friction, expected)
    expected[0, 1] = expected[1, 0] = 0.4
    np.testing.assert_array_equal(sim.mats.pair_restitution, expected)
    state = sim.get_state()
    restored = Simulation.from_state(state)
    np.testing.assert_array_equal(restored.mats.pair_restitution, sim.mats.pair_restitution)
    older = older_state(state, 1)  # (no version, no pair tables)
    restored = Simulation.from_state(older)
    assert np.isnan(restored.mats.pair_friction).all()
    assert restored.mats.pair_restitution.shape == (2, 2)
    sim.set_state(older)
    assert np.isnan(sim.mats.pair_friction).all()


@pytest.mark.parametrize(
    "kwargs, fragment",
    [
        ({"friction": -0.1}, "friction = -0.1 is outside the valid range [0, inf)"),
        ({"friction": math.inf}, "friction = inf is not a finite number"),
        ({"restitution": 0.0}, "restitution = 0 is outside the valid range (0, 1]"),
        ({"restitution": 1.5}, "restitution = 1.5 is outside the valid range (0, 1]"),
        ({"material_b": 7}, "material_b = 7 is not a material id; valid range [0, 1]"),
    ],
)
def test_bad_pair_values_are_refused_with_their_name(kwargs, fragment):
    scene = Scene()
    for _ in range(2):
        scene.add_material(Material(density=RHO, kn=1e5))
    args = {"material_a": 0, "material_b": 1, **kwargs}
    a, b = args.pop("material_a"), args.pop("material_b")
    with pytest.raises(ValueError) as err:
        scene.set_pair(a, b, **args)
    assert fragment in str(err.value)


def test_materials_giving_kn_are_the_rule_given_and_older_files_still_load():
    """Materials giving k_n set the stiffness rule RULE_GIVEN once (whatever
    ``stiffness_rule`` says); a state saved with the per-material flag of older files
    (``mats.given_kn``, rule 0) loads with that rule and runs bit-identically."""
    from dominowave.dem.material_pairs import RULE_GIVEN, RULE_YADE

    def build(rule):
        scene = Scene(stiffness_rule=rule)
        m = scene.add_material(Material(density=RHO, kn=1e5, restitution=0.5))
        scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
        scene.add_sphere((0.0, 0.0, 0.0051), 0.005, m, velocity=(0.0, 0.0, -0.2))
        return scene.build()

    assert build("paper").mats.rule[0] == build("yade").mats.rule[0] == RULE_GIVEN
    young = Scene(stiffness_rule="yade")
    young.add_material(Material(density=RHO, young=1e7))
    young.add_sphere((0.0, 0.0, 0.0), 0.005, 0)
    assert young.build().mats.rule[0] == RULE_YADE
    sim = build("paper")
    older = older_state(sim.get_state(), 1)
    assert older["mats.given_kn"][0] == 1  # (the paper rule, overridden by the flag)
    restored = Simulation.from_state(older)
    assert restored.mats.rule[0] == RULE_GIVEN
    sim.run(n_steps=3000)
    restored.run(n_steps=3000)
    np.testing.assert_array_equal(restored.bodies.pos, sim.bodies.pos)
    assert sim.bodies.vel_full[0, 2] > 0  # it bounced
