"""Validation of the contact laws against analytic two-body results."""

import numpy as np
import pytest
from dem_scenes import RHO, R, sphere_mass

from dominowave.dem import ONSET, Material, Scene
from dominowave.dem.contact import pair_stiffness, particle_stiffness, viscous_coefficient


def _collide(scene_factory, safety=0.02, **kw):
    sim = scene_factory(**kw).build(safety=safety)
    res = sim.run(until=0.03)
    ev = res.events
    assert list(ev.kind) == [ONSET, 0], "exactly one contact onset and end"
    return sim, ev.time[1] - ev.time[0]


def test_validate_head_on_duration_and_elastic_restitution(two_sphere_scene):
    """Linear spring: contact lasts half a period pi sqrt(m_r / k) and e = 1."""
    kn = 1e4
    sim, duration = _collide(two_sphere_scene, kn=kn)
    m_r = sphere_mass() / 2.0
    expected = np.pi * np.sqrt(m_r / kn)
    assert abs(duration / expected - 1.0) < 5e-3
    restitution = sim.bodies.vel[1, 0] / 0.1
    assert abs(restitution - 1.0) < 1e-4


@pytest.mark.parametrize("e", [0.3, 0.7, 0.95])
def test_validate_viscous_restitution(two_sphere_scene, e):
    """The dashpot from the analytic damped-oscillator relation reproduces e."""
    sim, duration = _collide(two_sphere_scene, restitution=e)
    measured = sim.bodies.vel[1, 0] / 0.1
    assert abs(measured / e - 1.0) < 1e-3
    # damped half period pi / omega_d, omega_d = omega_0 sqrt(1 - zeta^2)
    m_r = sphere_mass() / 2.0
    log_e = np.log(e)
    zeta = -log_e / np.sqrt(np.pi**2 + log_e**2)
    expected = np.pi / (np.sqrt(1e4 / m_r) * np.sqrt(1.0 - zeta**2))
    assert abs(duration / expected - 1.0) < 5e-3


def test_validate_stiffness_rules():
    """paper: k = pi R E per sphere in series (equal spheres: pi R E / 2, paper eq. 21);
    yade: 2 E1 R1 E2 R2 / (E1 R1 + E2 R2)."""
    E1, R1, E2, R2 = 2e7, 0.004, 5e7, 0.006
    k1, k2 = np.pi * R1 * E1, np.pi * R2 * E2
    paper = pair_stiffness(
        particle_stiffness(E1, R1, False, 0), particle_stiffness(E2, R2, False, 0), False, 0
    )
    assert paper == pytest.approx(k1 * k2 / (k1 + k2), rel=1e-14)
    same = pair_stiffness(
        particle_stiffness(E1, R1, False, 0), particle_stiffness(E1, R1, False, 0), False, 0
    )
    assert same == pytest.approx(np.pi * R1 * E1 / 2, rel=1e-14)
    yade = pair_stiffness(
        particle_stiffness(E1, R1, False, 1), particle_stiffness(E2, R2, False, 1), False, 1
    )
    assert yade == pytest.approx(2 * E1 * R1 * E2 * R2 / (E1 * R1 + E2 * R2), rel=1e-14)
    assert pair_stiffness(3e3, 3e3, True, 0) == pytest.approx(3e3, rel=1e-14)


def test_validate_young_modulus_collision_time():
    """A collision with the paper rule lasts pi sqrt(m_r / (pi R E / 2))."""
    E = 1e6
    scene = Scene(gravity=(0, 0, 0), stiffness_rule="paper")
    m = scene.add_material(Material(density=RHO, young=E))
    scene.add_sphere((0, 0, 0), R, m, velocity=(0.05, 0, 0))
    scene.add_sphere((2 * R + 1e-4, 0, 0), R, m)
    sim = scene.build(safety=0.01)
    ev = sim.run(until=0.02).events
    expected = np.pi * np.sqrt(sphere_mass() / 2 / (np.pi * R * E / 2))
    assert abs((ev.time[1] - ev.time[0]) / expected - 1) < 5e-3


def test_viscous_coefficient_limits():
    assert viscous_coefficient(1.0, 1.0, 1.0) == 0.0
    # critical damping is approached as e -> 0
    assert viscous_coefficient(1e-12, 1.0, 1.0) == pytest.approx(2.0, rel=0.05)


def test_validate_sphere_sphere_friction_rolling_free_of_slip():
    """A sphere sliding on a frictional floor ends rolling at v = 5/7 v0 (I = 2/5 m R^2)."""
    scene = Scene(gravity=(0, 0, -9.81))
    m = scene.add_material(
        Material(density=RHO, kn=1e4, friction=0.5, kt_ratio=1.0, restitution=0.3)
    )
    scene.add_wall((0, 0, 0), (0, 0, 1), m)
    v0 = 0.2
    scene.add_sphere(
        (0, 0, R - 9.81 * sphere_mass() / 1e4), R, m, velocity=(v0, 0, 0), blocked="y rx rz"
    )
    sim = scene.build(safety=0.05, overlap_tolerance=0.1)
    # the initial (equilibrium) overlap counts in the ledger from t = 0
    delta0 = 9.81 * sphere_mass() / 1e4
    e0 = sim.energy()
    assert e0["elastic_normal"] == pytest.approx(0.5 * 1e4 * delta0**2, rel=1e-12)
    res = sim.run(until=0.2, trajectory_every=10)
    # after slip stops the undamped tangential spring oscillates (+-0.4 %): time-average
    late = res.times > 0.1
    v_mean = res.velocities[late, 0, 0].mean()
    assert v_mean == pytest.approx(5 / 7 * v0, rel=5e-4)
    # the slip work is the kinetic energy lost: m v0^2/2 (1 - 5/7)
    lost = 0.5 * sphere_mass() * v0**2 * (1 - 5 / 7)
    assert sim.energy()["dissipated_friction"] == pytest.approx(lost, rel=5e-3)
    assert abs(sim.energy()["total"] - e0["total"]) < 1e-6 * e0["kinetic_translational"]


def test_validate_collision_restitution_error_order(two_sphere_scene):
    """Elastic collision across the kink of the linear law at zero overlap: with the
    kick-averaged onset/end (contact.kick_averaged_overlap) the restitution error of one
    collision is below 0.5 (omega dt)^4 for every impact phase (fourth order; the plain
    midpoint rule gives ~0.1 (omega dt)^2)."""
    m_r = sphere_mass() / 2.0
    omega = np.sqrt(1e4 / m_r)
    worst = {}
    for safety in (0.1, 0.05):
        errors = []
        for gap in np.linspace(0.001, 0.0012, 9):
            sim = two_sphere_scene(gap=gap).build(safety=safety)
            sim.run(until=0.03)
            errors.append(abs(sim.bodies.vel[1, 0] / 0.1 - 1.0))
        worst[safety] = max(errors)
        assert worst[safety] < 0.5 * (omega * sim.dt) ** 4
    assert worst[0.1] / worst[0.05] > 8.0
