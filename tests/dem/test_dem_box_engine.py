"""Rounded-cuboid bodies in the engine (dem/boxes.py): validations against independent
calculations (an incline, resting corners, tipping against an ODE, elastic and
eccentric collisions, the planar against the general path)."""

import math

import numpy as np
import pytest
from dem_scenes import momenta
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from dominowave.dem import Material, Scene

G = 9.81
RHO = 1000.0


def _about_y(angle):
    return Rotation.from_rotvec([0.0, angle, 0.0]).as_matrix()


def _rotation_angle(q):
    """Angle [rad] of the rotation of the quaternion q (w, x, y, z)."""
    return 2.0 * math.atan2(np.linalg.norm(q[1:]), abs(q[0]))


# ----------------------------------------------------------------------- at rest


@pytest.mark.parametrize("planar", [False, True])
def test_validate_box_dropped_flat_rests_on_its_corners(planar):
    """A cuboid dropped flat settles with each of its 4 (3D) / 2 (2D) bottom corners
    carrying m g / 4 per corner of the 3D body, and without rotation (< 1e-9 rad)."""
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=RHO, kn=2e4, friction=0.5, restitution=0.3))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    half = np.array([0.012, 0.004, 0.024])
    blocked = "y rx rz" if planar else ""
    scene.add_box((0.0, 0.0, half[2] + 0.002), half, 0.001, m, blocked=blocked)
    sim = scene.build(safety=0.05)
    assert sim.planar == planar
    sim.run(until=0.5)
    rows = sim.boxes.rows
    n = rows.n[0]
    weight = sim.bodies.mass[0] * G
    assert n == (2 if planar else 4)
    per_corner = rows.fn[:n]  # (a planar row stands for mult = 2 corners)
    np.testing.assert_allclose(per_corner, weight / 4, rtol=1e-9)
    np.testing.assert_allclose(rows.mult[:n], 2.0 if planar else 1.0)
    assert _rotation_angle(sim.bodies.quat[0]) < 1e-9
    np.testing.assert_allclose(sim.bodies.pos[0, :2], 0.0, atol=1e-12)


# ----------------------------------------------------------------------- incline


@pytest.mark.parametrize("tilt_deg, mu", [(30.0, 0.3), (30.0, 0.7), (15.0, 0.2)])
def test_validate_box_on_an_incline_slides_or_sticks(tilt_deg, mu):
    """A flat cuboid on a plane inclined by t (gravity turned by t): it slides with
    a = g (sin t - mu cos t) if tan t > mu and sticks otherwise."""
    t = math.radians(tilt_deg)
    gravity = (G * math.sin(t), 0.0, -G * math.cos(t))
    scene = Scene(gravity=gravity)
    m = scene.add_material(Material(density=RHO, kn=1e5, friction=mu, restitution=0.2))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    half = np.array([0.02, 0.02, 0.005])  # flat: it cannot tip
    r = 0.001
    mass = 8 * half.prod() * RHO
    sink = mass * G * math.cos(t) / (4 * 1e5)
    scene.add_box((0.0, 0.0, half[2] - sink), half, r, m)
    sim = scene.build(safety=0.05)
    sim.run(until=0.05)  # the normal contacts settle (dashpot)
    t1, v1 = sim.time, sim.bodies.vel_full[0, 0]
    x1 = sim.bodies.pos[0, 0]
    sim.run(until=0.25)
    t2, v2 = sim.time, sim.bodies.vel_full[0, 0]
    x2 = sim.bodies.pos[0, 0]
    expected = G * (math.sin(t) - mu * math.cos(t))
    if expected > 0:
        assert (v2 - v1) / (t2 - t1) == pytest.approx(expected, rel=1e-4)
    else:
        # sticking: the box rests on its tangential springs, which carry m g sin t; it
        # moved by a few static deflections m g sin t / (4 k_t) (its springs were
        # loaded suddenly), no more
        assert abs(v2) < 1e-6
        assert abs(x2 - x1) < 1e-9
        assert abs(sim.bodies.pos[0, 0]) < 5 * mass * G * math.sin(t) / (4 * 1e5)


# ----------------------------------------------------------------------- tipping


def _tipping_scene(planar, r=1e-6):
    """A thin cuboid (thickness 2a along x, height 2c) standing on its bottom edge at
    x = +a, tilted just past balance."""
    a, b, c = 0.005, 0.005, 0.025
    tilt = math.atan2(a, c) + 0.02
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=RHO, kn=1e5, friction=2.0, restitution=0.5))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    R = _about_y(tilt)  # box axis z turned towards +x
    pivot = R @ np.array([a - r, 0.0, -(c - r)])  # core edge relative to the centre
    centre = np.array([0.0, 0.0, r]) - pivot
    scene.add_box(centre, (a, b, c), r, m, orientation=R, blocked="y rx rz" if planar else "")
    return scene, tilt, (a, b, c)


