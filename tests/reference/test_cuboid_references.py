"""The cuboid references checked themselves: mass properties against quadrature and
limits, motions against closed forms, limits and a second method."""

import math

import numpy as np
import pytest
from scipy.integrate import dblquad, solve_ivp
from scipy.special import ellipkinc, ellipkm1

from reference.box_distance import box_box_distance, box_point_distance, box_wall_distance
from reference.cuboid import (
    box_edge_inertia,
    box_mass_properties,
    rounded_box_mass_properties,
    rounded_rectangle_mass_properties,
)
from reference.edge_tipping import (
    edge_fall_by_newton,
    edge_fall_time,
    edge_reaction,
    edge_slip_tilt,
    first_contact_time,
)
from reference.incline import (
    incline_acceleration,
    incline_corner_forces,
    incline_motion,
    incline_regime,
)
from reference.resting_box import (
    resting_box_modes,
    resting_corner_load,
    stack_bounce_frequencies,
    stack_loads,
)
from reference.rigid_chain import ej_fall_time
from reference.rigid_impact import (
    Body,
    compliant_impact,
    dashpot_for_restitution,
    effective_mass,
    energy_loss,
    impulse_collision,
    normal_velocity,
)
from reference.rounded_tipping import (
    rounded_fall_by_lagrange,
    rounded_fall_time,
    rounded_first_contact_time,
    rounded_geometry,
)

G = 9.81
# a common domino: 48 x 24 x 7.5 mm, ABS-like density
L_DOM, W_DOM, S_DOM, RHO = 0.048, 0.024, 0.0075, 1050.0


# --- cuboid: mass properties ----------------------------------------------------------


def test_validate_box_mass_properties_closed_form():
    """The box moments are the textbook m (L_y^2 + L_z^2) / 12 with full extents, and
    the edge moment of a domino is m (l^2 + s^2) / 3 (a rod of length l for s -> 0)."""
    a, b, c = S_DOM / 2, W_DOM / 2, L_DOM / 2
    m, inertia = box_mass_properties(a, b, c, RHO)
    assert m == pytest.approx(RHO * L_DOM * W_DOM * S_DOM, rel=1e-15)
    expected = m / 12 * np.array([W_DOM**2 + L_DOM**2, L_DOM**2 + S_DOM**2, S_DOM**2 + W_DOM**2])
    np.testing.assert_allclose(inertia, expected, rtol=1e-14)
    assert box_edge_inertia(a, b, c, RHO) == pytest.approx(m * (L_DOM**2 + S_DOM**2) / 3, 1e-14)


def _rounded_box_by_quadrature(a, b, c, r):
    """Volume and second moments (S_x, S_y, S_z) of the rounded box by 2D quadrature over
    its footprint: at (x, y) it spans |z| <= c + sqrt(r^2 - dx^2 - dy^2) with dx, dy the
    distances beyond the core's faces; the footprint splits into four smooth pieces."""

    def half_height(y, x):
        dx, dy = max(abs(x) - a, 0.0), max(abs(y) - b, 0.0)
        return c + math.sqrt(max(r * r - dx * dx - dy * dy, 0.0))

    def integral(weight):
        total = 0.0
        pieces = (  # x range, y upper limit as a function of x
            ((0.0, a), lambda x: b),
            ((0.0, a), lambda x: b + r),
            ((a, a + r), lambda x: b),
            ((a, a + r), lambda x: b + math.sqrt(max(r * r - (x - a) ** 2, 0.0))),
        )
        lower = (lambda x: 0.0, lambda x: b, lambda x: 0.0, lambda x: b)
        for ((x0, x1), upper), low in zip(pieces, lower, strict=True):
            value, _ = dblquad(
                lambda y, x: weight(x, y, half_height(y, x)),
                x0,
                x1,
                low,
                upper,
                epsabs=0.0,
                epsrel=1e-12,
            )
            total += 4.0 * value  # four quadrants
        return total

    volume = integral(lambda x, y, h: 2.0 * h)
    s_x = integral(lambda x, y, h: 2.0 * h * x * x)
    s_y = integral(lambda x, y, h: 2.0 * h * y * y)
    s_z = integral(lambda x, y, h: 2.0 * h**3 / 3.0)
    return volume, np.array([s_x, s_y, s_z])


@pytest.mark.parametrize(
    ("a", "b", "c", "r"),
    [(0.003, 0.011, 0.023, 0.00075), (0.2, 0.5, 0.9, 0.3), (0.0, 0.4, 0.7, 0.5)],
)
def test_validate_rounded_box_equals_quadrature(a, b, c, r):
    """The piece-wise volume and moments of the rounded box against an independent 2D
    quadrature of its height over its footprint (measured agreement <= 4e-16)."""
    volume, mass, inertia = rounded_box_mass_properties(a, b, c, r, RHO)
    v_quad, s = _rounded_box_by_quadrature(a, b, c, r)
    assert volume == pytest.approx(v_quad, rel=1e-10)
    assert mass == pytest.approx(RHO * v_quad, rel=1e-10)
    expected = RHO * np.array([s[1] + s[2], s[2] + s[0], s[0] + s[1]])
    np.testing.assert_allclose(inertia, expected, rtol=1e-10)


