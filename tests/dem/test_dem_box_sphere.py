"""Box-sphere contacts (boxes._box_sphere_pass; shapes.cuboid.box_sphere and its planar
version shapes.rectangle.rect_sphere): validations against closed forms and
conservation laws."""

import math

import numpy as np
import pytest
from dem_scenes import manifold_buffers, momenta
from scipy.spatial.transform import Rotation

from dominowave.dem import ONSET, Material, Scene, Simulation, timestep
from dominowave.dem.boxes import empty_boxes
from dominowave.dem.shapes.cuboid import box_sphere
from dominowave.dem.shapes.rectangle import rect_sphere

G = 9.81
RHO = 1000.0
HALF = np.array([0.01, 0.008, 0.015])
R_BOX = 0.001
R_BALL = 0.004
PLANAR = "y rx rz"


# ----------------------------------------------------------------------- geometry
def test_validate_planar_box_sphere_geometry_equals_the_3d_one():
    """A box turned about y and a sphere in its plane (and beside it in y): the planar
    function gives the 3D function's point, normal and overlap to round-off, for
    centres off a face, off an edge and off a corner region of the rectangle."""
    rng = np.random.default_rng(7)
    core = HALF - R_BOX
    checked = inside_checked = 0
    for _ in range(400):
        R = Rotation.from_rotvec([0.0, rng.uniform(-math.pi, math.pi), 0.0]).as_matrix()
        x = rng.uniform(-0.01, 0.01, 3)
        c = x + rng.uniform(-0.03, 0.03, 3)
        c[1] = x[1] + rng.choice([0.0, rng.uniform(-0.012, 0.012)])
        out3, out2 = manifold_buffers(), manifold_buffers()
        n3 = box_sphere(x, R, core, R_BOX, c, R_BALL, 1.0, *out3)
        n2 = rect_sphere(x, R, core, R_BOX, c, R_BALL, 1.0, *out2)
        assert n3 == n2 == 1
        depth = core - np.abs(R.T @ (c - x))  # how deep inside each pair of faces
        if np.all(depth >= 0.0) and depth[1] < min(depth[0], depth[2]):
            continue  # (inside, nearest the y faces: the planar path takes an in-plane face)
        inside_checked += bool(np.all(depth >= 0.0))
        np.testing.assert_allclose(out2[0][0], out3[0][0], atol=1e-14)
        np.testing.assert_allclose(out2[1][0], out3[1][0], atol=1e-14)
        np.testing.assert_allclose(out2[2][0], out3[2][0], atol=1e-15)
        checked += 1
    assert checked > 300 and inside_checked > 0


# ----------------------------------------------------------------------- impacts
def _head_on(planar, restitution, mu=0.0, kn=2e4, speed=0.3, peak=False):
    """A ball flying down onto the middle of a free box's top face, no gravity."""
    scene = Scene(gravity=(0.0, 0.0, 0.0))
    m = scene.add_material(Material(density=RHO, kn=kn, friction=mu, restitution=restitution))
    blocked = PLANAR if planar else ""
    scene.add_box((0.0, 0.0, 0.0), HALF, R_BOX, m, blocked=blocked)
    scene.add_sphere((0.0, 0.0, HALF[2] + R_BALL + 1e-4), R_BALL, m, blocked=blocked,
                     velocity=(0.0, 0.0, -speed))  # fmt: skip
    return scene.build(safety=0.02, record_peak_force=peak)