def test_validate_box_tipping_over_its_edge_matches_the_rigid_body_ode():
    """From rest just past balance the cuboid turns about its bottom edge:
    ``I_p psi'' = m g rho sin psi`` (psi the angle of the COM past the vertical through
    the edge, rho = sqrt(a^2 + c^2), I_p = 4/3 m rho^2), until its face lands
    (tilt 90 deg).  The tilt is compared with solve_ivp up to 85 deg."""
    scene, tilt0, (a, _, c) = _tipping_scene(planar=True)
    sim = scene.build(safety=0.05)
    res = sim.run(until=0.6, trajectory_every=50)
    times = res.times
    quats = res.quaternions[:, 0]
    tilt = np.array([Rotation.from_quat(q[[1, 2, 3, 0]]).as_rotvec()[1] for q in quats])
    rho = math.hypot(a, c)
    beta = math.atan2(a, c)
    omega2 = 3.0 * G / (4.0 * rho)

    def ode(_, y):
        return [y[1], omega2 * math.sin(y[0])]

    def landed(_, y):
        return y[0] + beta - math.radians(85.0)

    landed.terminal = True
    sol = solve_ivp(ode, (0.0, 2.0), [tilt0 - beta, 0.0], events=landed, rtol=1e-11, atol=1e-13,
                    dense_output=True)  # fmt: skip
    t_land = sol.t_events[0][0]
    # the simulated time of reaching 85 deg
    k = np.flatnonzero(tilt >= math.radians(85.0))[0]
    frac = (math.radians(85.0) - tilt[k - 1]) / (tilt[k] - tilt[k - 1])
    t_sim = times[k - 1] + frac * (times[k] - times[k - 1])
    assert t_sim == pytest.approx(t_land, rel=2e-3)
    # and the whole history before
    early = times < 0.9 * t_land
    psi = sol.sol(times[early])[0] + beta
    np.testing.assert_allclose(tilt[early], psi, atol=2e-3)


# ----------------------------------------------------------------------- collisions


def _two_box_collision(mu=0.0, restitution=None, n_steps=100_000):
    scene = Scene(gravity=(0.0, 0.0, 0.0))
    m = scene.add_material(Material(density=RHO, kn=5e4, friction=mu, restitution=restitution))
    half = np.array([0.01, 0.008, 0.015])
    Ri = Rotation.from_rotvec([0.3, -0.2, 0.5]).as_matrix()
    Rj = Rotation.from_rotvec([-0.4, 0.6, 0.1]).as_matrix()
    scene.add_box((0.0, 0.0, 0.0), half, 0.001, m, orientation=Ri, velocity=(0.4, 0.02, 0.01),
                  angular_velocity=(1.0, -2.0, 3.0))  # fmt: skip
    scene.add_box((0.045, 0.006, -0.004), half * [1.2, 0.9, 1.0], 0.0015, m, orientation=Rj,
                  velocity=(-0.3, 0.0, 0.02), angular_velocity=(0.0, 4.0, -1.0))  # fmt: skip
    sim = scene.build(safety=0.02)
    return sim


def test_validate_elastic_box_collision_conserves_energy_and_momenta():
    """Two rotating cuboids collide obliquely (elastic, frictionless): total energy to
    < 1e-5 over 1e5 steps, linear and angular momentum to round-off."""
    sim = _two_box_collision()
    e0 = sim.energy()["total"]
    p0, L0 = momenta(sim)
    res = sim.run(n_steps=100_000, energy_every=1000)
    assert res.n_steps == 100_000
    # the boxes did collide: their velocities changed
    assert abs(sim.bodies.vel_full[0, 0] - 0.4) > 0.1
    p1, L1 = momenta(sim)
    e1 = sim.energy()["total"]
    assert abs(e1 - e0) < 1e-5 * e0
    scale_p = np.abs(sim.bodies.mass[:, None] * sim.bodies.vel_full).sum()
    np.testing.assert_allclose(p1, p0, atol=1e-13 * scale_p)
    np.testing.assert_allclose(L1, L0, atol=1e-12 * (np.abs(L0).sum() + scale_p * 0.05))