def test_validate_rounded_box_limits():
    """r = 0 is the box; a = b = c = 0 is the ball (2/5 m r^2); a = b = 0 a capsule
    (cylinder 2c plus a ball); r -> 0 converges to the box linearly in r."""
    a, b, c = 0.3, 0.5, 0.7
    volume, m, inertia = rounded_box_mass_properties(a, b, c, 0.0, RHO)
    m_box, i_box = box_mass_properties(a, b, c, RHO)
    assert m == pytest.approx(m_box, rel=1e-15)
    assert volume == pytest.approx(8 * a * b * c, rel=1e-15)
    np.testing.assert_allclose(inertia, i_box, rtol=1e-14)
    r = 0.2
    _, m_ball, i_ball = rounded_box_mass_properties(0.0, 0.0, 0.0, r, RHO)
    assert m_ball == pytest.approx(RHO * 4 / 3 * math.pi * r**3, rel=1e-15)
    np.testing.assert_allclose(i_ball, 0.4 * m_ball * r * r, rtol=1e-14)
    # capsule: cylinder (r, length 2c) + ball, the halves of the ball at +-c along z
    _, m_cap, i_cap = rounded_box_mass_properties(0.0, 0.0, c, r, RHO)
    m_cyl = RHO * math.pi * r * r * 2 * c
    i_axis = m_cyl * r * r / 2 + 0.4 * m_ball * r * r
    hemi = 0.4 * m_ball * r * r + m_ball * (c * c + 2 * c * 3 * r / 8)  # Steiner, both halves
    i_across = m_cyl * (r * r / 4 + c * c / 3) + hemi
    assert m_cap == pytest.approx(m_cyl + m_ball, rel=1e-15)
    np.testing.assert_allclose(i_cap, [i_across, i_across, i_axis], rtol=1e-14)
    errors = [
        abs(rounded_box_mass_properties(a, b, c, r, RHO)[2][0] / i_box[0] - 1) for r in (1e-4, 1e-5)
    ]
    assert errors[0] / errors[1] == pytest.approx(10, rel=1e-3)


def test_validate_rounded_rectangle_is_a_wide_rounded_box():
    """Per unit width, a rounded box of huge width b (only its middle counts) is the
    planar rounded rectangle: area and polar moment agree to O(r / b)."""
    a, c, r, b = 0.003, 0.023, 0.001, 1e3
    volume, m3, i3 = rounded_box_mass_properties(a, b, c, r, RHO)
    area, m2, i2 = rounded_rectangle_mass_properties(a, c, r, RHO)
    assert volume / (2 * b) == pytest.approx(area, rel=1e-5)
    assert m3 / (2 * b) == pytest.approx(m2, rel=1e-5)
    assert i3[1] / (2 * b) == pytest.approx(i2, rel=1e-5)
    # r = 0: the rectangle's polar moment m (L_x^2 + L_z^2) / 12
    _, m0, i0 = rounded_rectangle_mass_properties(a, c, 0.0, RHO)
    assert i0 == pytest.approx(m0 * ((2 * a) ** 2 + (2 * c) ** 2) / 12, rel=1e-14)


# --- incline --------------------------------------------------------------------------


@pytest.mark.parametrize(("t", "mu", "v0"), [(0.5, 0.3, 0.0), (0.5, 0.3, 0.2), (0.3, 0.5, 0.4)])
def test_validate_incline_motion_equals_newton(t, mu, v0):
    """Sliding and stopping against Newton's law with Coulomb friction (kinetic while
    v > 0, the stop located by an event, then sticking), solve_ivp DOP853."""
    a = G * (math.sin(t) - mu * math.cos(t))

    def stop(_t, y):
        return y[1]

    stop.terminal, stop.direction = True, -1
    times = np.linspace(0.0, 1.0, 11)
    sol = solve_ivp(
        lambda _t, y: [y[1], a],
        (0, 1.0),
        [0.0, v0],
        method="DOP853",
        rtol=1e-13,
        atol=1e-15,
        events=stop,
        dense_output=True,
    )
    t_end = sol.t[-1]
    x_ode = np.where(times <= t_end, sol.sol(np.minimum(times, t_end))[0], sol.y[0][-1])
    x, v = incline_motion(t, mu, v0, times, G)
    np.testing.assert_allclose(x, x_ode, rtol=1e-11, atol=1e-15)
    assert np.all(v >= 0)
    if math.tan(t) > mu:
        assert incline_acceleration(t, mu, G) == pytest.approx(a, rel=1e-15)
    else:
        assert incline_acceleration(t, mu, G) == 0.0
        assert v[-1] == 0.0


def test_validate_incline_regimes_from_corner_forces():
    """The regime boundaries are where a corner force of the two-point statics vanishes
    (tipping) or the friction needed reaches mu N (sliding); the forces balance the
    block's weight and its moment about G (cross products)."""
    s, h, m = S_DOM, L_DOM / 2, 0.009
    lever = s / (2 * h)
    for mu, t, regime in (
        (0.5, 0.9 * math.atan(lever), "rest"),
        (0.5, 1.01 * math.atan(lever), "tip"),
        (0.1, 1.01 * math.atan(0.1), "slide"),
        (0.1, 0.99 * math.atan(0.1), "rest"),
        (0.1, 1.5, "slide"),
    ):
        assert incline_regime(t, mu, s, h) == regime
        if regime == "tip":
            with pytest.raises(ValueError, match="tips"):
                incline_corner_forces(t, mu, s, h, m, G)
            continue
        down, up, friction = incline_corner_forces(t, mu, s, h, m, G)
        # slope frame: x downhill, z normal; G at (0, h); weight (m g sin t, -m g cos t)
        forces = np.array([[0.0, down], [0.0, up], [-friction, 0.0], [-friction, 0.0]])
        forces[2:] *= 0.5  # the friction split between the corners: no moment difference
        points = np.array([[s / 2, 0.0], [-s / 2, 0.0], [s / 2, 0.0], [-s / 2, 0.0]])
        weight = m * G * np.array([math.sin(t), -math.cos(t)])
        assert np.allclose(forces.sum(0) + weight, 0, atol=1e-15) == (regime == "rest")
        arm = points - np.array([0.0, h])
        torque = np.sum(arm[:, 0] * forces[:, 1] - arm[:, 1] * forces[:, 0])
        assert torque == pytest.approx(0.0, abs=1e-16)
    # the tipping boundary: the uphill corner unloads at tan t = s / 2h
    _, up, _ = incline_corner_forces(math.atan(lever) * (1 - 1e-12), 0.5, s, h, m, G)
    assert up == pytest.approx(0.0, abs=1e-12 * m * G)


