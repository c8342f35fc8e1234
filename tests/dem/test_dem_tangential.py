"""The tangential (Cundall-Strack) law against closed forms, for both shear kinematics
(``Scene(shear_kinematics=...)``: "contact_point", the default, and "yade", YADE's
ratcheting-free rate; dem/contact.py)."""

import numpy as np
import pytest
from dem_scenes import RHO, R, sphere_mass
from older_states import older_state

from dominowave.dem import Material, Scene, Simulation
from dominowave.dem.laws.tangential import yade_shear_velocity

G = 9.81
KINEMATICS = ("contact_point", "yade")


def _sliding_sphere(kinematics, direction, mu, v0, w0, kn=1e5, planar=True):
    """A sphere on a frictional floor at its equilibrium overlap, moving with speed v0 along
    the horizontal unit vector ``direction`` and spinning with w0 about ``e_z x direction``
    (w0 = v0 / R would be rolling)."""
    scene = Scene(gravity=(0, 0, -G), shear_kinematics=kinematics)
    m = scene.add_material(Material(density=RHO, kn=kn, friction=mu, kt_ratio=1.0))
    scene.add_wall((0, 0, 0), (0, 0, 1), m)
    delta = G * sphere_mass() / kn
    e = np.asarray(direction, float)
    spin_axis = np.cross((0.0, 0.0, 1.0), e)
    scene.add_sphere(
        (0, 0, R - delta),
        R,
        m,
        velocity=v0 * e,
        angular_velocity=w0 * spin_axis,
        blocked="y rx rz" if planar else "",
    )
    return scene.build(safety=0.05, overlap_tolerance=0.1), delta, e, spin_axis


@pytest.mark.parametrize("kinematics", KINEMATICS)
@pytest.mark.parametrize(
    ("direction", "planar"), [((1.0, 0.0, 0.0), True), ((0.6, 0.8, 0.0), False)]
)
def test_validate_sphere_slides_then_rolls(kinematics, direction, planar):
    """A sphere thrown with backspin on a plane (Coulomb mu, normal force m g).

    Closed form while it slips (slip ``s = v - rho w``, contact lever ``rho = R - delta/2``,
    ``I = 2/5 m R^2``): ``dv/dt = -mu g``, ``dw/dt = mu m g rho / I = 5 mu g rho/(2 R^2)``,
    so ``ds/dt = -mu g (1 + 5 rho^2 / (2 R^2))`` and slip ends at
    ``t* = s0 / (mu g (1 + 5 rho^2/(2 R^2)))`` (= 2 (v0 - R w0) / (7 mu g) for rho = R);
    afterwards it rolls at ``v0 - mu g t*`` (= (5 v0 + 2 R w0) / 7).  Both shear
    kinematics obey it: they differ only while the contact sticks (test below), and the
    rolling condition ``s = 0`` is the same for both (laws.tangential.yade_shear_velocity).  In the
    xz plane (planar kernels) and along a diagonal in 3D (general kernels)."""
    mu, v0, w0 = 0.3, 0.2, -10.0
    sim, delta, e, spin_axis = _sliding_sphere(kinematics, direction, mu, v0, w0, planar=planar)
    rho = R - 0.5 * delta
    s0 = v0 - rho * w0
    t_star = s0 / (mu * G * (1.0 + 2.5 * rho**2 / R**2))
    v_final = v0 - mu * G * t_star
    res = sim.run(until=2.5 * t_star, trajectory_every=1)
    assert sim.settings.planar == planar  # (the planar or the general kernels)
    v = res.velocities[:, 0] @ e
    w = res.angular_velocities[:, 0] @ spin_axis
    # no motion out of the line of the throw
    np.testing.assert_allclose(res.velocities[:, 0] @ spin_axis, 0.0, atol=1e-12)
    slip = v - rho * w
    sliding = (res.times > 0.1 * t_star) & (res.times < 0.9 * t_star)
    assert np.polyfit(res.times[sliding], v[sliding], 1)[0] == pytest.approx(-mu * G, rel=1e-4)
    alpha = np.polyfit(res.times[sliding], w[sliding], 1)[0]
    assert alpha == pytest.approx(2.5 * mu * G * rho / R**2, rel=1e-4)
    # slip ends at t* (the crossing interpolated between steps), within one step
    k = np.argmax(slip <= 0.0)
    crossing = res.times[k - 1] + slip[k - 1] / (slip[k - 1] - slip[k]) * sim.dt
    assert abs(crossing - t_star) <= sim.dt
    # then it rolls: the tangential spring oscillates about zero slip (time-averaged)
    late = res.times > 1.5 * t_star
    assert np.abs(slip[late]).max() < 1e-2 * s0
    assert v[late].mean() == pytest.approx(v_final, rel=5e-4)
    assert (w[late] * rho).mean() == pytest.approx(v_final, rel=5e-4)


