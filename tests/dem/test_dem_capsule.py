"""Capsules (spherocylinders) in the engine: the rounded cuboid whose core is a segment
(Scene.add_capsule).  Validations against independent calculations: the mass properties
against quadrature, the contact geometry against the exact distance of the cores (bounded
least squares), rolling down an incline against the rigid-body solution, elastic
collisions against the conservation laws, the planar against the general path."""

import math

import numpy as np
import pytest
from dem_scenes import at_core_gap, core_distance, manifold_buffers, momenta
from scipy.integrate import dblquad
from scipy.spatial.transform import Rotation

from dominowave.dem import Material, Scene, Simulation
from dominowave.dem.shapes.cuboid import (
    box_box,
    box_plane,
    box_sphere,
    capsule_mass_properties,
)
from dominowave.dem.shapes.rectangle import rect_plane

G = 9.81
RHO = 1200.0


def _core(c):
    """Core half-extents [m] of a capsule of half-length c (Scene.add_capsule)."""
    return np.array([0.0, 0.0, c])


# ----------------------------------------------------------------------- mass properties


@pytest.mark.parametrize("c, r", [(0.03, 0.01), (0.002, 0.02), (0.1, 0.001)])
def test_validate_capsule_mass_properties_against_quadrature(c, r):
    """m, the axial and the diametral moment of a uniform capsule against the volume
    integrals over the solid of revolution, rho(z) = r on the cylinder, ``sqrt(r^2 -
    (|z| - c)^2)`` on the caps (scipy dblquad in z and the distance s from the axis)."""
    rho = 1100.0
    mass, moments = capsule_mass_properties(c, r, rho)

    def radius_at(z):
        return r if abs(z) <= c else math.sqrt(max(r * r - (abs(z) - c) ** 2, 0.0))

    def integral(f):
        return rho * dblquad(
            lambda s, z: f(s, z) * 2.0 * math.pi * s, -c - r, c + r, 0.0, radius_at,
            epsabs=0.0, epsrel=1e-12,
        )[0]  # fmt: skip

    assert mass == pytest.approx(integral(lambda s, z: 1.0), rel=1e-9)
    assert moments[2] == pytest.approx(integral(lambda s, z: s * s), rel=1e-9)
    diametral = integral(lambda s, z: 0.5 * s * s + z * z)
    np.testing.assert_allclose(moments[:2], diametral, rtol=1e-9)


# ----------------------------------------------------------------------- geometry


def _manifold(xi, Ri, hi, ri, xj, Rj, hj, rj):
    normal, point, overlap, key = manifold_buffers()
    work = np.zeros((2, 9, 4))
    n = box_box(xi, Ri, hi, ri, xj, Rj, hj, rj, 0.0, work, normal, point, overlap, key)
    return normal[:n], point[:n], overlap[:n], key[:n]


@pytest.mark.parametrize("partner", ["capsule", "box"])
@pytest.mark.parametrize("seed", range(12))
def test_validate_capsule_pair_deepest_point_against_exact_distance(partner, seed):
    """A capsule and a capsule or a box in random attitudes, their cores ``g`` apart
    (``0 < g < r_i + r_j``): the deepest point of the manifold has the overlap ``r_i + r_j -
    g`` of the exact core distance, and no two points of it coincide (a core of zero extent
    gives each location once)."""
    rng = np.random.default_rng(seed)
    hi, ri = _core(0.02), 0.006
    box = (np.array([0.012, 0.004, 0.02]), 0.001)
    hj, rj = (_core(0.015), 0.004) if partner == "capsule" else box
    Ri = Rotation.random(random_state=rng).as_matrix()
    Rj = Rotation.random(random_state=rng).as_matrix()
    xi = rng.normal(size=3) * 0.01
    u = rng.normal(size=3)
    u /= np.linalg.norm(u)
    gap = rng.uniform(0.1, 0.9) * (ri + rj)
    xj = at_core_gap(xi, Ri, hi, Rj, hj, u, gap, far=0.5, steps=55)
    exact = core_distance(xi, Ri, hi, xj, Rj, hj)
    normal, point, overlap, _ = _manifold(xi, Ri, hi, ri, xj, Rj, hj, rj)
    assert overlap.size > 0
    assert overlap.max() == pytest.approx(ri + rj - exact, abs=1e-9 * (ri + rj))
    np.testing.assert_allclose(np.linalg.norm(normal, axis=1), 1.0, rtol=1e-12)
    gaps = np.linalg.norm(point[:, None] - point[None], axis=2) + np.eye(len(point))
    assert gaps.min() > 1e-6 * (ri + rj)