# --- edge_tipping ---------------------------------------------------------------------


def _inverted_pendulum_time(kappa, phi0, phi1):
    """Closed form: from rest at phi0 > 0, phi'' = kappa^2 sin(phi) reaches phi1 at
    t = (F(pi/2, k) - F(u, k)) / kappa, k = cos(phi0 / 2), sin u = cos(phi1/2) / k (the
    ordinary pendulum psi = pi - phi from its amplitude psi0 = pi - phi0)."""
    m = math.cos(phi0 / 2) ** 2
    u = math.asin(math.cos(phi1 / 2) / math.cos(phi0 / 2))
    return (ellipkm1(math.sin(phi0 / 2) ** 2) - ellipkinc(u, m)) / kappa


@pytest.mark.parametrize(("s", "dtheta0"), [(S_DOM, 0.05), (S_DOM, 0.3), (0.02, 0.1)])
def test_validate_edge_fall_from_rest_three_methods(s, dtheta0):
    """A box released at rest just beyond its balance tilt atan(s/l) lands flat: energy
    quadrature, Newton's law (DOP853, rtol 1e-12) and the elliptic-integral closed form of
    the inverted pendulum agree to 1e-10 (measured: quadrature 2e-16, DOP853 2e-13)."""
    alpha = math.atan(s / L_DOM)
    theta0 = alpha + dtheta0
    t_quad = edge_fall_time(L_DOM, s, theta0, 0.0, math.pi / 2, G)
    t_ode, omega_land = edge_fall_by_newton(L_DOM, s, theta0, 0.0, math.pi / 2, G)
    rho = math.hypot(L_DOM, s) / 2
    t_exact = _inverted_pendulum_time(math.sqrt(3 * G / (4 * rho)), dtheta0, math.pi / 2 - alpha)
    assert t_quad == pytest.approx(t_exact, rel=1e-10)
    assert t_ode == pytest.approx(t_exact, rel=1e-10)
    # energy on landing: (1/2) I w^2 = m g (height lost by G)
    drop = rho * (math.cos(dtheta0) - math.cos(math.pi / 2 - alpha))
    assert 0.5 * (4 / 3) * rho**2 * omega_land**2 == pytest.approx(G * drop, rel=1e-10)


def test_validate_edge_fall_small_tilt_limit():
    """Released a hair beyond balance: phi'' = kappa^2 phi gives t = acosh(phi1/phi0) /
    kappa, the correction O(phi1^2) (100-fold smaller for 10-fold smaller angles)."""
    rho = math.hypot(L_DOM, S_DOM) / 2
    kappa, alpha = math.sqrt(3 * G / (4 * rho)), math.atan(S_DOM / L_DOM)
    errors = []
    for phi0, phi1 in ((1e-4, 1e-2), (1e-5, 1e-3)):
        t = edge_fall_time(L_DOM, S_DOM, alpha + phi0, 0.0, alpha + phi1, G)
        errors.append(t * kappa / math.acosh(phi1 / phi0) - 1)
    assert errors[0] / errors[1] == pytest.approx(100, rel=1e-3)


def test_validate_edge_fall_thin_box_is_a_rod():
    """s -> 0: a pushed uniform rod obeys the EJ law with l_eff = 2 l / 3 (theta'' =
    (3 g / 2 l) sin theta), so the first contact time is EJ's fall time (eq 11)."""
    omega, d = 5.0, 0.3 * L_DOM
    t, tilt = first_contact_time(L_DOM, 0.0, d, omega, G)
    assert tilt == pytest.approx(math.asin(0.3), rel=1e-15)
    assert t == pytest.approx(ej_fall_time(omega, tilt, 2 * L_DOM / 3, G), rel=1e-11)


def _first_touch_by_geometry(l, s, d, omega, g):
    """Newton's law (T) with the contact found by geometry: the event is the largest
    forward x of domino 0's four corners reaching domino 1's back face x = d."""
    rho, alpha = math.hypot(l, s) / 2, math.atan2(s, l)
    corners = np.array([[0.0, 0.0], [0.0, l], [-s, l], [-s, 0.0]])

    def front(_t, y):
        c, si = math.cos(y[0]), math.sin(y[0])
        return max(corners[:, 0] * c + corners[:, 1] * si) - d

    front.terminal, front.direction = True, 1
    sol = solve_ivp(
        lambda _t, y: [y[1], 3 * g / (4 * rho) * math.sin(y[0] - alpha)],
        (0, 10.0),
        [0.0, omega],
        method="DOP853",
        rtol=1e-12,
        atol=1e-14,
        events=front,
    )
    return sol.t_events[0][0], sol.y_events[0][0][0]