V_STICK = 0.005  # [m/s] initial speed of the sticking sphere


def _sticking_sphere(kinematics, sink):
    """A sphere that cannot turn, resting on a frictional floor (mu = 1) with an overlap
    ``sink * R``, given the speed V_STICK along x; kt = kn.  Returns the run (every step
    recorded, energies every 10) and the closed-form frequency
    ``sqrt(k_t / m)`` [rad/s]."""
    kn = G * sphere_mass() / (sink * R)
    scene = Scene(gravity=(0, 0, -G), shear_kinematics=kinematics)
    m = scene.add_material(Material(density=RHO, kn=kn, friction=1.0, kt_ratio=1.0))
    scene.add_wall((0, 0, 0), (0, 0, 1), m)
    scene.add_sphere((0, 0, R - sink * R), R, m, velocity=(V_STICK, 0, 0), blocked="rx ry rz")
    sim = scene.build(safety=0.02, overlap_tolerance=0.5)
    omega = np.sqrt(kn / sphere_mass())
    # it sticks: the spring force stays below mu m g (amplitude V_STICK / omega)
    assert V_STICK / omega * kn < 0.2 * kn * sink * R
    res = sim.run(until=12 * 2 * np.pi / omega, trajectory_every=1, energy_every=10)
    return res, omega


def _period(res):
    """Mean period [s] between downward zero crossings of the x velocity (interpolated)."""
    v = res.velocities[:, 0, 0]
    down = np.flatnonzero((v[:-1] > 0) & (v[1:] <= 0))
    t = res.times[down] + v[down] / (v[down] - v[down + 1]) * (res.times[1] - res.times[0])
    return np.mean(np.diff(t))


@pytest.mark.parametrize("sink", [0.02, 0.1])
def test_validate_sticking_contact_is_stiffer_by_alpha_with_yade_kinematics(sink):
    """The cause of the difference between the two shear kinematics, against closed forms.

    A sphere that cannot turn, resting on the floor with overlap delta, displaced
    tangentially while the contact sticks, oscillates on the tangential spring: with the
    contact-point rate the spring stretches by the displacement, period
    ``2 pi sqrt(m / k_t)``; YADE's rate is ``alpha = 2R / (2R - delta)`` times the sliding
    velocity (a wall takes the sphere's radius), so its spring is alpha times stiffer:
    period ``2 pi sqrt(m / (alpha k_t))``.  With delta = 0.02 R and 0.1 R that is 0.5 %
    and 2.6 % shorter."""
    periods = {}
    for kinematics in KINEMATICS:
        res, omega = _sticking_sphere(kinematics, sink)
        periods[kinematics] = _period(res)
    alpha = 2.0 / (2.0 - sink)
    assert periods["contact_point"] == pytest.approx(2 * np.pi / omega, rel=2e-4)
    assert periods["yade"] == pytest.approx(2 * np.pi / (omega * np.sqrt(alpha)), rel=2e-4)


def _tangential(v, n):
    return v - (v @ n) * n