def _lying(axis, centre):
    """A capsule's (R, x) with its axis along the unit ``axis`` (in the xy plane)."""
    R = Rotation.align_vectors([axis], [[0.0, 0.0, 1.0]])[0].as_matrix()
    return R, np.asarray(centre, float)


# (body i: a capsule lying along x, c = 0.02, r = 0.005, its lowest core line at z = 0;
# partner j; the expected points as (x, y) of each and the overlap)
_FACE = np.array([0.03, 0.01, 0.01])  # a box's core, rounding 0.002
_DEPTH = 1e-5
_CASES = {
    "on a box face": (
        (_FACE, 0.002, np.eye(3), [0.0, 0.0, -0.007 - 0.01 + _DEPTH]),
        [(-0.02, 0.0), (0.02, 0.0)],
    ),
    "across a box face": (
        (np.array([0.01, 0.03, 0.01]), 0.002, np.eye(3), [0.0, 0.0, -0.007 - 0.01 + _DEPTH]),
        [(-0.01, 0.0), (0.01, 0.0)],
    ),
    "crossing a capsule": (
        (_core(0.02), 0.002, _lying([0.0, 1.0, 0.0], [0, 0, 0])[0], [0.0, 0.0, -0.007 + _DEPTH]),
        [(0.0, 0.0)],
    ),
    "parallel to a capsule": (
        (_core(0.02), 0.002, np.eye(3)[:, [1, 2, 0]], [0.015, 0.0, -0.007 + _DEPTH]),
        [(-0.005, 0.0), (0.02, 0.0)],
    ),
    "on a box edge": (  # (the box turned by 45 deg about x: an edge along the capsule)
        (
            np.array([0.03, 0.01, 0.01]),
            0.002,
            Rotation.from_rotvec([np.pi / 4, 0, 0]).as_matrix(),
            [0.0, 0.0, -0.007 + _DEPTH - 0.01 * np.sqrt(2.0)],
        ),
        [(-0.02, 0.0), (0.02, 0.0)],
    ),
}


