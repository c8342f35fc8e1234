"""Validation of the hinged-domino model against independent calculations."""

import math

import numpy as np
import pytest

from dominowave.rods import RodChain, block, first_collisions, point_mass, simulate, thin_rod
from dominowave.rods import kernel as K
from reference.compliant_collision import linear_contact
from reference.contact_mechanics import dashpot_restitution, hertz_collision
from reference.rigid_chain import hinged_fall_time_from_rest

G = 9.81
L = 1.0
M = 1.0
K_STAR = M * G / L


def _fall_time(mass, theta0, theta1):
    """Time [s] for a rod-model domino of mass distribution ``mass`` to fall from rest at
    ``theta0`` to ``theta1`` (energy quadrature, tests/reference/rigid_chain.py)."""
    return hinged_fall_time_from_rest(mass.m, mass.inertia, mass.cm_u, mass.cm_w, theta0, theta1, G)


@pytest.mark.parametrize("mass", [point_mass(M, L), thin_rod(M, L)], ids=["point", "rod"])
def test_validate_single_domino_fall_time(mass):
    """Released from rest at 0.05 rad, it reaches the next domino (d/l = 0.9) at the
    time given by quadrature of its energy equation, to 1e-4."""
    d = 0.9 * L
    chain = RodChain(n=2, l=L, d=d, mass=mass, k=1e4 * K_STAR / 2)
    theta0 = 0.05
    run = simulate(chain, push=0.0, theta0=[theta0, 0.0], omega0=[0.0, 0.0])
    expected = _fall_time(mass, theta0, math.asin(d / L))
    assert run.arrival[1] == pytest.approx(expected, rel=1e-4)


def test_validate_base_reaction_of_falling_point_mass():
    """A point mass on a massless hinged rod: the rod force is axial, N = m g (3 cos - 2),
    so |H|/V = tan(theta) until the base would lift off at cos(theta) = 2/3."""
    mass = point_mass(M, L)
    chain = RodChain(n=2, l=L, d=0.95 * L, mass=mass, k=1e4 * K_STAR / 2)
    theta0 = 1e-3
    # stop before lift-off: peak |H|/V is tan of the angle reached
    t_early = _fall_time(mass, theta0, 0.8)
    run = simulate(chain, push=0.0, theta0=[theta0, 0.0], omega0=[0.0, 0.0], t_max=t_early)
    assert run.lift_steps[0] == 0
    assert run.hv_max[0] == pytest.approx(math.tan(run.theta[0]), rel=1e-4)
    # run past cos(theta) = 2/3 (but before the contact at asin 0.95): the base lifts off
    t_late = _fall_time(mass, theta0, 1.1)
    run = simulate(chain, push=0.0, theta0=[theta0, 0.0], omega0=[0.0, 0.0], t_max=t_late)
    assert run.lift_steps[0] > 0
    assert run.hv_max[0] == pytest.approx(math.tan(math.acos(2.0 / 3.0)), rel=1e-3)


@pytest.mark.parametrize(
    ("normal", "d_over_l", "s"),
    [
        ("geometric", 0.4, 0.0),
        ("head-on", 0.4, 0.0),
        ("head-on", 0.8, 0.0),
        ("geometric", 0.7, 0.1),
    ],
)
def test_validate_two_body_collision(normal, d_over_l, s):
    """g = 0, stiff linear spring: duration and momentum exchange of the simulated
    collision match the linearised two-body solution (docs/theory_vs_rods.md)."""
    mass = point_mass(M, L) if s == 0 else block(M, L, s)
    k = 1e8 * K_STAR
    chain = RodChain(n=2, l=L, d=d_over_l * L, s=s, mass=mass, k=k, normal=normal, g=0.0)
    theta_c = math.asin(d_over_l)  # corner (0, l) meets the back face: l sin(theta) = d
    omega = 1.0
    run = simulate(
        chain, push=omega, theta0=[theta_c - 1e-5, 0.0], omega0=[omega, 0.0], steps_per_contact=400
    )
    col = first_collisions(run)
    c2 = math.cos(theta_c) ** 2
    if normal == "geometric":  # force along the face normal: lever arms l cos(beta) on both
        ga = gb = L * math.cos(theta_c)
    else:  # force along the striker's path xi: lever l on the striker, l cos^2 on the struck
        ga, gb = L, L * c2
    duration, omega_b, omega_next = linear_contact(ga, gb, mass.inertia, k, omega)
    assert col.duration[0] == pytest.approx(duration, rel=1e-3)
    assert col.omega_b[0] == pytest.approx(omega_b, abs=1e-3 * omega)
    assert col.omega_next[0] == pytest.approx(omega_next, rel=1e-3)
    if normal == "head-on" and s == 0:
        # the paper's model: EJ's map (eq 3, 4) and T_c of eq 31 with k_r = k
        f_plus = 2.0 / (c2 + 1.0 / c2)
        assert col.transfer[0] == pytest.approx(f_plus, rel=1e-3)
        t_c = math.pi * math.sqrt(M / (k * (1.0 + c2 * c2)))
        assert col.duration[0] == pytest.approx(t_c, rel=1e-3)
    if normal == "geometric":
        assert col.transfer[0] == pytest.approx(1.0, rel=1e-3)  # full transfer