@pytest.mark.parametrize(("Ri", "Rj"), [(0.005, 0.005), (0.005, 0.0025)])
def test_validate_yade_shear_velocity_is_mcnamaras_rate(Ri, Rj):
    """YADE's shear rate against its definition from the material-point velocities.

    For spheres i, j (centre velocities v_i, v_j, spins w_i, w_j, unit normal n from i to
    j, overlap delta) it is ``alpha`` times the relative velocity of the two material points
    at the point that divides the centre line in the ratio R_i : R_j (McNamara et al.,
    Phys. Rev. E 77, 031304 (2008)), ``alpha = (R_i + R_j) / (R_i + R_j - delta)``.  For
    equal radii that point is the contact point midway through the overlap, where the
    default ("contact_point") kinematics takes the velocities: the YADE rate is exactly
    alpha times the default one; for unequal radii the two points differ by O(delta)."""
    rng = np.random.default_rng(7)
    for _ in range(20):
        vi, vj, wi, wj = rng.standard_normal((4, 3))
        n = rng.standard_normal(3)
        n /= np.linalg.norm(n)
        delta = 0.1 * min(Ri, Rj) * rng.random()
        dist = Ri + Rj - delta
        alpha = (Ri + Rj) / dist
        got = np.array(yade_shear_velocity(*(vj - vi), *(Ri * wi + Rj * wj), *n, Ri + Rj, delta))
        # the points at Ri dist / (Ri + Rj) from centre i and Rj dist / (Ri + Rj) from j
        ri, rj = Ri * dist / (Ri + Rj) * n, -Rj * dist / (Ri + Rj) * n
        mcnamara = alpha * ((vj + np.cross(wj, rj)) - (vi + np.cross(wi, ri)))
        np.testing.assert_allclose(_tangential(got, n), _tangential(mcnamara, n), atol=1e-13)
        # the default: material points at the contact point midway through the overlap
        ci, cj = (Ri - 0.5 * delta) * n, -(Rj - 0.5 * delta) * n
        contact_point = (vj + np.cross(wj, cj)) - (vi + np.cross(wi, ci))
        gap = np.abs(_tangential(got - alpha * contact_point, n)).max()
        if Ri == Rj:
            assert gap < 1e-13
        else:  # spins on levers differing by delta (Ri - Rj) / (2 (Ri + Rj))
            assert gap > 1e-6 * delta


def test_validate_energy_books_the_non_conjugate_yade_spring():
    """The energy ledger closes with either kinematics, and shows what YADE's rate does.

    The ledger books as friction dissipation the work of the tangential forces on the
    bodies (contact-point velocities) minus the change of the energy stored in the
    springs.  For the sticking sphere of the test above (displacement x, spring force
    ``-k_t u``): with the contact-point rate ``u = x``, nothing is dissipated; with YADE's
    ``u = alpha x``, the work ``-alpha k_t x^2 / 2`` and the stored ``alpha^2 k_t x^2 / 2``
    differ by ``-(alpha - 1) alpha k_t x^2 / 2``: energy created while the spring loads and
    returned while it unloads, least at the turning points, ``-(alpha - 1) m v0^2 / 2``
    (``alpha k_t x_max^2 = m v0^2``).  The total stays constant in both."""
    sink = 0.1
    alpha = 2.0 / (2.0 - sink)
    for kinematics in KINEMATICS:
        res, _ = _sticking_sphere(kinematics, sink)
        friction = res.energy["dissipated_friction"]
        total = res.energy["total"]
        kinetic0 = 0.5 * sphere_mass() * V_STICK**2
        # (the ledger is exact to O(dt^2): ~3e-5 of kinetic0 here, alpha - 1 = 0.053)
        assert np.abs(total - total[0]).max() < 1e-3 * kinetic0
        if kinematics == "contact_point":
            assert np.abs(friction).max() < 1e-3 * kinetic0
        else:
            assert friction.min() == pytest.approx(-(alpha - 1.0) * kinetic0, rel=1e-2)
            assert friction.max() < 1e-3 * kinetic0


def test_state_saved_without_the_shear_kinematics_loads():
    """Checkpoints written before the option existed load with the default kinematics."""
    sim, *_ = _sliding_sphere("contact_point", (1.0, 0.0, 0.0), 0.3, 0.2, -10.0)
    sim.run(n_steps=50)
    restored = Simulation.from_state(older_state(sim.get_state(), 1))
    assert restored.mats.shear_kinematics[0] == sim.mats.shear_kinematics[0]
    restored.run(n_steps=50)
    sim.run(n_steps=50)
    np.testing.assert_array_equal(restored.bodies.pos, sim.bodies.pos)


def test_yade_kinematics_is_checkpointed():
    sim, *_ = _sliding_sphere("yade", (1.0, 0.0, 0.0), 0.3, 0.2, -10.0)
    sim.run(n_steps=50)
    restored = Simulation.from_state(sim.get_state())
    restored.run(n_steps=50)
    sim.run(n_steps=50)
    np.testing.assert_array_equal(restored.bodies.pos, sim.bodies.pos)


def test_unknown_shear_kinematics_is_refused():
    with pytest.raises(ValueError, match="shear_kinematics = 'exact' is not one of"):
        Scene(shear_kinematics="exact")