@pytest.mark.parametrize("planar", [False, True])
@pytest.mark.parametrize("restitution", [0.3, 0.7, 1.0])
def test_validate_ball_bouncing_on_a_box_face(planar, restitution):
    """Head-on impact of a ball on a free box's face: the relative normal velocity after
    is -e times the one before (e set), and the contact lasts the half period of the
    damped linear oscillator of the effective mass ``m_b m_s / (m_b + m_s)``,
    ``t_c = pi / sqrt(k/m_eff - (c / 2 m_eff)^2)`` with ``c = 2 zeta sqrt(m_eff k)``,
    ``zeta = -ln e / sqrt(pi^2 + ln^2 e)``; no rotation (measured 2026-11-25, ~300 steps
    in contact: restitution -8.3e-5 / -2.1e-5 / -2.4e-10 at e = 0.3 / 0.7 / 1, contact
    time 1.0e-5 / -3.8e-6 / -4.6e-6; planar -8.4e-5 / -2.1e-5 / -2.6e-11 and 1.6e-5 /
    -2.1e-6 / -4.7e-6)."""
    kn, speed = 2e4, 0.3
    sim = _head_on(planar, restitution, kn=kn, speed=speed)
    assert sim.planar == planar
    mb, ms = sim.bodies.mass
    res = sim.run(until=0.02)
    v = sim.bodies.vel_full
    rel = v[1, 2] - v[0, 2]
    assert rel == pytest.approx(restitution * speed, rel=3e-4)
    m_eff = mb * ms / (mb + ms)
    log_e = math.log(restitution)
    zeta = -log_e / math.sqrt(math.pi**2 + log_e**2)
    t_c = math.pi / (math.sqrt(kn / m_eff) * math.sqrt(1.0 - zeta**2))
    ev = res.events
    onset = ev.time[(ev.kind == ONSET) & (ev.body_j == 1)]
    end = ev.time[(ev.kind != ONSET) & (ev.body_j == 1)]
    assert onset.size == end.size == 1
    assert end[0] - onset[0] == pytest.approx(t_c, rel=1e-4)
    assert np.abs(sim.bodies.omega_full).max() < 1e-12


def _oblique(planar, mu, skin=None, balls=1):
    """A spinning ball hits a turning, tilted free box off-centre, no gravity, elastic
    (``balls`` > 1: more balls far away, in a row along x)."""
    scene = Scene(gravity=(0.0, 0.0, 0.0))
    m = scene.add_material(Material(density=RHO, kn=5e4, friction=mu, restitution=1.0))
    blocked = PLANAR if planar else ""
    tilt = [0.0, 0.4, 0.0] if planar else [0.3, 0.4, -0.2]
    spin = (0.0, 3.0, 0.0) if planar else (1.0, 3.0, -2.0)
    R = Rotation.from_rotvec(tilt).as_matrix()
    scene.add_box((0.0, 0.0, 0.0), HALF, R_BOX, m, blocked=blocked, orientation=R,
                  angular_velocity=spin)  # fmt: skip
    scene.add_sphere((0.004, 0.0, 0.022), R_BALL, m, blocked=blocked, velocity=(0.05, 0.0, -0.4),
                     angular_velocity=(0.0, -20.0, 0.0))  # fmt: skip
    for k in range(1, balls):
        scene.add_sphere((0.05 * k, 0.0, 0.0), R_BALL, m, blocked=blocked)
    return scene.build(safety=0.02, skin=skin)


@pytest.mark.parametrize("planar", [False, True])
@pytest.mark.parametrize("mu", [0.0, 0.5])
def test_validate_elastic_ball_box_collision_conserves_energy_and_momenta(planar, mu):
    """An oblique elastic impact of a spinning ball on a turning box, 1e5 steps: the
    total energy (with the friction ledger) constant to < 1e-5, linear momentum to
    round-off, angular momentum to round-off (3D: all components; planar: about y)."""
    sim = _oblique(planar, mu)
    e0 = sim.energy()["total"]
    p0, L0 = momenta(sim)
    v0 = sim.bodies.vel_full[1].copy()
    res = sim.run(n_steps=100_000)
    assert res.n_steps == 100_000
    assert np.abs(sim.bodies.vel_full[1] - v0).max() > 0.1  # they collided
    energy = sim.energy()
    if mu > 0:
        assert energy["dissipated_friction"] > 1e-4 * e0  # it slid
    assert abs(energy["total"] - e0) < 1e-5 * e0
    p1, L1 = momenta(sim)
    scale_p = np.abs(sim.bodies.mass[:, None] * sim.bodies.vel_full).sum()
    np.testing.assert_allclose(p1, p0, atol=1e-13 * scale_p)
    axes = [1] if planar else [0, 1, 2]
    np.testing.assert_allclose(L1[axes], L0[axes], atol=1e-12 * (np.abs(L0).sum() + scale_p * 0.05))


