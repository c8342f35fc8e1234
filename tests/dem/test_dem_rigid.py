"""Validation of rigid-body dynamics: clump mass properties, free rotation, pivoting,
inclined plane, local damping, blocked degrees of freedom."""

import numpy as np
import pytest
from dem_scenes import RHO, R, column, sphere_mass, tilt_of

from dominowave.dem import Material, Scene, clump_mass_properties
from dominowave.dem.integrate import kick
from reference.rigid_body import free_rotation, quaternion_matrix
from reference.rolling_column import rolling_column_friction_ratio, rolling_column_time

G = 9.81


def test_validate_clump_mass_and_inertia():
    """Two spheres at +-a on x: m = 2 m_s, I_x = 4/5 m_s R^2,
    I_y = I_z = 2 (2/5 m_s R^2 + m_s a^2)."""
    a = 0.02
    mass, com, moments, axes, _ = clump_mass_properties([[-a, 1, 2], [a, 1, 2]], [R, R], [RHO, RHO])
    ms = sphere_mass()
    assert mass == pytest.approx(2 * ms, rel=1e-14)
    np.testing.assert_allclose(com, [0, 1, 2], atol=1e-15)
    np.testing.assert_allclose(
        moments,
        [0.8 * ms * R**2, 2 * (0.4 * ms * R**2 + ms * a**2), 2 * (0.4 * ms * R**2 + ms * a**2)],
        rtol=1e-12,
    )
    assert abs(axes[0, 0]) == pytest.approx(1.0, abs=1e-12)
    assert np.linalg.det(axes) == pytest.approx(1.0, abs=1e-12)


def test_validate_clump_inertia_against_monte_carlo_free_orientation():
    """An asymmetric clump: the tensor equals sum of sphere tensors (checked by rotating)."""
    rng = np.random.default_rng(1)
    centres = rng.normal(size=(5, 3)) * 0.01
    radii = rng.uniform(0.002, 0.004, 5)
    dens = rng.uniform(500, 2000, 5)
    _, _, moments, axes, tensor = clump_mass_properties(centres, radii, dens)
    # the eigen decomposition reproduces the tensor; rotating the clump rotates the tensor
    np.testing.assert_allclose(axes @ np.diag(moments) @ axes.T, tensor, rtol=1e-12, atol=1e-20)
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    _, _, moments_rot, _, tensor_rot = clump_mass_properties(centres @ Q.T, radii, dens)
    np.testing.assert_allclose(tensor_rot, Q @ tensor @ Q.T, rtol=1e-10, atol=1e-20)
    np.testing.assert_allclose(moments_rot, moments, rtol=1e-10)


@pytest.mark.parametrize("x", [0.0, 0.02, 0.06, 0.37, 12.5])
def test_validate_a_column_keeps_the_world_axes_as_principal_axes(x):
    """A column of spheres along z (two equal moments, the DEM domino) has the world axes
    as principal axes wherever it stands: the frame must not depend on the round-off of
    its position (LAPACK may rotate the basis of a degenerate pair by any angle)."""
    centres = column(6, base=(x, 0.001, R))
    _, _, moments, axes, tensor = clump_mass_properties(centres, [R] * 6, [RHO] * 6)
    assert set(np.unique(np.abs(axes))) <= {0.0, 1.0}
    np.testing.assert_allclose(axes @ np.diag(moments) @ axes.T, tensor, rtol=1e-12, atol=0)


def _racket_scene():
    scene = Scene(gravity=(0, 0, 0))
    m = scene.add_material(Material(density=RHO, kn=1e4))
    centres = [[0, 0, 0], [0.03, 0, 0], [0, 0.015, 0.0]]
    scene.add_clump(centres, [0.006, 0.004, 0.003], m)
    return scene