def test_validate_elastic_box_collision_with_friction_closes_the_energy_ledger():
    """With friction the energy dissipated by slip is booked: the total stays constant
    to < 1e-5 as well; momenta to round-off."""
    sim = _two_box_collision(mu=0.4)
    e0 = sim.energy()["total"]
    p0, L0 = momenta(sim)
    sim.run(n_steps=100_000)
    energy = sim.energy()
    assert energy["dissipated_friction"] > 1e-4 * e0  # it slid
    assert abs(energy["total"] - e0) < 1e-5 * e0
    p1, L1 = momenta(sim)
    scale_p = np.abs(sim.bodies.mass[:, None] * sim.bodies.vel_full).sum()
    np.testing.assert_allclose(p1, p0, atol=1e-13 * scale_p)
    np.testing.assert_allclose(L1, L0, atol=1e-12 * (np.abs(L0).sum() + scale_p * 0.05))


@pytest.mark.parametrize("restitution", [0.3, 0.7, 0.9, 1.0])
def test_validate_eccentric_corner_impact_has_the_set_restitution(restitution):
    """A tilted cuboid falls corner-first onto a plane (no gravity, so only the
    impact acts): the normal velocity of the material point at the corner after the
    impact is -e times the one before, e the set restitution (within 1 %), although the
    impact spins the body (the dashpot from the effective mass at the contact point)."""
    scene = Scene(gravity=(0.0, 0.0, 0.0))
    m = scene.add_material(Material(density=RHO, kn=1e6, restitution=restitution))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    half = np.array([0.01, 0.006, 0.02])
    r = 0.0005
    R = Rotation.from_rotvec([0.35, -0.5, 0.0]).as_matrix()
    core = half - r
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    world = corners * core @ R.T
    low = np.argmin(world[:, 2])
    centre = np.array([0.0, 0.0, r + 1e-4]) - world[low]
    scene.add_box(centre, half, r, m, orientation=R, velocity=(0.0, 0.0, -0.5))
    sim = scene.build(safety=0.02)

    def corner_velocity():
        b = sim.bodies
        arm = b.rot[0] @ (corners[low] * core)
        return (b.vel_full[0] + np.cross(b.omega_full[0], arm))[2]

    v_before = corner_velocity()
    touched = False
    while not touched or sim.boxes.rows.n[0] > 0:  # until the impact is over
        sim.run(n_steps=1)
        assert sim.boxes.rows.n[0] <= 1  # one corner only
        touched = touched or sim.boxes.rows.n[0] == 1
    assert np.abs(sim.bodies.omega_full[0]).max() > 1.0  # the impact spun the body
    # (measured right after the impact: in free flight the corner's velocity changes as
    # the body tumbles)
    assert -corner_velocity() / v_before == pytest.approx(restitution, rel=1e-2)


# ----------------------------------------------------------------------- planar path