def test_validate_planar_and_3d_paths_agree():
    """The same oblique scene in the plane (blocked "y rx rz"), once with the planar
    kernels and once with the general ones: trajectories agree to round-off."""
    planar, general = _oblique(True, 0.5), _oblique(True, 0.5)
    general.planar_kernels = False
    a = planar.run(n_steps=20_000, trajectory_every=500)
    b = general.run(n_steps=20_000, trajectory_every=500)
    assert planar.settings.planar and not general.settings.planar
    np.testing.assert_allclose(a.positions, b.positions, rtol=0, atol=1e-12)
    np.testing.assert_allclose(a.velocities, b.velocities, rtol=0, atol=1e-9)


def test_box_sphere_checkpoint_resumes_bit_identically(tmp_path):
    sim = _oblique(False, 0.5)
    while sim.boxes.rows.n[0] == 0:  # to a step in contact
        sim.run(n_steps=500)
        assert sim.time < 0.05
    sim.save(tmp_path / "s.npz")
    sim.run(n_steps=3000)
    reference = sim.get_state()
    restored = Simulation.load(tmp_path / "s.npz")
    restored.run(n_steps=3000)
    again = restored.get_state()
    for key, value in reference.items():
        np.testing.assert_array_equal(again[key], value, err_msg=key)


@pytest.mark.parametrize("planar", [False, True])
def test_validate_ball_rolling_off_a_box_edge(planar):
    """A ball rolling without slipping over the rounded top edge of a fixed box: its
    centre on the circle of radius ``rho = R + r`` about the core edge, energy
    ``7/10 m v^2 + m g rho cos t = 7/10 m v0^2 + m g rho`` (spin ``v / R``) and
    ``m g cos t - N = m v^2 / rho`` give the normal force
    ``N = m g (17 cos t - 10 - 7 v0^2 / (g rho)) / 7``, which vanishes at
    ``cos t = (10 + 7 v0^2 / (g rho)) / 17`` (10/17 from rest), where the ball leaves.
    The normal force recorded (contact-force recorder, box-sphere rows) against the
    angle of the recorded centre: within 3e-4 m g of that line while N > 0.1 m g (past
    10 degrees), and its zero, extrapolated from there, within 3e-4 in cos t (measured:
    6.4e-5 m g and -3.0e-5, 2D and 3D alike; at k_n = 2e5 ten times less).  (Rolling
    needs ``f / N = 2 sin t / (17 cos t - 10)`` from rest, which diverges at the end:
    mu = 1000.  The compliant contact itself ends later, at zero overlap: cos t 0.5888 at
    k_n = 2e4, 0.5898 at 2e5, for 0.5916.)"""
    kn, v0 = 2e4, 0.02
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=RHO, kn=kn, friction=1e3, restitution=0.5))
    scene.add_box((0.0, 0.0, 0.0), HALF, R_BOX, m, blocked="x y z rx ry rz")
    edge = HALF[[0, 2]] - R_BOX  # the core edge (x, z) the ball rolls over
    ms = RHO * 4.0 / 3.0 * math.pi * R_BALL**3
    z0 = HALF[2] + R_BALL - ms * G / kn  # resting on the top face
    # on the flat at the start of the edge, rolling: omega_y = v / R
    scene.add_sphere((edge[0], 0.0, z0), R_BALL, m, velocity=(v0, 0.0, 0.0),
                     angular_velocity=(0.0, v0 / R_BALL, 0.0),
                     blocked=PLANAR if planar else "")  # fmt: skip
    sim = scene.build(safety=0.05)
    res = sim.run(until=0.15, trajectory_every=1, record_contact_forces=True)
    cf = res.contact_frames
    frame = np.repeat(np.arange(res.times.size), np.diff(cf.start))
    assert np.all(cf.second == 0) and np.all(cf.first == 1)  # ball 0, box = shape 1
    arm = res.positions[frame, 1][:, [0, 2]] - edge
    cos_t = arm[:, 1] / np.hypot(arm[:, 0], arm[:, 1])
    normal = (cf.force[:, [0, 2]] * arm).sum(axis=1) / np.hypot(arm[:, 0], arm[:, 1])
    weight = ms * G
    rho = R_BALL + R_BOX
    expected = weight * (17.0 * cos_t - 10.0 - 7.0 * v0**2 / (G * rho)) / 7.0
    # (past the first 10 degrees: the ball starts resting on the flat, its normal spring
    # then relaxes to the curved path's load with a transient of ~1 % of m g)
    on_edge = (cos_t < math.cos(math.radians(10.0))) & (normal > 0.1 * weight)
    assert on_edge.sum() > 100 and cos_t[on_edge].min() < 0.64
    np.testing.assert_allclose(normal[on_edge], expected[on_edge], atol=3e-4 * weight)
    slope, intercept = np.polyfit(cos_t[on_edge], normal[on_edge], 1)
    cos_theory = (10.0 + 7.0 * v0**2 / (G * rho)) / 17.0
    assert -intercept / slope == pytest.approx(cos_theory, abs=3e-4)