def test_validate_tennis_racket_free_rotation():
    """Free asymmetric top spun near its intermediate axis: L and E conserved, body-frame
    omega(t) follows Euler's equations (scipy), including the flip."""
    scene = _racket_scene()
    sim = scene.build(dt=2e-5)
    b = sim.bodies
    I = b.inertia[0].copy()
    assert I[0] < I[1] < I[2]
    w_body0 = np.array([1e-3, 10.0, 1e-3])
    sim.set_velocity(0, angular_velocity=b.rot[0] @ w_body0)
    L0 = b.angmom[0].copy()
    E0 = sim.energy()["kinetic_rotational"]
    t_end = 3.0
    res = sim.run(until=t_end, trajectory_every=50, energy_every=50)
    # body-frame angular velocity from the recorded quaternions
    w_body = np.array(
        [
            quaternion_matrix(q).T @ w
            for q, w in zip(res.quaternions[:, 0], res.angular_velocities[:, 0], strict=True)
        ]
    )
    ref = free_rotation(I, w_body0, res.times)  # Euler's equations by scipy
    assert np.min(w_body[:, 1]) < -9.0, "the racket flips"
    np.testing.assert_allclose(w_body, ref, atol=0.05)  # rad/s, of |omega| = 10
    np.testing.assert_allclose(b.angmom[0], L0, rtol=1e-12, atol=1e-18)
    # the largest energy error over the whole run, the flip included
    # (measured 4.9e-10: the splitting's bounded energy error, no drift)
    assert np.max(np.abs(res.energy["kinetic_rotational"] / E0 - 1)) < 1e-8
    assert np.max(np.abs(res.energy["total"] / E0 - 1)) < 1e-8


def test_validate_domino_pivot_fall_time():
    """A column of 10 spheres (planar, y rx rz blocked) on a frictional floor falls from
    0.05 rad to 1 rad in the time of the rigid column rolling without slip on its base
    sphere (energy quadrature, tests/reference/rolling_column.py)."""
    n, theta0, theta_end, mu, kn = 10, 0.05, 1.0, 1.0, 1e6
    scene = Scene(gravity=(0, 0, -G))
    floor = scene.add_material(Material(density=RHO, kn=kn, friction=mu, restitution=0.5))
    scene.add_wall((0, 0, 0), (0, 0, 1), floor)
    scene.add_clump(column(n, tilt=theta0), R, floor, blocked="y rx rz")
    sim = scene.build(safety=0.1)
    # the rigid column rolling on its base sphere, from the geometry alone
    upright = (np.full(n, sphere_mass()), column(n)[:, 2], np.full(n, R), R)
    t_ref = rolling_column_time(*upright, 0.0, theta_end, G, theta0=theta0)
    ratio = rolling_column_friction_ratio(*upright, 0.0, theta_end, G, theta0=theta0)
    assert ratio < mu, "friction suffices for rolling without slip"
    res = sim.run(until=1.2 * t_ref, trajectory_every=20)
    theta = tilt_of(sim, res.quaternions[:, 0])
    k = np.flatnonzero(theta >= theta_end)[0]
    t_dem = np.interp(theta_end, theta[k - 1 : k + 1], res.times[k - 1 : k + 1])
    assert abs(t_dem / t_ref - 1) < 1e-2
    pytest.dem_pivot_error = t_dem / t_ref - 1  # reported by the benchmark note


@pytest.mark.parametrize(
    ("tan_theta", "slides", "block_mu"),
    [(0.3, False, 0.5), (0.45, False, 0.5), (0.55, True, 0.5), (0.8, True, 0.5), (0.55, True, 0.8)],
)
def test_validate_inclined_plane(tan_theta, slides, block_mu):
    """A flat 2x2 clump on a plane tilted by theta (gravity tilted instead), plane mu =
    0.5, block mu = block_mu: the pair uses min(mu_1, mu_2) = 0.5; the block sticks if
    tan(theta) < mu, else slides with a = g (sin theta - mu cos theta); the friction
    dissipation equals mu m g cos(theta) times the distance slid."""
    mu = 0.5
    th = np.arctan(tan_theta)
    scene = Scene(gravity=(G * np.sin(th), 0, -G * np.cos(th)))
    plane = scene.add_material(
        Material(density=RHO, kn=1e5, kt_ratio=1.0, friction=mu, restitution=0.2)
    )
    block = scene.add_material(
        Material(density=RHO, kn=1e5, kt_ratio=1.0, friction=block_mu, restitution=0.2)
    )
    scene.add_wall((0, 0, 0), (0, 0, 1), plane)
    d = 2 * R
    centres = [[0, 0, R], [d, 0, R], [0, d, R], [d, d, R]]
    scene.add_clump(centres, R, block)
    sim = scene.build(safety=0.1)
    res = sim.run(until=0.3, trajectory_every=20)
    x = res.positions[:, 0, 0] - res.positions[0, 0, 0]
    late = res.times > 0.05
    a_fit = np.polyfit(res.times[late], x[late], 2)[0] * 2
    if slides:
        a_ref = G * (np.sin(th) - mu * np.cos(th))
        assert a_fit == pytest.approx(a_ref, rel=2e-3)
        m = sim.bodies.mass[0]
        expected = mu * m * G * np.cos(th) * x[-1]  # (the elastic shear, < 1e-6 m, neglected)
        assert sim.energy()["dissipated_friction"] == pytest.approx(expected, rel=5e-3)
    else:
        assert abs(x[-1]) < 1e-5  # only the elastic shear of the contacts (~1e-6 m)
        assert abs(res.velocities[-1, 0, 0]) < 1e-3


