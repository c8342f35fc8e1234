"""The reference solutions checked themselves: against closed forms and limits where one
exists, and against each other where two methods compute the same motion."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from reference.block_statics import block_moment_about_com, moment, sign_change_force
from reference.compliant_collision import head_on_contact, linear_contact
from reference.contact_mechanics import dashpot_restitution, hertz_collision
from reference.planar_chain import PlanarBodies
from reference.rigid_body import free_rotation, quaternion_matrix
from reference.rigid_chain import (
    ej_chain_by_newton,
    ej_collision,
    ej_fall_time,
    ej_transfer_factor,
    ej_transient_arrivals,
    fall_by_newton,
    hinged_fall_time_from_rest,
)
from reference.rolling_column import (
    rolling_column_by_ode,
    rolling_column_contact_angle,
    rolling_column_friction_ratio,
    rolling_column_rate,
    rolling_column_time,
)

L, M, G = 0.05, 0.008, 9.81
S = math.sqrt(G / L)  # the domino's rate sqrt(g/l) [1/s]


# --- rigid_chain --------------------------------------------------------------------


@pytest.mark.parametrize(("beta", "omega_scale"), [(1e-2, 0.1), (1e-2, 1.0), (1e-3, 0.1)])
def test_validate_ej_fall_time_small_angle_limit(beta, omega_scale):
    """Small tilts: theta'' = (g/l) theta gives T_0 = asinh(beta s / Omega) / s. With
    1 - cos(theta) = theta^2/2 - theta^4/24 the first correction, for Omega >> s beta,
    is T / T_0 - 1 = s^2 beta^4 / (120 Omega^2)."""
    omega = omega_scale * S
    linear = math.asinh(beta * S / omega) / S
    predicted = S**2 * beta**4 / (120 * omega**2)
    assert ej_fall_time(omega, beta, L, G) / linear - 1 == pytest.approx(predicted, rel=0.02)


@pytest.mark.parametrize("beta", [0.3, 1.0, 1.5])
def test_validate_ej_fall_time_fast_limit(beta):
    """A fast domino barely feels gravity: T = (beta / Omega)(1 - (s / Omega)^2
    (1 - sin(beta) / beta) + O(Omega^-4))."""
    omega = 1e4 * S
    first = -((S / omega) ** 2) * (1 - math.sin(beta) / beta)
    rel = ej_fall_time(omega, beta, L, G) * omega / beta - 1
    assert rel == pytest.approx(first, rel=1e-6)


@pytest.mark.parametrize("beta", [0.1, 0.8, 1.5])
@pytest.mark.parametrize("omega_scale", [0.05, 1.0, 20.0])
def test_validate_ej_fall_time_quadrature_equals_newton(beta, omega_scale):
    """Eq 11 by quadrature and Newton's law by DOP853 give the same fall (measured 2e-13),
    and the angular velocity on arrival obeys the energy integral."""
    omega = omega_scale * S
    t_newton, omega_beta = fall_by_newton(0.0, omega, beta, L, G)
    assert ej_fall_time(omega, beta, L, G) == pytest.approx(t_newton, rel=1e-11)
    energy = omega**2 + 2 * G / L * (1 - math.cos(beta))
    assert omega_beta**2 == pytest.approx(energy, rel=1e-12)


@pytest.mark.parametrize("beta", [0.05, 0.7, 1.2, 1.55])
def test_validate_ej_collision_root_is_the_closed_form(beta):
    """The numerically solved collision conserves energy and the angular momentum about
    the struck hinge, and its root is eq 4: Omega_{n+1} = f_+ Omega_f."""
    omega_f = 3.0
    omega_next, omega_back = ej_collision(omega_f, beta)
    c = math.cos(beta) ** 2
    assert omega_back**2 + omega_next**2 == pytest.approx(omega_f**2, rel=1e-14)
    assert omega_next == pytest.approx(c * (omega_f - omega_back), rel=1e-14)
    assert omega_next == pytest.approx(ej_transfer_factor(beta) * omega_f, rel=1e-13)
    assert omega_back < 0


@pytest.mark.parametrize(("beta", "omega_scale"), [(0.6, 0.2), (1.1, 4.0)])
def test_validate_ej_chain_newton_equals_quadrature_and_recursion(beta, omega_scale):
    """Two references for the rigid transient agree (measured 3e-14): Newton's law and
    numerically solved collisions, and eq 11 by quadrature with the recursion eq 6; the
    late intervals approach d / v of eq 14."""
    omega_1 = omega_scale * S
    t, x, v_limit = ej_transient_arrivals(300, math.sin(beta), L, omega_1, G)
    np.testing.assert_allclose(ej_chain_by_newton(40, omega_1, beta, L, G), t[:40], rtol=1e-11)
    assert x[1] / (t[-1] - t[-2]) == pytest.approx(v_limit, rel=1e-6)


def test_validate_hinged_fall_from_rest_small_angle_limit():
    """A thin rod (I = m l^2 / 3, centre of mass at l/2) from rest at small theta0:
    theta'' = (3 g / 2 l) theta gives t_0 = sqrt(2 l / 3 g) acosh(theta1 / theta0); the
    relative correction is O(theta1^2): it shrinks 100-fold when the angles shrink 10-fold."""
    inertia = M * L**2 / 3
    errors = []
    for theta0, theta1 in ((1e-4, 1e-2), (1e-5, 1e-3)):
        linear = math.sqrt(2 * L / (3 * G)) * math.acosh(theta1 / theta0)
        rel = hinged_fall_time_from_rest(M, inertia, 0.0, L / 2, theta0, theta1, G) / linear - 1
        assert 0 < rel < theta1**2 / 100
        errors.append(rel)
    assert errors[0] / errors[1] == pytest.approx(100, rel=1e-3)


@pytest.mark.parametrize(("cm_u", "theta0"), [(0.0, 0.05), (-0.005, 0.3)])
def test_validate_hinged_fall_from_rest_equals_newton(cm_u, theta0):
    """The from-rest quadrature against Newton's law I theta'' = m g (cm_w sin theta +
    cm_u cos theta) integrated by DOP853: a point mass at the tip, and a block of
    thickness s = 0.01 (I = m (l^2 + s^2) / 3, centre of mass at (-s/2, l/2)) released
    beyond its tipping angle atan(s / l) = 0.197."""
    if cm_u == 0.0:
        inertia, cm_w = M * L**2, L
    else:
        inertia, cm_w = M * (L**2 + 4 * cm_u**2) / 3, L / 2

    def rhs(_t, y):
        return [y[1], M * G * (cm_w * math.sin(y[0]) + cm_u * math.cos(y[0])) / inertia]

    def hit(_t, y):
        return y[0] - 1.2

    hit.terminal = True
    sol = solve_ivp(
        rhs, (0, 10), [theta0, 0.0], method="DOP853", rtol=1e-13, atol=1e-15, events=hit
    )
    t_quad = hinged_fall_time_from_rest(M, inertia, cm_u, cm_w, theta0, 1.2, G)
    assert t_quad == pytest.approx(sol.t_events[0][0], rel=1e-10)


# --- compliant_collision --------------------------------------------------------------


@pytest.mark.parametrize("beta", [0.2, 1.0, 1.4])
def test_validate_head_on_contact_equals_closed_form(beta):
    """The integrated head-on contact is the linear two-body collision with lever arms
    l and l cos^2(beta) (measured 4e-12); the elastic spring returns all the energy."""
    k_r = 1e4 * M * G / L
    duration, omega_a, omega_b, _, _ = head_on_contact(2.0, beta, k_r, M, L)
    closed = linear_contact(L, L * math.cos(beta) ** 2, M * L**2, k_r, 2.0)
    np.testing.assert_allclose((duration, omega_a, omega_b), closed, rtol=1e-10)
    assert omega_a**2 + omega_b**2 == pytest.approx(4.0, rel=1e-10)


@pytest.mark.parametrize(("ga", "gb"), [(1.0, 1.0), (0.05, 0.01), (0.3, 0.9)])
def test_validate_linear_contact_conserves_energy_and_impulse_balance(ga, gb):
    """The closed form conserves energy, and the one impulse J acts on both bodies:
    I (omega_a' - omega) = -J g_a and I omega_b' = J g_b."""
    inertia, omega = 0.02, 1.5
    _, omega_a, omega_b = linear_contact(ga, gb, inertia, 1e3, omega)
    assert omega_a**2 + omega_b**2 == pytest.approx(omega**2, rel=1e-14)
    assert (omega_a - omega) / ga + omega_b / gb == pytest.approx(0.0, abs=1e-14 * omega / ga)


# --- contact_mechanics ----------------------------------------------------------------


def _contact_by_ode(force, m_r, v):
    """Integrate m_r delta'' = -force(delta, delta') from delta = 0, delta' = v until the
    force returns to zero: (duration, delta' at the end, largest overlap)."""

    def ends(t, y):
        return force(*y) if t > 0 else 1.0

    ends.terminal, ends.direction = True, -1
    sol = solve_ivp(
        lambda _t, y: [y[1], -force(*y) / m_r],
        (0, 10.0),
        [0.0, v],
        method="DOP853",
        rtol=1e-12,
        atol=1e-15,
        events=ends,
        dense_output=True,
    )
    t_end = sol.t_events[0][0]
    return t_end, sol.y_events[0][0][1], np.max(sol.sol(np.linspace(0, t_end, 20001))[0])


def test_validate_hertz_collision_against_ode():
    """Hertz's duration (4/5) B(2/5, 1/2) delta_max / v = 2.9432 delta_max / v and
    delta_max against m_r delta'' = -k delta^(3/2) integrated by DOP853."""
    m_r, k, v = 0.3, 2e6, 0.7
    duration, delta_max = hertz_collision(m_r, k, v)
    assert duration * v / delta_max == pytest.approx(2.9432, abs=1e-4)
    # the force continued as -k |delta|^(3/2) below zero, so that it changes sign at the end
    t, v_out, largest = _contact_by_ode(lambda d, _dv: k * math.copysign(abs(d) ** 1.5, d), m_r, v)
    assert duration == pytest.approx(t, rel=1e-9)
    assert delta_max == pytest.approx(largest, rel=1e-8)
    assert v_out == pytest.approx(-v, rel=1e-9)


@pytest.mark.parametrize("zeta", [0.05, 0.2, 0.5])
def test_validate_dashpot_restitution_against_ode(zeta):
    """Schwager & Poeschel's restitution against the spring-dashpot integrated until its
    force returns to zero (the dashpot may not pull), and above the textbook value."""
    m_r, k, v = 0.3, 1e5, 0.5
    c = 2 * zeta * math.sqrt(m_r * k)
    _, v_out, _ = _contact_by_ode(lambda d, dv: k * d + c * dv, m_r, v)
    e = dashpot_restitution(zeta)
    assert -v_out / v == pytest.approx(e, rel=1e-9)
    assert e > math.exp(-zeta * math.pi / math.sqrt(1 - zeta**2))
    with pytest.raises(ValueError, match="zeta"):
        dashpot_restitution(0.8)


# --- rolling_column -------------------------------------------------------------------


def _column(n=10, radius=0.005, density=1000.0):
    """n touching spheres of one radius standing upright: (masses, heights, radii, R)."""
    masses = np.full(n, density * 4.0 / 3.0 * math.pi * radius**3)
    return masses, radius * (1 + 2 * np.arange(n)), np.full(n, radius), radius


@pytest.mark.parametrize(("omega0", "theta0"), [(0.0, 0.05), (3.0, 0.0), (0.5 * S, 0.0)])
def test_validate_rolling_column_quadrature_equals_lagrange_ode(omega0, theta0):
    """The energy quadrature and the Lagrange equation integrated by scipy give the same
    fall to 1 rad (measured 2e-13), from rest at a tilt and from upright with a push."""
    column = _column()
    t_ode, omega_ode = rolling_column_by_ode(*column, omega0, 1.0, G, theta0)
    assert rolling_column_time(*column, omega0, 1.0, G, theta0) == pytest.approx(t_ode, rel=1e-10)
    rate = rolling_column_rate(*column, omega0, G, theta0)
    assert rate(1.0) == pytest.approx(omega_ode, rel=1e-10)


def test_validate_rolling_column_without_base_radius_is_the_hinged_domino():
    """R = 0 and one point mass at height l: the column is EJ's domino (eq 11 from upright,
    energy quadrature from rest), so both references must agree."""
    point = ([M], [L], [0.0], 0.0)
    assert rolling_column_time(*point, S, 1.0, G) == pytest.approx(
        ej_fall_time(S, 1.0, L, G), rel=1e-12
    )
    from_rest = hinged_fall_time_from_rest(M, M * L**2, 0.0, L, 0.05, 1.0, G)
    assert rolling_column_time(*point, 0.0, 1.0, G, theta0=0.05) == pytest.approx(
        from_rest, rel=1e-12
    )


def test_validate_rolling_column_friction_ratio_at_rest():
    """Released from rest at theta0 the floor force is m a_cm + m g with omega = 0 and
    alpha = m g a sin(theta0) / J(theta0): the friction ratio at the start, by hand; over
    the fall the largest ratio is at least that."""
    masses, z, radii, r = _column()
    m = masses.sum()
    a = float(np.sum(masses * z) / m) - r
    i_cm = float(np.sum(masses * (0.4 * radii**2 + (z - (a + r)) ** 2)))
    theta0 = 0.05
    j0 = i_cm + m * (r * r + a * a + 2 * r * a * math.cos(theta0))
    alpha = m * G * a * math.sin(theta0) / j0
    start = (r + a * math.cos(theta0)) * alpha / (G - a * math.sin(theta0) * alpha)
    ratio = rolling_column_friction_ratio(masses, z, radii, r, 0.0, theta0, G, theta0, samples=1)
    assert ratio == pytest.approx(start, rel=1e-12)
    assert rolling_column_friction_ratio(masses, z, radii, r, 0.0, 1.0, G, theta0) > start


@pytest.mark.parametrize("pitch", [0.02, 0.04])
def test_validate_rolling_column_contact_angle_is_the_first_touch(pitch):
    """At the returned tilt the closest sphere pair is exactly 2 R apart; at every
    smaller tilt all pairs are farther apart."""
    _, z, _, r = _column()
    theta_c = rolling_column_contact_angle(z, r, pitch)

    def gap(th):
        x = r * th + (z - r) * np.sin(th)
        zz = r + (z - r) * np.cos(th)
        return np.sqrt(np.min((x[:, None] - pitch) ** 2 + (zz[:, None] - z[None, :]) ** 2)) - 2 * r

    assert abs(gap(theta_c)) < 1e-15
    assert all(gap(th) > 0 for th in np.linspace(0, theta_c, 200, endpoint=False))


# --- rigid_body -----------------------------------------------------------------------


def test_validate_euler_equations_conserve_energy_and_angular_momentum():
    """Spun near the intermediate axis the body flips; energy and |L| stay constant
    (measured 1.2e-10 and 6e-11 over the run, the integrator's tolerance)."""
    inertia = np.array([1.0, 2.0, 3.0])
    w0 = np.array([1e-3, 10.0, 1e-3])
    w = free_rotation(inertia, w0, np.linspace(0, 10, 2001))
    energy = 0.5 * np.sum(inertia * w**2, axis=1)
    ang_mom = np.linalg.norm(inertia * w, axis=1)
    assert np.min(w[:, 1]) < -9.0
    np.testing.assert_allclose(energy, energy[0], rtol=1e-9)
    np.testing.assert_allclose(ang_mom, ang_mom[0], rtol=1e-9)


def test_validate_euler_equations_axisymmetric_closed_form():
    """I_1 = I_2: omega_3 is constant and (omega_1, omega_2) turns at
    Omega = (I_3 - I_1) omega_3 / I_1: omega_1 = A cos(Omega t), omega_2 = A sin(Omega t)."""
    inertia = np.array([2.0, 2.0, 5.0])
    t = np.linspace(0, 4, 801)
    w = free_rotation(inertia, [0.7, 0.0, 3.0], t)
    rate = (5.0 - 2.0) * 3.0 / 2.0
    expected = np.column_stack([0.7 * np.cos(rate * t), 0.7 * np.sin(rate * t), np.full_like(t, 3)])
    np.testing.assert_allclose(w, expected, atol=1e-8)


def test_validate_quaternion_matrix_is_rodrigues_rotation():
    """q = (cos(phi/2), sin(phi/2) n) rotates by phi about n: Rodrigues' formula
    R = cos(phi) 1 + sin(phi) [n]_x + (1 - cos(phi)) n n^T."""
    n = np.array([1.0, -2.0, 0.5])
    n /= np.linalg.norm(n)
    phi = 2.1
    q = np.concatenate([[math.cos(phi / 2)], math.sin(phi / 2) * n])
    cross = np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
    rodrigues = math.cos(phi) * np.eye(3) + math.sin(phi) * cross
    rodrigues += (1 - math.cos(phi)) * np.outer(n, n)
    np.testing.assert_allclose(quaternion_matrix(q), rodrigues, atol=1e-15)


# --- planar_chain ---------------------------------------------------------------------


def test_validate_planar_bodies_bounce_of_a_sphere_on_the_floor():
    """One sphere, no gravity, moving down onto the floor at speed v: the linear spring
    holds it for half a period pi sqrt(m / k_n) and returns it at v."""
    r, m, kn, v = 0.005, 1e-3, 1e3, 0.2
    bodies = PlanarBodies(np.zeros((1, 2)), np.array([r]), m, 1e-9, kn, g=0.0)
    t_c = math.pi * math.sqrt(m / kn)
    end = bodies.solve(np.array([[0.0, r]]), np.array([[0.0, -v, 0.0]]), t_c).y[:, -1]
    assert end[1] == pytest.approx(r, abs=1e-12 * r)
    assert end[4] == pytest.approx(v, rel=1e-10)


def test_validate_planar_bodies_conserve_energy_through_collisions():
    """Two 5-sphere dominoes on the floor, the first pushed into the second: springs
    without damping or friction, so the total energy stays constant through the floor
    and domino contacts (measured drift 6e-11 m g l, the integrator's tolerance)."""
    r, n = 0.005, 5
    local = np.column_stack([np.zeros(n), r * (2 * np.arange(n) - (n - 1))])
    sphere = 1000 * 4 / 3 * math.pi * r**3
    mass, inertia = n * sphere, n * 0.4 * sphere * r**2 + sphere * np.sum(local[:, 1] ** 2)
    height = 2 * n * r
    bodies = PlanarBodies(local, np.full(n, r), mass, inertia, 1e4 * mass * G / height)
    centres = np.array([[0.0, n * r], [0.4 * height, n * r]])
    vel = np.zeros((2, 3))
    vel[0, 2] = 2 * math.sqrt(G / height)
    sol = bodies.solve(centres, vel, 0.1)
    assert sol.t_events[0].size > 0, "the dominoes collide"
    energy = np.array([bodies.energy(y) for y in sol.y.T])
    assert np.max(np.abs(energy - energy[0])) < 1e-9 * mass * G * height


# --- block_statics --------------------------------------------------------------------


def test_validate_block_moments_by_hand():
    """The signed moments are cross products: a unit horizontal force at height 1 about
    the origin turns clockwise (-1); the push alone balances the weight's moment about
    the front edge at f = s / (2 cos^2 beta)."""
    assert moment((0.0, 1.0), (1.0, 0.0), (0.0, 0.0)) == -1.0
    assert moment((2.0, 0.0), (0.0, 3.0), (0.0, 0.0)) == 6.0
    beta, s = 0.7, 0.1
    front = (s / 2, 0.0)

    def about_front(f):
        push = moment((-s / 2, math.cos(beta)), (f * math.cos(beta), 0.0), front)
        return push + moment((0.0, 0.5), (0.0, -1.0), front)

    assert sign_change_force(about_front) == pytest.approx(s / (2 * math.cos(beta) ** 2))
    # friction and normal force under G: only the push and the friction turn the block
    f = 2.0
    by_hand = -(math.cos(beta) - 0.5) * f * math.cos(beta) + 0.5 * 0.3
    assert block_moment_about_com(f, beta, 0.3, s, +1, 0.0) == pytest.approx(by_hand)