@pytest.mark.parametrize("planar", [False, True])
def test_box_sphere_candidates_do_not_change_the_trajectory(planar):
    """The neighbour list of box-sphere pairs (box_sphere.build_box_sphere_candidates)
    holds only the pairs near each box, and a run with a small skin (many builds) has
    the trajectory of one whose skin lists every pair, bit for bit."""
    small = _oblique(planar, 0.5, skin=2e-4, balls=6)
    large = _oblique(planar, 0.5, skin=10.0, balls=6)
    a = small.run(n_steps=20_000, trajectory_every=1000)
    b = large.run(n_steps=20_000, trajectory_every=1000)
    assert large.boxes.n_sphere_cand[0] == 6
    assert 0 <= small.boxes.n_sphere_cand[0] < 6
    assert small.rec.n_rebuilds[0] > 3 * large.rec.n_rebuilds[0]
    np.testing.assert_array_equal(a.positions, b.positions)
    np.testing.assert_array_equal(a.angular_velocities, b.angular_velocities)
    np.testing.assert_array_equal(small.boxes.rows.shear, large.boxes.rows.shear)


def test_validate_recorded_ball_box_forces_give_the_momentum_change():
    """Recorded every step (contact-force recorder), the force on the ball summed times dt
    equals its momentum change (a frictionless head-on impact, e = 1: to the end impulse
    of the linear law, which is not a row; 1e-4, measured -5.9e-6); the rows name the box as shape
    ``n_spheres + 0`` and the ball as sphere 0; the peak normal force of the pair is the
    largest recorded force."""
    sim = _head_on(False, 1.0, peak=True)
    ms = sim.bodies.mass[1]
    v0 = sim.bodies.vel_full[1].copy()
    res = sim.run(until=0.02, trajectory_every=1, record_contact_forces=True)
    cf = res.contact_frames
    assert cf.first.size > 100
    assert np.all(cf.first == 1) and np.all(cf.second == 0)
    impulse = cf.force.sum(axis=0) * sim.dt
    dp = ms * (sim.bodies.vel_full[1] - v0)
    np.testing.assert_allclose(impulse, dp, rtol=1e-4, atol=1e-12)
    peak = sim.pairs.peak_normal_force[0, 1]
    assert peak == pytest.approx(np.linalg.norm(cf.force, axis=1).max(), rel=1e-12)


# ----------------------------------------------------------------------- time step
def _ball_and_box(k_box, k_ball, tau_box, tau_ball, box_density, fixed, gravity=0.0, lift=0.0):
    """A ball of material (k_ball, kt_ratio tau_ball) resting on the middle of the top face
    of a box of (k_box, tau_box) and density ``box_density`` (a uniform cuboid);
    ``fixed``: the box cannot move and the ball moves only along z; ``lift`` [m] the
    ball's height above the equilibrium of its overlap under ``gravity``."""
    scene = Scene(gravity=(0.0, 0.0, -gravity))
    box_mat = scene.add_material(Material(density=box_density, kn=k_box, kt_ratio=tau_box))
    ball_mat = scene.add_material(Material(density=RHO, kn=k_ball, kt_ratio=tau_ball))
    ball_mass = RHO * 4.0 / 3.0 * math.pi * R_BALL**3
    k = 2.0 * k_box * k_ball / (k_box + k_ball)  # (the pair's k_n: RULE_GIVEN)
    sink = ball_mass * gravity / k
    scene.add_box((0.0, 0.0, 0.0), HALF, R_BOX, box_mat,
                  blocked="x y z rx ry rz" if fixed else "")  # fmt: skip
    scene.add_sphere((0.0, 0.0, HALF[2] + R_BALL - sink + lift), R_BALL, ball_mat,
                     blocked="x y rx ry rz" if fixed else "")  # fmt: skip
    return scene, ball_mass, k, sink