def test_validate_hertz_collision_duration():
    """Hertz law F = k delta^1.5, g = 0: duration 2.9432 delta_max / v with
    delta_max = (5 m_r v^2 / (4 k))^(2/5) (Johnson, Contact Mechanics, sec. 11.4)."""
    k = 1e9
    chain = RodChain(n=2, l=L, d=0.4, mass=point_mass(M, L), k=k, law="hertz", g=0.0)
    theta_c = math.asin(0.4)
    omega = 1.0
    run = simulate(
        chain, push=omega, theta0=[theta_c - 1e-5, 0.0], omega0=[omega, 0.0], steps_per_contact=400
    )
    lever = L * math.cos(theta_c)
    m_r = M * L * L / (2 * lever * lever)
    v = lever * omega
    duration, delta_max = hertz_collision(m_r, k, v)  # duration 2.9432 delta_max / v
    col = first_collisions(run)
    assert col.duration[0] == pytest.approx(duration, rel=2e-3)
    assert col.delta_max[0] == pytest.approx(delta_max, rel=2e-3)


def test_validate_restitution_of_dashpot():
    """Linear spring-dashpot with damping ratio zeta, force clipped at zero: the normal
    approach speed is reversed with the restitution coefficient of Schwager & Poeschel,
    Phys. Rev. E 75, 051304 (2007), eq. 20: e = exp(-zeta/sqrt(1-zeta^2) (pi - atan(
    2 zeta sqrt(1-zeta^2) / (1 - 2 zeta^2)))) for zeta < 1/sqrt(2) (the textbook
    exp(-zeta pi/sqrt(1-zeta^2)) = 0.527 assumes the dashpot may pull; the run gives 0.572)."""
    zeta = 0.2
    k = 1e8 * K_STAR
    chain = RodChain(n=2, l=L, d=0.4, mass=point_mass(M, L), k=k, g=0.0, damping_ratio=zeta)
    theta_c = math.asin(0.4)
    run = simulate(
        chain, push=1.0, theta0=[theta_c - 1e-5, 0.0], omega0=[1.0, 0.0], steps_per_contact=400
    )
    col = first_collisions(run)
    # overlap rate delta' = l cos(beta) (omega_a - omega_b) for the geometric normal
    e = -(col.omega_b[0] - col.omega_next[0]) / (col.omega_f[0] - 0.0)
    assert e == pytest.approx(dashpot_restitution(zeta), rel=2e-3)


def test_validate_energy_conservation_100_dominoes():
    """No damping: kinetic + gravitational + elastic energy of a 100-domino run is
    conserved to 1e-6 (relative to the initial total energy)."""
    chain = RodChain(n=100, l=L, d=0.4 * L, mass=point_mass(M, L), k=1e4 * K_STAR / 2)
    run = simulate(chain, push=1.0, steps_per_contact=1600, n_samples=5000)
    assert run.status == "wave passed"
    assert run.samples[-1, K.SA_FLOOR] == 0.0
    assert run.samples[-1, K.SA_DISSIPATED] == 0.0
    energy = run.total_energy
    assert np.max(np.abs(energy - energy[0])) / energy[0] < 1e-6


def test_validate_energy_balance_with_damping_and_friction():
    """Dashpot and friction: E_total + E_dissipated stays constant (O(dt^2) ledger)."""
    chain = RodChain(
        n=30, l=L, d=0.4 * L, mass=thin_rod(M, L), k=1e4 * K_STAR / 2, damping_ratio=0.1, mu=0.3
    )
    run = simulate(chain, push=2.0, steps_per_contact=800, n_samples=3000)
    dissipated = run.samples[:, K.SA_DISSIPATED] + run.samples[:, K.SA_FLOOR]
    ledger = run.total_energy + dissipated
    assert dissipated[-1] > 0.05 * (run.total_energy[0] - run.samples[-1, K.SA_GRAV])
    assert np.max(np.abs(ledger - ledger[0])) < 2e-3 * dissipated[-1]


def test_validate_skipping_untouched_dominoes_is_exact():
    """Integrating every domino from the start gives bit-identical results to the
    default that skips untouched upright dominoes (standing rule of kernel.py)."""
    chain = RodChain(n=12, l=L, d=0.4 * L, mass=point_mass(M, L), k=1e3 * K_STAR / 2)
    dt = chain.time_step(100)
    results = []
    for n_awake in (1, chain.n):
        theta = np.zeros(chain.n)
        omega = np.zeros(chain.n)
        omega[0] = 1.0
        p = K.ChainParams.typed(
            L, 0.0, chain.pitch, M, M * L * L, 0.0, L, G, K.LAW_LINEAR, chain.k, 0.0, 0.0, 1e-3,
            K.NORMAL_GEOMETRIC, 0.0, True, dt, 20.0, 20.0, 0.0, 100, 0,
        )  # fmt: skip
        st = K.run_chain(p, theta, omega, n_awake, 1000, 1000, 0)
        results.append((theta, omega, st.events[: st.n_events[0]]))
    np.testing.assert_array_equal(results[0][0], results[1][0])
    np.testing.assert_array_equal(results[0][1], results[1][1])
    np.testing.assert_array_equal(results[0][2], results[1][2])