@pytest.mark.parametrize(
    ("s", "d", "omega_scale"),
    [(S_DOM, 0.0094, 1.5), (S_DOM, 0.015, 3.0), (0.01, 0.03, 1.2), (0.002, 0.04, 10.0)],
)
def test_validate_first_contact_equals_newton_event(s, d, omega_scale):
    """Domino 0 pushed upright with omega about its front bottom edge: the quadrature time
    and the tilt asin(d/l) against Newton's law with a corner-geometry event (which finds
    the touching corner itself), measured <= 2.3e-11 (the ODE's error); omega a multiple of
    the push that just tips it over."""
    rho, alpha = math.hypot(L_DOM, s) / 2, math.atan(s / L_DOM)
    omega_min = math.sqrt(3 * G / (2 * rho) * (1 - math.cos(alpha)))
    omega = omega_scale * omega_min
    t, tilt = first_contact_time(L_DOM, s, d, omega, G)
    t_ode, tilt_ode = _first_touch_by_geometry(L_DOM, s, d, omega, G)
    assert tilt == pytest.approx(tilt_ode, rel=1e-10)
    assert t == pytest.approx(t_ode, rel=1e-10)
    assert t == pytest.approx(edge_fall_by_newton(L_DOM, s, 0.0, omega, tilt, G)[0], rel=1e-10)
    with pytest.raises(ValueError, match="omega0"):
        first_contact_time(L_DOM, s, d, 0.99 * omega_min, G)
    # a contact before the balance tilt needs only the push that gets it there
    d_near = 0.5 * L_DOM * math.sin(alpha)
    tilt_near = math.asin(d_near / L_DOM)
    omega_near = math.sqrt(3 * G / (2 * rho) * (math.cos(tilt_near - alpha) - math.cos(alpha)))
    t_near, _ = first_contact_time(L_DOM, s, d_near, 1.01 * omega_near, G)
    assert t_near == pytest.approx(
        edge_fall_by_newton(L_DOM, s, 0.0, 1.01 * omega_near, tilt_near, G)[0], rel=1e-9
    )
    with pytest.raises(ValueError, match="omega0"):
        first_contact_time(L_DOM, s, d_near, 0.99 * omega_near, G)


def test_validate_first_contact_without_gravity():
    """g -> 0: uniform rotation, t = asin(d / l) / omega."""
    t, tilt = first_contact_time(L_DOM, S_DOM, 0.01, 7.0, 1e-30)
    assert tilt == math.asin(0.01 / L_DOM)
    assert t == pytest.approx(tilt / 7.0, rel=1e-13)


def test_validate_edge_reaction_balances_momentum():
    """The hinge force is m times the centre's acceleration plus its weight: compared with
    a finite-difference second derivative of the centre's path along a DOP853 solution;
    at the balance tilt, at rest, it carries the full weight."""
    s = S_DOM
    rho, alpha = math.hypot(L_DOM, s) / 2, math.atan(s / L_DOM)
    sol = solve_ivp(
        lambda _t, y: [y[1], 3 * G / (4 * rho) * math.sin(y[0] - alpha)],
        (0, 0.1),
        [alpha + 0.2, 0.0],
        method="DOP853",
        rtol=1e-13,
        atol=1e-15,
        dense_output=True,
    )
    tm, h = 0.05, 1e-4

    def centre(t):
        phi = sol.sol(t)[0] - alpha
        return rho * np.array([math.sin(phi), math.cos(phi)])

    acc = (centre(tm + h) - 2 * centre(tm) + centre(tm - h)) / h**2
    theta, omega = sol.sol(tm)
    f_x, f_z = edge_reaction(L_DOM, s, theta, omega, G)
    np.testing.assert_allclose([f_x, f_z], [acc[0], acc[1] + G], rtol=1e-6)
    np.testing.assert_allclose(edge_reaction(L_DOM, s, alpha, 0.0, G), [0.0, G], atol=1e-15)


# --- rigid_impact ---------------------------------------------------------------------


def _box_body(m, half, rotation, x, v, w):
    """A uniform box of mass m and half-extents ``half`` (3,), its principal axes turned by
    ``rotation`` (3, 3), as a reference Body."""
    a, b, c = half
    principal = m / 3.0 * np.array([b * b + c * c, c * c + a * a, a * a + b * b])
    inertia = rotation @ np.diag(principal) @ rotation.T
    return Body(m, inertia, np.asarray(x, float), np.asarray(v, float), np.asarray(w, float))


def _eccentric_pair():
    """Two tilted, spinning dominoes meeting off their centres (a generic 3D impact)."""
    rng = np.random.default_rng(7)
    q_i, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    q_j, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    half = np.array([S_DOM, W_DOM, L_DOM]) / 2
    body_i = _box_body(0.009, half, q_i, [0, 0, 0.02], [0.3, 0.05, -0.1], [2.0, -5.0, 1.0])
    body_j = _box_body(0.012, half, q_j, [0.03, 0.004, 0.01], [-0.2, 0.0, 0.1], [0.0, 3.0, -1])
    p = np.array([0.012, 0.006, 0.031])
    n = np.array([1.0, 0.2, -0.3])
    return body_i, body_j, p, n / np.linalg.norm(n)


@pytest.mark.parametrize("e", [1.0, 0.7, 0.3])
def test_validate_impulse_collision_conservation(e):
    """Newton's law at an eccentric point: momentum and angular momentum (about the
    origin and about another point) conserved to round-off, u' = -e u, and the energy lost
    is (1 - e^2) m_eff u^2 / 2."""
    body_i, body_j, p, n = _eccentric_pair()
    u = normal_velocity(body_i, body_j, p, n)
    after_i, after_j, _, m_eff = impulse_collision(body_i, body_j, p, n, e)
    momentum = body_i.m * body_i.v + body_j.m * body_j.v
    np.testing.assert_allclose(after_i.m * after_i.v + after_j.m * after_j.v, momentum, 1e-14)
    for about in (np.zeros(3), np.array([0.1, -0.2, 0.3])):
        before = body_i.angular_momentum(about) + body_j.angular_momentum(about)
        after = after_i.angular_momentum(about) + after_j.angular_momentum(about)
        np.testing.assert_allclose(after, before, rtol=1e-13, atol=1e-18)
    assert normal_velocity(after_i, after_j, p, n) == pytest.approx(-e * u, rel=1e-13, abs=1e-17)
    total = body_i.kinetic_energy() + body_j.kinetic_energy()
    lost = total - after_i.kinetic_energy() - after_j.kinetic_energy()
    assert lost == pytest.approx(energy_loss(m_eff, u, e), rel=1e-10, abs=1e-14 * total)