@pytest.mark.parametrize("damp_gravity", [True, False])
def test_validate_local_damping_free_fall(damp_gravity):
    """YADE local damping: free fall accelerates at g (1 - lambda) with gravity damped,
    at g without; a rising body decelerates at g (1 + lambda)."""
    lam = 0.3
    scene = Scene(gravity=(0, 0, -G))
    m = scene.add_material(Material(density=RHO, kn=1e4))
    scene.add_sphere((0, 0, 0), R, m)
    scene.add_sphere((1, 0, 0), R, m, velocity=(0, 0, 5.0))
    sim = scene.build(dt=1e-4, damping=lam, damp_gravity=damp_gravity)
    e0 = sim.energy()["total"]
    res = sim.run(n_steps=2000, trajectory_every=10)
    early = res.times < 0.15  # body 1 is still rising
    a_fall = np.polyfit(res.times, res.velocities[:, 0, 2], 1)[0]
    a_rise = np.polyfit(res.times[early], res.velocities[early, 1, 2], 1)[0]
    if damp_gravity:
        assert a_fall == pytest.approx(-G * (1 - lam), rel=1e-10)
        assert a_rise == pytest.approx(-G * (1 + lam), rel=1e-10)
    else:
        assert a_fall == pytest.approx(-G, rel=1e-10)
        assert a_rise == pytest.approx(-G, rel=1e-10)
    # the ledger books the work of the damping forces: the total stays constant
    e = sim.energy()
    scale = 0.5 * sim.bodies.mass[1] * 25.0
    assert (e["dissipated_damping"] > 0.01 * scale) == damp_gravity
    assert abs(e["total"] - e0) < 1e-9 * scale


def test_validate_blocked_dofs_stay_zero():
    """Planar columns (y rx rz blocked) pushed into each other under a gravity with a y
    component: y, omega_x, omega_z stay exactly at their initial values."""
    scene = Scene(gravity=(0.0, 3.0, -G))
    floor = scene.add_material(Material(density=RHO, kn=1e5, friction=0.3))
    mat = scene.add_material(Material(density=RHO, kn=1e5, friction=0.0))
    scene.add_wall((0, 0, 0), (0, 0, 1), floor)
    for k in range(4):
        mats = [floor] + [mat] * 5
        scene.add_clump(
            column(6, base=(k * 0.02, 0.001, R)),
            R,
            mats,
            blocked="y rx rz",
            angular_velocity=(0, 8.0 if k == 0 else 0.0, 0),
        )
    scene.add_sphere((0.1, 0.0, 0.02), R, mat, blocked="x y", velocity=(0, 0, -0.1))
    sim = scene.build(safety=0.1)
    y0 = sim.positions()[:, 1]
    sphere_y0 = sim.sphere_positions()[:, 1]
    res = sim.run(until=0.4, trajectory_every=20)
    assert res.events.time.size > 4
    assert np.ptp(res.positions[:, 0, 0]) > 0.01, "the pushed column moved"
    np.testing.assert_array_equal(
        res.positions[:, :, 1], np.broadcast_to(y0, res.positions[:, :, 1].shape)
    )
    np.testing.assert_array_equal(res.angular_velocities[:, :4, 0], 0.0)
    np.testing.assert_array_equal(res.angular_velocities[:, :4, 2], 0.0)
    np.testing.assert_array_equal(res.positions[:, 4, 0], 0.1)
    np.testing.assert_array_equal(sim.sphere_positions()[:, 1], sphere_y0)