@pytest.mark.parametrize("roll", [0.0, 0.3, np.pi / 4, np.pi / 2])
@pytest.mark.parametrize("swap", [False, True])
@pytest.mark.parametrize("case", _CASES)
def test_validate_capsule_lying_on_a_face_or_a_capsule_gets_its_exact_points(case, swap, roll):
    """A capsule lying on a box face, across a narrow one, across a capsule, along one
    (offset by 15 mm) and along a box edge: each touching place once -- the two caps on
    a face; the two places over the edges across a narrow face; the crossing point; the
    two ends of the overlap of two parallel segments or of the edge -- with the overlap
    of its depth (1e-5 m), whichever body is i, however the capsule's frame is turned
    about its axis (``roll``: the same body, other face axes in the separating-axis test)."""
    (hj, rj, Rj, xj), expected = _CASES[case]
    Ri, xi = _lying([1.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    Ri = Ri @ Rotation.from_rotvec([0.0, 0.0, roll]).as_matrix()
    pair = (xi, Ri, _core(0.02), 0.005), (np.array(xj, float), Rj, hj, rj)
    normal, point, overlap, _ = _manifold(*pair[swap], *pair[not swap])
    order = np.argsort(point[:, 0])
    np.testing.assert_allclose(point[order, :2], expected, atol=1e-12)
    np.testing.assert_allclose(overlap, _DEPTH, atol=1e-12)
    down = -1.0 if not swap else 1.0  # (from i to j)
    np.testing.assert_allclose(normal, [[0.0, 0.0, down]] * len(expected), atol=1e-12)


@pytest.mark.parametrize("roll", [0.0, np.pi / 2])
@pytest.mark.parametrize("swap", [False, True])
def test_validate_capsule_on_a_pitched_box_edge_touches_at_both_caps(swap, roll):
    """A capsule lying along a box edge that is pitched by 1e-4 rad (the box turned by 45
    deg about x, then by 1e-4 about y): two points, one at each cap, each with the overlap
    of its cap's centre over the box core (the exact distance), whichever body is i and
    however the capsule's frame is turned about its axis."""
    Ri, xi = _lying([1.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    Ri = Ri @ Rotation.from_rotvec([0.0, 0.0, roll]).as_matrix()
    hj, rj = np.array([0.03, 0.01, 0.01]), 0.002
    Rj = Rotation.from_rotvec([0.0, 1e-4, 0.0]) * Rotation.from_rotvec([np.pi / 4, 0, 0])
    Rj = Rj.as_matrix()
    xj = np.array([0.0, 0.0, -0.007 + _DEPTH - 0.01 * np.sqrt(2.0)])
    pair = (xi, Ri, _core(0.02), 0.005), (xj, Rj, hj, rj)
    _, point, overlap, _ = _manifold(*pair[swap], *pair[not swap])
    assert len(overlap) == 2
    order = np.argsort(point[:, 0])
    np.testing.assert_allclose(point[order, 0], [-0.02, 0.02], atol=1e-6)
    caps = (np.array([x, 0.0, 0.0]) for x in (-0.02, 0.02))  # (the capsule along x)
    exact = [0.007 - core_distance(cap, np.eye(3), np.zeros(3), xj, Rj, hj) for cap in caps]
    assert min(exact) > 0.0 and abs(exact[0] - exact[1]) > 3e-6  # (pitched: 1e-4 x 40 mm)
    # (to the manifold's tolerance, 1e-9 of the sizes: a face point's depth is taken
    # along the reference normal, 1e-4 rad off the true one here)
    np.testing.assert_allclose(overlap[order], exact, rtol=0, atol=1e-9 * (0.03 + 0.02 + 0.007))


def test_validate_capsule_and_sphere_against_the_point_segment_distance():
    """A sphere near a capsule: one point, overlap ``r + R - d`` with d the distance of the
    sphere's centre from the axis segment (clamped projection)."""
    rng = np.random.default_rng(3)
    c, r, radius = 0.02, 0.005, 0.008
    for _ in range(20):
        R = Rotation.random(random_state=rng).as_matrix()
        x = rng.normal(size=3) * 0.01
        centre = x + rng.normal(size=3) * 0.02
        along = np.clip((centre - x) @ R[:, 2], -c, c)
        d = np.linalg.norm(centre - (x + along * R[:, 2]))
        normal, point, overlap, key = manifold_buffers()
        n = box_sphere(x, R, _core(c), r, centre, radius, 1.0, normal, point, overlap, key)
        assert n == 1
        assert overlap[0] == pytest.approx(r + radius - d, abs=1e-12)


@pytest.mark.parametrize("tilt", [0.0, 0.3, math.pi / 2])
def test_validate_capsule_on_a_plane_touches_at_its_caps(tilt):
    """A capsule tilted by t from lying flat, its lower cap touching a plane: one point
    per cap within reach, overlap the cap's depth below ``z = r`` (its lowest point), 2
    points lying flat (t = 0), 1 otherwise; the planar geometry gives the same."""
    c, r, depth = 0.03, 0.01, 1e-5
    R = Rotation.from_rotvec([0.0, math.pi / 2 - tilt, 0.0]).as_matrix()  # axis 2 tilted
    x = np.array([0.0, 0.0, r - depth + c * math.sin(tilt)])
    ends = x + np.outer([-c, c], R[:, 2])
    expected = sorted(r - ends[:, 2][ends[:, 2] < r + 1e-3])  # within reach 1 mm
    for geometry in (box_plane, rect_plane):
        normal, point, overlap, key = manifold_buffers()
        n = geometry(x, R, _core(c), r, np.zeros(3), np.array([0.0, 0.0, 1.0]), 1e-3,
                     normal, point, overlap, key)  # fmt: skip
        assert n == len(expected) == (2 if tilt == 0.0 else 1)
        np.testing.assert_allclose(sorted(overlap[:n]), expected, atol=1e-15)
        assert len(set(key[:n])) == n


# ----------------------------------------------------------------------- engine


def rolling_down_an_incline(tilt_deg):
    """A capsule (c = 30 mm, r = 10 mm) lying across a rough plane inclined by t (gravity
    turned by t), run from rest: ``(acceleration [m/s^2] from 0.05 to 0.25 s, its value
    rolling without slip, omega r / v - 1, the slip work over the kinetic energy)``."""
    t = math.radians(tilt_deg)
    scene = Scene(gravity=(G * math.sin(t), 0.0, -G * math.cos(t)))
    m = scene.add_material(Material(density=RHO, kn=2e5, friction=1.0, restitution=0.3))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    c, r = 0.03, 0.01
    mass, moments = capsule_mass_properties(c, r, RHO)
    sink = mass * G * math.cos(t) / (2 * 2e5)
    scene.add_capsule((0.0, 0.0, r - sink), c, r, m, axis=(0.0, 1.0, 0.0))
    sim = scene.build(safety=0.05)
    sim.run(until=0.05)
    t1, v1 = sim.time, sim.bodies.vel_full[0, 0]
    sim.run(until=0.25)
    t2, v2 = sim.time, sim.bodies.vel_full[0, 0]
    expected = G * math.sin(t) / (1.0 + moments[2] / (mass * r * r))
    spin = sim.bodies.omega_full[0, 1] * r / v2 - 1.0
    slip = sim.energy()["dissipated_friction"] / (0.5 * mass * v2 * v2)
    return (v2 - v1) / (t2 - t1), expected, spin, slip


@pytest.mark.parametrize("tilt_deg", [10.0, 20.0])
def test_validate_capsule_rolling_down_an_incline(tilt_deg):
    """A capsule lying across a plane inclined by t, rough enough not to slip, rolls on
    its two caps with ``a = g sin t / (1 + I_axis / (m r^2))``, the acceleration of a
    rigid body of that moment rolling without slip; its spin follows ``omega = v / r``."""
    acceleration, expected, spin, slip = rolling_down_an_incline(tilt_deg)
    assert acceleration == pytest.approx(expected, rel=1e-4)
    assert abs(spin) < 2e-3
    assert slip < 1e-6  # no slip


def _two_bodies(partner, mu=0.0):
    """A spinning capsule flying obliquely at a capsule or a box, no gravity, elastic."""
    scene = Scene(gravity=(0.0, 0.0, 0.0))
    m = scene.add_material(Material(density=RHO, kn=5e5, friction=mu, restitution=1.0))
    scene.add_capsule(
        (0.0, 0.0, 0.0), 0.03, 0.01, m, axis=(0.3, 0.2, 1.0),
        velocity=(0.4, 0.05, 0.02), angular_velocity=(1.0, -2.0, 3.0),
    )  # fmt: skip
    if partner == "capsule":
        scene.add_capsule((0.06, 0.01, 0.005), 0.02, 0.012, m, axis=(1.0, -0.4, 0.2))
    else:
        R = Rotation.from_rotvec([0.2, 0.4, -0.3]).as_matrix()
        scene.add_box((0.065, 0.01, 0.005), (0.012, 0.02, 0.03), 0.002, m, orientation=R)
    return scene.build(safety=0.05)


@pytest.mark.parametrize("partner", ["capsule", "box"])
@pytest.mark.parametrize("mu", [0.0, 0.4])
def test_validate_elastic_capsule_collision_closes_the_energy_ledger(partner, mu):
    """An elastic oblique collision of a spinning capsule with a capsule or a box: the
    total energy (with the friction booked in the ledger) to < 1e-5, linear and angular
    momentum to round-off."""
    sim = _two_bodies(partner, mu)
    e0 = sim.energy()["total"]
    p0, L0 = momenta(sim)
    sim.run(until=0.4)
    assert abs(sim.bodies.vel_full[0, 0] - 0.4) > 0.05  # they did collide
    if mu > 0.0:
        assert sim.energy()["dissipated_friction"] > 1e-5 * e0  # it slid
    assert abs(sim.energy()["total"] - e0) < 1e-5 * e0
    p1, L1 = momenta(sim)
    scale_p = np.abs(sim.bodies.mass[:, None] * sim.bodies.vel_full).sum()
    np.testing.assert_allclose(p1, p0, atol=1e-13 * scale_p)
    np.testing.assert_allclose(L1, L0, atol=1e-12 * (np.abs(L0).sum() + scale_p * 0.05))


def _falling_capsule():
    """A capsule in the xz plane falling tilted onto the floor of a planar scene, rough:
    it lands on one cap, slides, turns and rests on both."""
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=RHO, kn=1e5, friction=0.5, restitution=0.4))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    scene.add_capsule(
        (0.0, 0.0, 0.04), 0.03, 0.01, m, axis=(1.0, 0.0, 0.5), blocked="y rx rz",
        velocity=(0.2, 0.0, 0.0), angular_velocity=(0.0, 3.0, 0.0),
    )  # fmt: skip
    return scene


def test_validate_planar_path_equals_general_path_for_capsules():
    """The falling capsule run with the planar kernels (a row per point: a capsule lying
    in the plane touches at one point, not along y) and with the general 3D ones: the same
    trajectory to round-off, at rest on both caps, each carrying half its weight."""
    out = []
    for kernels in (True, False):
        sim = _falling_capsule().build(safety=0.05)
        sim.planar_kernels = kernels
        res = sim.run(until=0.6, trajectory_every=2000)
        assert sim.settings.planar == kernels
        rows = sim.boxes.rows
        n = rows.n[0]
        assert n == 2
        np.testing.assert_allclose(rows.mult[:n], 1.0)
        np.testing.assert_allclose(rows.fn[:n], sim.bodies.mass[0] * G / 2, rtol=1e-12)
        out.append((res.positions[:, 0].copy(), res.quaternions[:, 0].copy()))
    np.testing.assert_allclose(out[0][0], out[1][0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(out[0][1], out[1][1], rtol=0, atol=1e-10)


def _standing_on_a_box(capsule_first, x=0.0):
    """A capsule standing upright on a box that rests on the floor, in a planar scene
    (the capsule added before or after the box), its axis at ``x`` [m]."""
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=RHO, kn=1e5, friction=0.5, restitution=0.4))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    box = dict(centre=(0.0, 0.0, 0.01 - 1e-6), half_extents=(0.02, 0.01, 0.01), rounding=0.001)

    def capsule():
        return scene.add_capsule((x, 0.0, 0.05), 0.02, 0.01, m, blocked="y rx rz")

    body = capsule() if capsule_first else None
    scene.add_box(material=m, blocked="y rx rz", **box)
    return scene, capsule() if body is None else body


@pytest.mark.parametrize("x", [0.0, 1.234e-3])
@pytest.mark.parametrize("capsule_first", [True, False])
def test_validate_capsule_standing_on_a_box_touches_at_one_point(capsule_first, x):
    """A capsule standing on its cap on a box (both moving in the xz plane), centred on
    it or not, rests on one point carrying its weight, with the planar kernels (the end
    of its core, a zero extent, clips a box face to one point, whichever body is the
    reference) and the general ones alike, in either order of the bodies: the same
    trajectory."""
    out = []
    for kernels in (True, False):
        scene, body = _standing_on_a_box(capsule_first, x)
        sim = scene.build(safety=0.05)
        sim.planar_kernels = kernels
        res = sim.run(until=0.3, trajectory_every=1000)
        assert sim.settings.planar == kernels
        rows = sim.boxes.rows
        n = rows.n[0]
        pair = (rows.j[:n] >= 0) & (rows.j[:n] < 2)
        assert pair.sum() == 1
        assert rows.mult[:n][pair][0] == 1.0
        weight = sim.bodies.mass[body] * G
        assert rows.fn[:n][pair][0] == pytest.approx(weight, rel=1e-12 if x == 0.0 else 1e-6)
        out.append(res.positions[:, body].copy())
    np.testing.assert_allclose(out[0], out[1], rtol=0, atol=1e-12)


def test_a_capsule_scene_resumes_bit_identically_from_its_state():
    """A capsule falling onto a box on the floor, saved mid-run (its contact rows and
    their shear springs) and resumed in a new Simulation: the same trajectory to the bit
    as the run that went on."""
    scene, _ = _standing_on_a_box(True, x=0.004)
    first = scene.build(safety=0.05)
    first.run(until=0.05)
    resumed = Simulation.from_state(first.get_state())
    a = first.run(until=0.15, trajectory_every=500)
    b = resumed.run(until=0.15, trajectory_every=500)
    assert first.boxes.rows.n[0] > 0
    np.testing.assert_array_equal(a.positions, b.positions)
    np.testing.assert_array_equal(a.quaternions, b.quaternions)


def test_a_capsule_at_rest_sleeps():
    """A capsule dropped flat onto the floor of a scene that puts resting bodies to sleep
    comes to rest on its two caps and is put to sleep: held, at rest, its floor rows put
    aside."""
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=RHO, kn=2e4, friction=0.4, restitution=0.5))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    scene.add_capsule((0.0, 0.0, 0.011), 0.03, 0.01, m, axis=(1.0, 0.0, 0.0))
    sim = scene.build(safety=0.1, sleep_speed=1e-3, sleep_time=0.02)
    sim.run(until=0.3)
    assert sim.bodies.held[0] == 1
    np.testing.assert_array_equal(sim.bodies.vel, 0.0)
    assert sim.boxes.rows.n[0] == 0 and sim.boxes.dormant.n[0] == 2