def test_validate_effective_mass_closed_forms():
    """Central impact of equal balls: m/2, and e = 1 swaps the velocities. A ball hitting
    the end of a free rod (length L, mass M) at right angles: 1/m_eff = 1/m + 4/M."""
    ball = np.eye(3) * 0.4 * 1.0 * 0.01**2
    a = Body(1.0, ball, np.zeros(3), np.array([1.0, 0, 0]), np.zeros(3))
    b = Body(1.0, ball, np.array([0.02, 0, 0]), np.zeros(3), np.zeros(3))
    p, n = np.array([0.01, 0, 0]), np.array([1.0, 0, 0])
    after_a, after_b, _, m_eff = impulse_collision(a, b, p, n, 1.0)
    assert m_eff == pytest.approx(0.5, rel=1e-15)
    np.testing.assert_allclose([after_a.v[0], after_b.v[0]], [0.0, 1.0], atol=1e-15)
    rod_l, rod_m = 0.5, 3.0
    rod = Body(rod_m, np.diag([rod_m * rod_l**2 / 12] * 3), np.zeros(3), np.zeros(3), np.zeros(3))
    point = Body(0.2, np.eye(3) * 1e-9, np.array([-0.1, rod_l / 2, 0]), np.zeros(3), np.zeros(3))
    m_eff = effective_mass(point, rod, np.array([0, rod_l / 2, 0]), np.array([1.0, 0, 0]))
    assert 1 / m_eff == pytest.approx(1 / 0.2 + 4 / rod_m, rel=1e-12)


@pytest.mark.parametrize("e", [1.0, 0.7, 0.3])
def test_validate_compliant_impact_equals_impulse(e):
    """The 12 velocities integrated through the spring-dashpot with c from m_eff (frozen
    geometry) end where Newton's restitution law puts them (measured ~1e-12 relative): m_eff is the
    mass the contact point feels, and the dashpot gives the restitution it is set for."""
    body_i, body_j, p, n = _eccentric_pair()
    m_eff = effective_mass(body_i, body_j, p, n)
    k = 1e4
    c = dashpot_for_restitution(e, k, m_eff)
    ode_i, ode_j, duration = compliant_impact(body_i, body_j, p, n, k, c)
    imp_i, imp_j, _, _ = impulse_collision(body_i, body_j, p, n, e)
    scale = np.linalg.norm(body_i.v) + np.linalg.norm(body_j.v)
    for ode, imp in ((ode_i, imp_i), (ode_j, imp_j)):
        np.testing.assert_allclose(ode.v, imp.v, atol=1e-11 * scale)
        np.testing.assert_allclose(ode.w, imp.w, atol=1e-11 * scale / L_DOM)
    zeta = c / (2 * math.sqrt(k * m_eff))
    assert duration == pytest.approx(math.pi / math.sqrt(k / m_eff * (1 - zeta**2)), rel=1e-10)


# --- resting_box ----------------------------------------------------------------------


def _hessian_modes(m, inertia, corners, h, k, kt, g):
    """Small-oscillation frequencies from the exact potential of the box on its corner
    springs (rotation by scipy's rotation vector, springs on the exact corner positions):
    Hessian by central differences at rest, then the generalized eigenproblem K v = w^2 M v."""
    from scipy.linalg import eigh
    from scipy.spatial.transform import Rotation

    corners = np.asarray(corners, float)
    body = np.column_stack((corners, np.full(len(corners), -h)))
    delta0 = m * g / (len(corners) * k)
    rest = body + np.array([0.0, 0.0, h - delta0])

    def potential(q):
        world = Rotation.from_rotvec(q[3:]).apply(body) + q[:3] + np.array([0, 0, h - delta0])
        overlap = np.maximum(-world[:, 2], 0.0)
        slide = world[:, :2] - rest[:, :2]
        return m * g * q[2] + 0.5 * k * overlap @ overlap + 0.5 * kt * np.sum(slide**2)

    eps = 1e-2 * delta0 / max(np.abs(corners).max(), h)  # the corners stay in contact
    stiffness = np.zeros((6, 6))
    for a in range(6):
        for b in range(6):
            ea, eb = np.eye(6)[a] * eps, np.eye(6)[b] * eps
            stiffness[a, b] = (
                potential(ea + eb) - potential(ea - eb) - potential(eb - ea) + potential(-ea - eb)
            ) / (4 * eps * eps)
    mass = np.diag([m, m, m, *inertia])
    return np.sqrt(np.maximum(eigh(stiffness, mass, eigvals_only=True), 0.0))


@pytest.mark.parametrize("kt", [0.0, 300.0])
def test_validate_resting_box_modes_equal_hessian(kt):
    """A 3D domino on its four base corners: the closed-form frequencies against the
    eigenfrequencies of the exact potential's Hessian (central differences; measured
    agreement <= 2e-8); corner load m g / 4."""
    m, k, h = 0.009, 1e3, L_DOM / 2
    _, inertia = box_mass_properties(S_DOM / 2, W_DOM / 2, L_DOM / 2, m / (L_DOM * W_DOM * S_DOM))
    corners = [[sx * S_DOM / 2, sy * W_DOM / 2] for sx in (-1, 1) for sy in (-1, 1)]
    force, overlap = resting_corner_load(m, 4, k, G)
    assert force == pytest.approx(m * G / 4, rel=1e-15)
    assert overlap * k == pytest.approx(force, rel=1e-15)
    modes = resting_box_modes(m, inertia, corners, h, k, kt, G)
    closed = sorted([modes["bounce"], *modes["rock_y"], *modes["rock_x"], modes["yaw"]])
    numeric = np.sort(_hessian_modes(m, inertia, corners, h, k, kt, G))
    np.testing.assert_allclose(numeric, closed, rtol=1e-6, atol=1e-3)
    if kt == 0.0:
        rock = math.sqrt((k * 4 * (S_DOM / 2) ** 2 - m * G * h) / inertia[1])
        assert modes["rock_y"] == (0.0, pytest.approx(rock, rel=1e-14))
        assert modes["bounce"] == pytest.approx(math.sqrt(4 * k / m), rel=1e-15)