def test_validate_time_step_estimate_of_a_ball_on_a_box_is_the_pair_closed_form():
    """A light ball of a soft material on a heavier box of a stiff one: the estimate is
    ``1/omega`` of the pair, ``omega^2 = max(k_n (w_x + 1/m), k_t (w_x + 3.5/m))`` with the
    box's bound ``w_x = 1/M + (|h| + r)^2 / I_min`` and the ball's inverse effective
    mass along the normal (``1/m``: no lever arm) and across it (``1/m + R^2/I``); it is
    smaller than the estimate of the ball alone and of the box alone, so that it would
    not hold if the box-sphere contact were left out."""
    k_box, k_ball, tau_box, tau_ball, box_density = 2e5, 2e4, 0.5, 1.0, 5.0 * RHO
    scene, m, kn, _ = _ball_and_box(k_box, k_ball, tau_box, tau_ball, box_density, fixed=False)
    box_mass = 8.0 * HALF.prod() * box_density
    kt = 2.0 * (tau_box * k_box) * (tau_ball * k_ball) / (tau_box * k_box + tau_ball * k_ball)
    outer = HALF  # (the uniform cuboid's principal moments, the smallest: about z)
    i_min = box_mass * (outer[0] ** 2 + outer[1] ** 2) / 3.0
    w_box = 1.0 / box_mass + (np.linalg.norm(HALF - R_BOX) + R_BOX) ** 2 / i_min
    omega2 = max(kn * (w_box + 1.0 / m), kt * (w_box + 3.5 / m))
    dt = scene.build().critical_dt
    assert dt == pytest.approx(1.0 / math.sqrt(omega2), rel=1e-12)

    ball_alone, box_alone = Scene(), Scene()
    for alone, k, tau, rho in ((ball_alone, k_ball, tau_ball, RHO),
                               (box_alone, k_box, tau_box, box_density)):  # fmt: skip
        mat = alone.add_material(Material(density=rho, kn=k, kt_ratio=tau))
        if alone is ball_alone:
            alone.add_sphere((0.0, 0.0, 0.0), R_BALL, mat)
        else:
            alone.add_box((0.0, 0.0, 0.0), HALF, R_BOX, mat)
    assert dt < 0.8 * min(ball_alone.build().critical_dt, box_alone.build().critical_dt)


def _oscillation(factor):
    """Largest excursion [m] of a ball (moving along z only) resting by gravity on a
    fixed box, started ``sink / 10`` above its equilibrium, over 300 steps of ``factor``
    times the leapfrog limit ``2 dt_crit`` of the estimate, relative to its overlap at
    rest ``sink``; inf if the run aborts (energy runaway)."""
    _, _, _, sink = _ball_and_box(2e5, 2e4, 0.0, 0.0, 100.0 * RHO, fixed=True, gravity=G)
    scene, _, _, _ = _ball_and_box(2e5, 2e4, 0.0, 0.0, 100.0 * RHO, fixed=True, gravity=G,
                                   lift=0.1 * sink)  # fmt: skip
    sim = scene.build()
    sim.settings = sim.settings._replace(dt=factor * 2.0 * sim.critical_dt)
    z_rest = HALF[2] + R_BALL - sink
    largest = 0.0
    try:
        for _ in range(300):
            sim.run(n_steps=1)
            largest = max(largest, abs(sim.bodies.pos[1, 2] - z_rest))
    except RuntimeError:
        return math.inf
    return largest / sink


def test_validate_box_sphere_contact_is_stable_below_the_estimate_and_not_above():
    """Leapfrog is stable for ``omega dt < 2``; for a ball (1/3600 of the box's mass, no
    tangential spring) on a fixed box the estimate is the pair's ``omega`` to 2e-4, so the
    ball's oscillation on the box stays bounded at 0.9 x the limit ``2 dt_crit`` and
    runs away at 1.1 x.  An estimate without the box-sphere contact is 1.35 times longer
    (the ball's own contact stiffness being 1.8 times softer than the pair's): the run at
    0.9 x its limit would run away."""
    assert _oscillation(0.9) < 0.5
    assert _oscillation(1.1) > 10.0