def test_validate_blocked_rotation_of_a_sphere_under_friction_torque():
    """Spheres sliding on a frictional floor with only 'ry' blocked: the friction torque
    would make them roll; omega_y stays exactly 0, so they slide with the Coulomb
    deceleration mu g until they stop (a free sphere ends rolling at 5/7 v0)."""
    mu, v0 = 0.4, 0.2
    scene = Scene(gravity=(0, 0, -G))
    m = scene.add_material(Material(density=RHO, kn=1e5, friction=mu, restitution=0.3))
    scene.add_wall((0, 0, 0), (0, 0, 1), m)
    sink = G * sphere_mass() / 1e5
    blocked = scene.add_sphere((0, 0, R - sink), R, m, velocity=(v0, 0, 0), blocked="ry")
    free = scene.add_sphere((0, 0.1, R - sink), R, m, velocity=(v0, 0, 0))
    sim = scene.build(safety=0.1, overlap_tolerance=0.1)
    res = sim.run(until=0.03, trajectory_every=20)
    np.testing.assert_array_equal(res.angular_velocities[:, blocked, 1], 0.0)
    assert np.max(np.abs(res.angular_velocities[:, free, 1])) > 1.0  # the torque is real
    sliding = (res.times > 0.002) & (res.times < 0.02)
    a_fit = np.polyfit(res.times[sliding], res.velocities[sliding, blocked, 0], 1)[0]
    assert a_fit == pytest.approx(-mu * G, rel=2e-3)


def test_validate_rotational_local_damping():
    """YADE local damping of rotations, against the formulas applied by hand to one kick:
    spheres and planar clumps damp each angular acceleration component with the
    second-order sign (alpha_i (omega_i + dt alpha_i / 2)); free aspherical clumps each
    torque component with sign(T_i omega_i) (YADE's first-order form for aspherical
    bodies)."""
    lam = 0.3
    scene = Scene(gravity=(0, 0, 0))
    m = scene.add_material(Material(density=RHO, kn=1e4))
    sphere = scene.add_sphere((0, 0, 0), R, m, angular_velocity=(0.0, 2.0, -1.0))
    planar = scene.add_clump(column(3, base=(0.1, 0, 0)), R, m, blocked="x rx rz")
    free = scene.add_clump([[0.2, 0, 0], [0.23, 0, 0], [0.2, 0.015, 0]], [0.006, 0.004, 0.003], m)
    sim = scene.build(safety=0.5, damping=lam)
    dt = sim.dt
    sim.set_velocity(planar, angular_velocity=(0, -3.0, 0))
    sim.set_velocity(free, angular_velocity=(1.0, -2.0, 0.5))
    sim.run(n_steps=1)  # leave the velocity-Verlet start: omega now at a half step
    b = sim.bodies
    torque = np.array([[1e-6, -2e-6, -3e-6], [0, 4e-6, 0], [2e-6, 1e-6, -5e-6]])
    w_old = b.omega.copy()
    L_old = b.angmom.copy()
    b.torque[:] = torque
    kick(b, np.zeros(3), dt, lam, True)
    # sphere: I alpha = T component-wise
    alpha = torque[sphere] / b.inertia[sphere, 0]
    expected = w_old[sphere] + dt * alpha * (
        1 - lam * np.sign(alpha * (w_old[sphere] + 0.5 * dt * alpha))
    )
    np.testing.assert_allclose(b.omega[sphere], expected, rtol=1e-14)
    # planar clump: rotation about y only, I_y from the geometry
    ms = sphere_mass()
    I_y = 3 * 0.4 * ms * R**2 + 2 * ms * (2 * R) ** 2
    alpha = torque[planar, 1] / I_y
    w = w_old[planar, 1]
    expected = w + dt * alpha * (1 - lam * np.sign(alpha * (w + 0.5 * dt * alpha)))
    assert b.omega[planar, 1] == pytest.approx(expected, rel=1e-12)
    # free clump: the angular momentum receives the damped torque
    T = torque[free]
    expected = L_old[free] + dt * T * (1 - lam * np.sign(T * w_old[free]))
    np.testing.assert_allclose(b.angmom[free], expected, rtol=1e-13)