def test_validate_resting_box_planar_limit_and_soft_springs():
    """Planar box on two corners: the rocking of a stiff contact tends to the brief's
    sqrt(k sum x^2 / I) (the -m g h correction ~ delta_0 h / (s/2)^2); a top-heavy box on
    soft springs is refused."""
    m, h, inertia = 0.009, L_DOM / 2, np.array([1.0, 1.7e-6, 1.0])
    corners = [[-S_DOM / 2, 0.0], [S_DOM / 2, 0.0]]
    for k in (1e6, 1e8):
        _, rock = resting_box_modes(m, inertia, corners, h, k)["rock_y"]
        stiff = math.sqrt(k * 2 * (S_DOM / 2) ** 2 / inertia[1])
        correction = -0.5 * m * G * h / (k * 2 * (S_DOM / 2) ** 2)
        assert rock / stiff - 1 == pytest.approx(correction, rel=1e-4)
    with pytest.raises(ValueError, match="too soft"):
        resting_box_modes(m, inertia, corners, h, 1.0)


# --- rounded_tipping ------------------------------------------------------------------


def test_validate_rounded_tipping_sharp_limit():
    """r = 0 is the sharp box of edge_tipping: the same fall and first contact (the
    uniform cuboid's k_G^2 = (l^2 + s^2) / 12 gives j = I_edge / m)."""
    alpha = math.atan(S_DOM / L_DOM)
    sharp = edge_fall_time(L_DOM, S_DOM, alpha + 0.1, 0.0, math.pi / 2, G)
    rounded = rounded_fall_time(L_DOM, S_DOM, 0.0, alpha + 0.1, 0.0, math.pi / 2, G)
    assert rounded == pytest.approx(sharp, rel=1e-13)
    t, tilt = rounded_first_contact_time(L_DOM, S_DOM, 0.0, 0.0094, 5.0, G)
    t_sharp, tilt_sharp = first_contact_time(L_DOM, S_DOM, 0.0094, 5.0, G)
    assert tilt == pytest.approx(tilt_sharp, rel=1e-14)
    assert t == pytest.approx(t_sharp, rel=1e-13)


@pytest.mark.parametrize(("theta0", "omega0"), [(0.2, 0.0), (0.0, 5.0), (0.0, 12.0)])
def test_validate_rounded_fall_quadrature_equals_lagrange(theta0, omega0):
    """Energy quadrature (E) against Lagrange's equation (L) by DOP853 for r = s/4 (the
    rounded body's own inertia), to 1e-10."""
    r = S_DOM / 4
    core = (S_DOM / 2 - r, W_DOM / 2 - r, L_DOM / 2 - r)
    _, mass, inertia = rounded_box_mass_properties(*core, r, RHO)
    k2 = inertia[1] / mass
    t_quad = rounded_fall_time(L_DOM, S_DOM, r, theta0, omega0, 1.4, G, k2)
    t_ode, _ = rounded_fall_by_lagrange(L_DOM, S_DOM, r, theta0, omega0, 1.4, G, k2)
    assert t_quad == pytest.approx(t_ode, rel=1e-10)


def _core_distance(l, s, r, d, theta):
    """Signed distance between the two core rectangles (corners to edges both ways,
    negative once a corner is inside the other core): domino 0 rolled by theta on its
    edge (axis K at (-r + r theta, r)), domino 1 upright at gap d."""
    k = np.array([-r + r * theta, r])
    c, si = math.cos(theta), math.sin(theta)
    body = np.array([[0.0, 0.0], [0.0, l - 2 * r], [-(s - 2 * r), l - 2 * r], [-(s - 2 * r), 0]])
    a = k + body @ np.array([[c, -si], [si, c]])  # (x, z) -> (x c + z s, -x s + z c)
    b = np.array([[d + r, r], [d + r, l - r], [d + s - r, l - r], [d + s - r, r]])

    def point_segment(p, u, v):
        length2 = (v - u) @ (v - u)
        t = 0.0 if length2 == 0.0 else np.clip((p - u) @ (v - u) / length2, 0.0, 1.0)
        return np.linalg.norm(p - u - t * (v - u))

    def inside(p, poly):
        edges = np.roll(poly, -1, axis=0) - poly
        cross = edges[:, 0] * (p - poly)[:, 1] - edges[:, 1] * (p - poly)[:, 0]
        return bool(np.all(cross > 0) or np.all(cross < 0))

    pairs = ((a, b), (b, a))
    distance = min(
        point_segment(p, poly[i], poly[(i + 1) % 4])
        for ps, poly in pairs
        for p in ps
        for i in range(4)
    )
    overlapping = any(inside(p, poly) for ps, poly in pairs for p in ps)
    return -distance if overlapping else distance


@pytest.mark.parametrize(("r", "d"), [(S_DOM / 20, 0.0094), (S_DOM / 4, 0.015), (S_DOM / 2, 0.03)])
def test_validate_rounded_first_contact_by_geometry(r, d):
    """The first-touch tilt (eq C) and time against Lagrange's equation with an event on
    the true distance between the two cores reaching 2 r (polygon distance); the time
    differs from the sharp box's by O(r / l) (measured -0.79 r / l at r = s/20, d = 9.4 mm,
    omega = 6 rad/s: 0.6 %, -0.06 % at r = s/200)."""
    omega = 6.0
    t, tilt = rounded_first_contact_time(L_DOM, S_DOM, r, d, omega, G)
    _, _, rho, alpha = rounded_geometry(L_DOM, S_DOM, r)
    k2 = (L_DOM**2 + S_DOM**2) / 12

    def rhs(_t, y):
        phi = y[0] - alpha
        j = k2 + rho * rho + r * r + 2 * r * rho * math.cos(phi)
        return [y[1], rho * math.sin(phi) * (G + r * y[1] ** 2) / j]

    def touch(_t, y):
        return _core_distance(L_DOM, S_DOM, r, d, y[0]) - 2 * r

    touch.terminal, touch.direction = True, -1
    sol = solve_ivp(
        rhs, (0, 1.0), [0.0, omega], method="DOP853", rtol=1e-12, atol=1e-14, events=touch
    )
    assert tilt == pytest.approx(sol.y_events[0][0][0], rel=1e-10)
    assert t == pytest.approx(sol.t_events[0][0], rel=1e-10)
    t_sharp, _ = first_contact_time(L_DOM, S_DOM, d, omega, G)
    assert abs(t / t_sharp - 1) < 3 * r / L_DOM