def _box_on_a_bed(n_side, gravity=0.0, lift=0.0):
    """A light box lying on an ``n_side`` x ``n_side`` bed of heavy fixed balls (radius
    0.4 mm, 1.2 mm apart: no ball touches another) under the middle of its bottom face,
    moving along z only, ``lift`` [m] above its rest under ``gravity``; returns the scene,
    the box's mass and the pair's k_n."""
    radius, spacing, k = 0.0004, 0.0012, 2e4
    scene = Scene(gravity=(0.0, 0.0, -gravity))
    heavy = scene.add_material(Material(density=1e6 * RHO, kn=k, kt_ratio=0.5))
    light = scene.add_material(Material(density=RHO / 10.0, kn=k, kt_ratio=0.5))
    offsets = (np.arange(n_side) - 0.5 * (n_side - 1)) * spacing
    for x in offsets:
        for y in offsets:
            scene.add_sphere((x, y, 0.0), radius, heavy, blocked="x y z rx ry rz")
    mass = 8.0 * HALF.prod() * RHO / 10.0
    sink = mass * gravity / (n_side**2 * k)
    scene.add_box((0.0, 0.0, radius + HALF[2] - sink + lift), HALF, R_BOX, light,
                  blocked="x y rx ry rz")  # fmt: skip
    return scene, mass, k


def test_validate_time_step_estimate_covers_a_box_on_a_bed_of_spheres(monkeypatch):
    """A light box resting by gravity on N = 144 heavy fixed balls vibrates along z at
    ``omega^2 = N k_n / M``.  Leapfrog is stable for ``omega dt < 2``; the estimate gives
    ``omega dt = sqrt(2)`` (the module's Gershgorin bound, ``omega^2 <= K_x / M`` taken
    at half, as for spheres) because the box-sphere contacts at start enter the box's
    sum, and a run at the estimate, started 0.1 um above rest, stays within that.
    Without them the estimate (four corners of the box, ``4 k_n / M``) gives ``omega dt
    = 6``: the run would blow up."""
    scene, mass, k = _box_on_a_bed(12, gravity=G)
    omega = math.sqrt(144 * k / mass)
    assert omega * scene.build().critical_dt == pytest.approx(math.sqrt(2.0), rel=1e-9)
    monkeypatch.setattr(timestep, "_touching_box_spheres", lambda *args: [])
    assert omega * scene.build().critical_dt == pytest.approx(6.0, rel=1e-9)
    monkeypatch.undo()

    scene, _, _ = _box_on_a_bed(12, gravity=G, lift=1e-7)
    sim = scene.build()
    rest = sim.bodies.pos[-1, 2] - 1e-7
    largest = 0.0
    for _ in range(20):
        sim.run(n_steps=50)
        largest = max(largest, abs(sim.bodies.pos[-1, 2] - rest))
    assert largest < 1.5e-7


def test_boxes_that_do_not_know_the_scene_s_spheres_are_refused():
    """The box rows name a sphere partner ``j = n_boxes + s`` and find its body in
    ``Boxes.partner_body``: box arrays built without the scene's spheres are refused in
    one line, not read past their end."""
    sim = _oblique(False, 0.5)
    s = sim.settings
    names = ("gravity", "dt", "damping", "damp_gravity", "skin", "record_pairs",
             "record_peak_force", "check_every", "track_energy", "sleep_speed",
             "sleep_time")  # fmt: skip
    x = sim.boxes
    boxes = empty_boxes(x.body, x.half, x.radius, x.material)  # (sphere_body not given)
    with pytest.raises(ValueError, match=r"1 boxes and 1 spheres need 2 \(dem\.boxes\.empty"):
        Simulation(sim.bodies, sim.spheres, sim.walls, sim.mats, critical_dt=sim.critical_dt,
                   boxes=boxes, **{k: getattr(s, k) for k in names})  # fmt: skip