def test_hertz_contacts_refuse_capsules():
    scene = Scene(normal_law="hertz")
    m = scene.add_material(Material(density=RHO, young=1e9, poisson=0.3))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    scene.add_capsule((0.0, 0.0, 0.02), 0.03, 0.01, m)
    with pytest.raises(ValueError, match="this scene has capsules"):
        scene.build()


def test_a_capsule_along_y_runs_the_general_kernels():
    """A capsule whose axis is world y has its body axis 1 off y: the scene is not planar
    (its planar geometry would take the axis out of the plane), whatever it blocks."""
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=RHO, kn=1e5))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    scene.add_capsule((0.0, 0.0, 0.02), 0.03, 0.01, m, axis=(0.0, 1.0, 0.0), blocked="y rx rz")
    assert not scene.build().planar


@pytest.mark.parametrize(
    "args, options, fragment",
    [
        ((0.0, 0.01), {}, "half_length of body 0 = 0 is outside the valid range (0, inf)"),
        ((np.inf, 0.01), {}, "half_length of body 0 = inf is outside the valid range (0, inf)"),
        ((0.02, -0.01), {}, "radius of body 0 = -0.01 is outside the valid range (0, inf)"),
        ((0.02, 0.01), {"axis": (0.0, 0.0, 0.0)}, "axis = (0.0, 0.0, 0.0) has no direction"),
        ((0.02, 0.01), {"axis": (1.0, 0.0)}, "axis = (1.0, 0.0) must have 3 components"),
        ((0.02, 0.01), {"mass": 0.0}, "mass = 0"),
    ],
)
def test_bad_capsule_input_is_refused_with_its_name(args, options, fragment):
    scene = Scene()
    m = scene.add_material(Material(density=RHO, kn=1e4))
    with pytest.raises(ValueError) as err:
        scene.add_capsule((0.0, 0.0, 0.1), *args, m, **options)
    assert fragment in str(err.value)