def test_validate_rounded_roll_conserves_energy_by_kinematics():
    """The rolling kinematics behind j(theta): along the Lagrange solution, the energy
    (1/2) |v_G|^2 + (1/2) k_G^2 theta'^2 + g z_G, with v_G by central differences of the
    centre's rolled position, stays constant (1e-7, the differencing error)."""
    r, k2 = S_DOM / 4, (L_DOM**2 + S_DOM**2) / 12
    p, q, rho, alpha = rounded_geometry(L_DOM, S_DOM, r)

    def rhs(_t, y):
        phi = y[0] - alpha
        j = k2 + rho * rho + r * r + 2 * r * rho * math.cos(phi)
        return [y[1], rho * math.sin(phi) * (G + r * y[1] ** 2) / j]

    sol = solve_ivp(
        rhs, (0, 0.12), [0.0, 6.0], method="DOP853", rtol=1e-13, atol=1e-15, dense_output=True
    )

    def centre(t):
        th = sol.sol(t)[0]
        return np.array([-r + r * th - p * math.cos(th) + q * math.sin(th),
                         r + p * math.sin(th) + q * math.cos(th)])  # fmt: skip

    h, energies = 1e-5, []
    for t in np.linspace(0.01, 0.11, 6):
        v = (centre(t + h) - centre(t - h)) / (2 * h)
        omega = sol.sol(t)[1]
        energies.append(0.5 * v @ v + 0.5 * k2 * omega**2 + G * centre(t)[1])
    np.testing.assert_allclose(energies, energies[0], rtol=1e-7)
    assert rounded_fall_by_lagrange(L_DOM, S_DOM, r, 0.0, 6.0, 1.0, G)[1] > 6.0


# --- box_distance ---------------------------------------------------------------------


def _turn(axis, angle):
    """Rotation matrix about a coordinate axis (0, 1, 2) by ``angle`` [rad]."""
    from scipy.spatial.transform import Rotation

    return Rotation.from_rotvec(np.eye(3)[axis] * angle).as_matrix()


def _corners(centre, rotation, half):
    signs = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)])
    return centre + (signs * half) @ rotation.T


def test_validate_box_distance_closed_forms():
    """Face-face (parallel, gap 0.1), edge-face (B turned 45 deg about y: its lowest
    edge (a + c)/sqrt 2 below its centre) and crossed edges (A turned about x, B about
    y: D = z_B - z_A - (b_A + c_A)/sqrt 2 - (a_B + c_B)/sqrt 2)."""
    half_a, half_b = np.array([0.3, 0.5, 0.7]), np.array([0.2, 0.4, 0.6])
    eye = np.eye(3)
    d, _, _ = box_box_distance([0, 0, 0], eye, half_a, [0.6, 0.1, -0.2], eye, half_b)
    assert d == pytest.approx(0.1, rel=1e-13)
    z_b = 2.0
    d, _, p_b = box_box_distance([0, 0, 0], eye, half_a, [0, 0, z_b], _turn(1, math.pi / 4), half_b)
    assert d == pytest.approx(z_b - 0.7 - (0.2 + 0.6) / math.sqrt(2), rel=1e-13)
    assert p_b[2] == pytest.approx(z_b - 0.8 / math.sqrt(2), rel=1e-13)
    d, p_a, p_b = box_box_distance(
        [0, 0, 0], _turn(0, math.pi / 4), half_a, [0.01, -0.02, z_b], _turn(1, math.pi / 4), half_b
    )
    assert d == pytest.approx(z_b - (0.5 + 0.7) / math.sqrt(2) - 0.8 / math.sqrt(2), rel=1e-13)
    np.testing.assert_allclose(p_b - p_a, [0, 0, d], atol=1e-13)


def test_validate_box_distance_separating_plane_certificate():
    """Random poses: the closest points lie in their boxes, and the plane normal to
    p_b - p_a through them separates all corners (the optimality certificate of a
    convex distance); the point and wall distances agree with a degenerate box."""
    rng = np.random.default_rng(3)
    from scipy.spatial.transform import Rotation

    for _ in range(20):
        rot_a, rot_b = Rotation.random(2, random_state=rng).as_matrix()
        half_a, half_b = rng.uniform(0.1, 1.0, 3), rng.uniform(0.1, 1.0, 3)
        c_a, c_b = np.zeros(3), rng.normal(size=3) * 3
        d, p_a, p_b = box_box_distance(c_a, rot_a, half_a, c_b, rot_b, half_b)
        for c, rot, half, p in ((c_a, rot_a, half_a, p_a), (c_b, rot_b, half_b, p_b)):
            assert np.all(np.abs(rot.T @ (p - c)) <= half * (1 + 1e-12))
        if d > 0:
            n = (p_b - p_a) / d
            assert np.max((_corners(c_a, rot_a, half_a) - p_a) @ n) < 1e-12
            assert np.min((_corners(c_b, rot_b, half_b) - p_b) @ n) > -1e-12
            # as a wall, the separating plane sees box b's lowest corner at distance D
            wall = box_wall_distance(c_b, rot_b, half_b, p_a, n)
            assert wall == pytest.approx(d, rel=1e-11)
        point = rng.normal(size=3) * 2
        d_point, _ = box_point_distance(c_b, rot_b, half_b, point)
        d_degenerate, _, _ = box_box_distance(c_b, rot_b, half_b, point, np.eye(3), np.zeros(3))
        assert d_point == pytest.approx(d_degenerate, rel=1e-12, abs=1e-14)