def test_validate_planar_path_equals_general_path_for_boxes():
    """The tipping scene (a box toppling onto the floor, friction, dashpot) run with the
    planar kernels and with the general 3D ones: the same trajectory to round-off."""
    out = []
    for kernels in (True, False):
        scene, _, _ = _tipping_scene(planar=True, r=1e-4)
        sim = scene.build(safety=0.05)
        sim.planar_kernels = kernels
        res = sim.run(until=0.5, trajectory_every=2000)
        assert sim.settings.planar == kernels
        out.append((res.positions[:, 0].copy(), res.quaternions[:, 0].copy()))
    np.testing.assert_allclose(out[0][0], out[1][0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(out[0][1], out[1][1], rtol=0, atol=1e-10)


# ----------------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    "half, rounding, options, fragment",
    [
        ((0.01, 0.0, 0.02), 0.001, {}, "half_extents[1] of body 0 = 0"),
        ((0.01, 0.005, 0.02), 0.006, {}, "rounding = 0.006 is outside the valid range [0, 0.005)"),
        ((0.01, 0.005, 0.02), -0.001, {}, "rounding = -0.001"),
        ((0.01, 0.005, 0.02), 0.001, {"orientation": np.diag([1.0, 1.0, -1.0])}, "reflection"),
        ((0.01, 0.005, 0.02), 0.001, {"orientation": np.ones((3, 3))}, "not a 3 x 3 rotation"),
        ((0.01, 0.005, 0.02), 0.001, {"mass": -1.0}, "mass = -1"),
    ],
)
def test_bad_box_input_is_refused_with_its_name(half, rounding, options, fragment):
    scene = Scene()
    m = scene.add_material(Material(density=RHO, kn=1e4))
    with pytest.raises(ValueError) as err:
        scene.add_box((0.0, 0.0, 0.1), half, rounding, m, **options)
    assert fragment in str(err.value)


# ----------------------------------------------------------------------- events


def test_validate_box_contact_events_at_the_free_fall_and_approach_times():
    """Body-level contact events of boxes: a box falling from rest onto the floor touches
    it at ``sqrt(2 h / g)``; two boxes approaching at relative speed v from a gap h touch
    at ``h / v`` and the touched stop fires there.  Event times are interpolated within
    the step (as for spheres)."""
    from dominowave.dem import ONSET, StopCondition

    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=RHO, kn=1e5, restitution=0.5))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    half = np.array([0.01, 0.01, 0.01])
    gap = 0.002
    scene.add_box((0.0, 0.0, half[2] + gap), half, 0.001, m)
    sim = scene.build(safety=0.05)
    res = sim.run(until=0.05)
    ev = res.events
    assert (ev.body_i[0], ev.body_j[0], ev.kind[0]) == (0, -1, ONSET)
    assert ev.time[0] == pytest.approx(math.sqrt(2 * gap / G), abs=1e-3 * sim.dt)

    scene = Scene(gravity=(0.0, 0.0, 0.0))
    m = scene.add_material(Material(density=RHO, kn=1e5))
    scene.add_box((0.0, 0.0, 0.0), half, 0.001, m, velocity=(0.3, 0.0, 0.0))
    scene.add_box((0.02 + 0.001, 0.003, 0.0), half, 0.001, m, velocity=(-0.1, 0.0, 0.0))
    sim = scene.build(safety=0.05)
    res = sim.run(until=1.0, stop=StopCondition(touched_body=1))
    assert res.stop_reason == "touched"
    assert res.events.kind[0] == ONSET
    assert res.events.time[0] == pytest.approx(0.001 / 0.4, abs=1e-9)
    assert sim.pairs.first_contact[0, 1] == res.events.time[0]
    res = sim.run(until=0.05)  # the boxes part again: one end event
    assert list(res.events.kind) == [0]
    assert sim.pairs.n_contacts[0, 1] == 1


def test_box_time_step_estimate_takes_every_kind_of_partner():
    """The boxes' frequency bound (timestep._box_omega2) looks at each kind of partner
    (material and rounding; a wall with the box's rounding) once: it equals the bound
    taken over every box and wall for every box, on a scene of two materials, two
    roundings, two sizes and two walls of a third material."""
    from dominowave.dem import timestep
    from dominowave.dem.material_pairs import pair_stiffness, particle_stiffness

    scene = Scene(gravity=(0.0, 0.0, -9.81))
    soft = scene.add_material(Material(density=900.0, kn=2e4, friction=0.3))
    stiff = scene.add_material(Material(density=1500.0, kn=7e4, kt_ratio=0.6, friction=0.5))
    wall = scene.add_material(Material(density=1000.0, kn=3e5, friction=0.8))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), wall)
    scene.add_wall((-0.1, 0.0, 0.0), (1.0, 0.0, 0.0), wall)
    for k, (m, r, size) in enumerate(
        [(soft, 1e-4, 1.0), (stiff, 3e-4, 1.0), (soft, 3e-4, 2.0), (stiff, 1e-4, 0.5)]
    ):
        half = size * np.array([0.0025, 0.0125, 0.025])
        scene.add_box((0.03 * k, 0.0, 0.05), half, r, m)
    sim = scene.build()
    bodies, boxes, walls, mats = sim.bodies, sim.boxes, sim.walls, sim.mats
    rule = int(mats.rule[0])

    def k_pair(ma, ra, mb, rb, kt):
        ka = particle_stiffness(mats.young[ma], mats.kn[ma], ra, rule)
        kb = particle_stiffness(mats.young[mb], mats.kn[mb], rb, rule)
        if kt:
            ka, kb = ka * mats.kt_ratio[ma], kb * mats.kt_ratio[mb]
        return pair_stiffness(ka, kb, rule)

    expected = 0.0
    for x in range(boxes.body.size):
        m, r = boxes.material[x], boxes.radius[x]
        partners = [(boxes.material[y], boxes.radius[y]) for y in range(boxes.body.size)]
        partners += [(w, r) for w in walls.material]
        k = max(max(k_pair(m, r, pm, pr, False), k_pair(m, r, pm, pr, True)) for pm, pr in partners)
        expected = max(expected, 4.0 * k * timestep._box_inverse_mass(bodies, boxes, x))
    assert timestep._box_omega2(bodies, boxes, walls, mats) == expected