def test_validate_box_distance_continuous_over_a_corner():
    """An edge of box B (turned 45 deg) sliding 0.05 above a face of box A and over its
    corner (validation 5's path): the nearest features go edge-face, edge-edge, face-edge,
    and the distance follows the closed form of each (0.05; the distance of the two edges,
    hypot(x - 0.5, 0.05); the corner to B's lower face, (x - 0.5 + 0.05) / sqrt 2), without
    a jump (steps bounded by the path step: D is 1-Lipschitz)."""
    half_a, half_b = np.array([0.5, 0.5, 0.5]), np.array([0.2, 0.3, 0.2])
    rot_b = _turn(1, math.pi / 4)  # the lowest edge of B runs along y
    height = 0.5 + 0.2 * math.sqrt(2) + 0.05  # B's edge 0.05 above A's top face
    xs = np.linspace(0.0, 0.7, 141)
    distances = np.array(
        [
            box_box_distance([0, 0, 0], np.eye(3), half_a, [x, 0, height], rot_b, half_b)[0]
            for x in xs
        ]
    )
    assert np.max(np.abs(np.diff(distances))) <= (xs[1] - xs[0]) * (1 + 1e-9)
    beyond = xs - 0.5
    expected = np.where(
        beyond <= 0.0,
        0.05,
        np.where(beyond <= 0.05, np.hypot(beyond, 0.05), (beyond + 0.05) / math.sqrt(2)),
    )
    np.testing.assert_allclose(distances, expected, rtol=1e-12)


def test_validate_stack_against_the_spring_chain():
    """A stack of five boxes on four corner springs per interface: the loads and overlaps
    against the static solution of the spring chain K u = -m g (u the boxes' vertical
    displacements), and the vertical-mode frequencies against its eigenvalues."""
    from scipy.linalg import eigh

    m, n_boxes, k = 0.009, 5, 2e5
    stiffness = np.zeros((n_boxes, n_boxes))
    for i in range(n_boxes):  # spring i sits under box i
        stiffness[i, i] += 4 * k
        if i > 0:
            stiffness[i - 1, i - 1] += 4 * k
            stiffness[i - 1, i] -= 4 * k
            stiffness[i, i - 1] -= 4 * k
    u = np.linalg.solve(stiffness, np.full(n_boxes, -m * G))
    overlaps = -np.diff(np.concatenate(([0.0], u)))  # spring i compressed by u_{i-1} - u_i
    force, overlap = stack_loads(m, n_boxes, 4, k, G)
    np.testing.assert_allclose(overlap, overlaps, rtol=1e-12)
    np.testing.assert_allclose(force, 4 * k * overlaps / 4, rtol=1e-12)
    omega = np.sqrt(eigh(stiffness, np.eye(n_boxes) * m, eigvals_only=True))
    np.testing.assert_allclose(stack_bounce_frequencies(m, n_boxes, 4, k), omega, rtol=1e-12)


def test_validate_edge_reaction_closed_form_and_slip():
    """From rest at phi0 beyond balance the floor force per unit weight is vertical
    1 - (3/4)(sin^2 phi + 2 (cos phi0 - cos phi) cos phi), horizontal (3/4) sin phi
    (3 cos phi - 2 cos phi0); the vertical one vanishes near cos phi = 1/3 (phi0 -> 0),
    so the edge slips there whatever mu: edge_slip_tilt finds it before
    alpha + acos(1/3) (79.4 deg for the 48 x 7.5 mm domino) even at mu = 100 (76.3 deg)."""
    alpha = math.atan(S_DOM / L_DOM)
    rho = math.hypot(L_DOM, S_DOM) / 2
    phi0 = 1e-3
    for phi in (0.2, 0.9, 1.3):
        omega = math.sqrt(3 * G / (2 * rho) * (math.cos(phi0) - math.cos(phi)))
        f_x, f_z = edge_reaction(L_DOM, S_DOM, alpha + phi, omega, G)
        vertical = 1 - 0.75 * (
            math.sin(phi) ** 2 + 2 * (math.cos(phi0) - math.cos(phi)) * math.cos(phi)
        )
        horizontal = 0.75 * math.sin(phi) * (3 * math.cos(phi) - 2 * math.cos(phi0))
        assert f_z / G == pytest.approx(vertical, rel=1e-12)
        assert f_x / G == pytest.approx(horizontal, rel=1e-12)
    slip = edge_slip_tilt(L_DOM, S_DOM, alpha + phi0, 0.0, 100.0, math.pi / 2, G)
    assert math.degrees(alpha + math.acos(1 / 3)) == pytest.approx(79.41, abs=0.01)
    # |F_x| / F_z > 100 once |1 - 3 cos phi| < 2 sqrt(0.707 / 100): cos phi < 0.389
    assert alpha + math.acos(0.39) < slip < alpha + math.acos(1 / 3)
    # mu = 0.3: the slip tilt is where |F_x| = mu F_z (closed forms above)
    slip = edge_slip_tilt(L_DOM, S_DOM, alpha + phi0, 0.0, 0.3, math.pi / 2, G)
    phi = slip - alpha
    ratio = (
        0.75
        * math.sin(phi)
        * (3 * math.cos(phi) - 2 * math.cos(phi0))
        / (1 - 0.75 * (math.sin(phi) ** 2 + 2 * (math.cos(phi0) - math.cos(phi)) * math.cos(phi)))
    )
    assert abs(ratio) == pytest.approx(0.3, rel=1e-10)
    assert edge_slip_tilt(L_DOM, S_DOM, alpha + phi0, 0.0, 100.0, 1.0, G) is None
