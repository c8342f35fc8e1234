"""The planar kernels (dem/planar.py, integrate.kick_body_planar/drift_body_planar):
which scenes are planar, and that the planar kernels are the general ones -- to the bit
for the body pass, to round-off for the contact law."""

import math

import numpy as np
import pytest
from dem_scenes import RHO, R, column
from hypothesis import given, settings
from hypothesis import strategies as st

from dominowave.dem import ONSET, Material, Scene, Simulation
from dominowave.dem.contact import cundall_strack, rotate_shear
from dominowave.dem.engine import _advance_bodies
from dominowave.dem.integrate import drift, kick
from dominowave.dem.planar import carry_shear_planar, coulomb_limit_planar, planar_violation


def _planar_scene(y=0.0, sphere_blocked="y rx rz", damping=0.0, **build):
    """Four frictional columns in the plane ``y``, two tilted and spinning so that they
    topple onto their neighbours, and a sphere rolling with spin on a frictional floor."""
    scene = Scene()
    floor = scene.add_material(Material(density=RHO, kn=1e4, friction=0.4))
    face = scene.add_material(Material(density=RHO, kn=1e4, friction=0.3, restitution=0.8))
    scene.add_wall((0, 0, 0), (0, 0, 1), floor)
    for c in range(4):
        scene.add_clump(
            column(6, base=(0.025 * c, y, R), tilt=0.3 if c % 2 == 0 else 0.0),
            R,
            [floor] + [face] * 5,
            blocked="y rx rz",
            angular_velocity=(0.0, 2.0 if c % 2 == 0 else 0.0, 0.0),
        )
    scene.add_sphere(
        (-0.03, y, R),
        R,
        face,
        velocity=(0.3, 0.0, 0.0),
        angular_velocity=(0.0, -20.0, 0.0),
        blocked=sphere_blocked,
    )
    return scene.build(damping=damping, **build)


def test_planar_scenes_are_recognised():
    assert _planar_scene().planar
    assert _planar_scene(y=0.01).planar  # any one plane y = y0
    sim = _planar_scene()
    sim.run(n_steps=200)
    assert sim.settings.planar  # the run used the planar kernels
    sim.planar_kernels = False
    sim.run(n_steps=10)
    assert not sim.settings.planar


@pytest.mark.parametrize(
    ("change", "reason"),
    [
        (lambda b, s, w: b.blocked.__setitem__((2, 1), 0), "body 2 has y, rx or rz free"),
        (lambda b, s, w: b.omega.__setitem__((1, 0), 1e-3), "body 1 moves out of the plane"),
        (lambda b, s, w: b.vel.__setitem__((3, 1), 1e-3), "body 3 moves out of the plane"),
        (lambda b, s, w: b.pos.__setitem__((2, 1), 1e-3), "body 2 lies in the plane y = 0.001"),
        (lambda b, s, w: b.axis.__setitem__(0, (1.0, 0.0, 0.0)), "body 0 does not turn about"),
        (
            lambda b, s, w: s.local.__setitem__(7, s.local[7] + 1e-4 * b.rot[s.body[7], 1]),
            "sphere 7 lies 0.0001 m out",
        ),
        (lambda b, s, w: w.normal.__setitem__(0, (0.0, 0.6, 0.8)), "wall 0 has a normal"),
    ],
)
def test_planar_violation_names_the_reason(change, reason):
    sim = _planar_scene()
    assert planar_violation(sim.bodies, sim.spheres, sim.walls) is None
    change(sim.bodies, sim.spheres, sim.walls)
    assert reason in planar_violation(sim.bodies, sim.spheres, sim.walls)


def test_free_bodies_and_spheres_off_the_plane_are_not_planar():
    assert "has y, rx or rz free" in planar_violation(
        *(lambda s: (s.bodies, s.spheres, s.walls))(_planar_scene(sphere_blocked=""))
    )
    scene = Scene()
    m = scene.add_material(Material(density=RHO, kn=1e4))
    scene.add_clump([(0, 0, R), (0, R, 3 * R)], R, m, blocked="y rx rz")
    sim = scene.build()
    assert "lies" in planar_violation(sim.bodies, sim.spheres, sim.walls)


@pytest.mark.parametrize("damping", [0.0, 0.3])
def test_validate_planar_body_pass_is_the_general_one_to_the_bit(damping):
    """kick_body_planar and drift_body_planar drop only terms that are exactly zero in a
    planar scene: the fused pass and the separate kick/drift give the state of the
    general kernels bit for bit (fresh bodies, clumps turning about e_y, and a sphere)."""
    states = []
    for planar in (True, False):
        sim = _planar_scene(damping=damping)
        sim.run(n_steps=300)  # contacts and torques on every body
        s = sim.settings._replace(planar=planar)
        sim.bodies.fresh[[1, 4]] = 1  # the half kick of a velocity-Verlet start
        for _ in range(50):
            _advance_bodies(sim.bodies, s)
        power = kick(sim.bodies, s.gravity, s.dt, damping, True, planar)
        drift(sim.bodies, s.dt, planar)
        states.append((sim.bodies, power))
    (a, power_a), (b, power_b) = states
    assert power_a == power_b
    for name in a._fields:
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)


def test_validate_planar_contacts_match_the_general_kernel():
    """The planar contact law is the general one in the plane: a run with colliding,
    sliding and rolling frictional bodies, dashpots and local damping (26 body-body
    contact onsets in 0.1 s) gives the trajectory of the general kernels up to round-off
    that the collisions amplify (measured: positions 6.5e-14, spins 2.2e-12 relative at
    0.1 s; 1e-11 and 6e-9 at 0.15 s)."""
    runs = []
    for planar in (True, False):
        sim = _planar_scene(damping=0.05, record_pairs=True)
        sim.planar_kernels = planar
        res = sim.run(until=0.1)
        runs.append(sim)
    assert np.sum((res.events.body_j >= 0) & (res.events.kind == ONSET)) >= 20
    a, b = runs
    assert a.settings.planar and not b.settings.planar
    scale = np.abs(b.bodies.pos).max()
    assert np.abs(a.bodies.pos - b.bodies.pos).max() < 1e-12 * scale
    assert np.abs(a.bodies.omega - b.bodies.omega).max() < 1e-10 * np.abs(b.bodies.omega).max()
    c = a.contacts
    assert c.active[: c.n[0]].sum() > 0 and np.abs(c.shear[: c.n[0]]).max() > 0
    assert np.all(c.shear[: c.n[0], 1] == 0.0)  # the shear stays in the plane exactly
    e_a, e_b = a.energy(), b.energy()
    for name in ("kinetic_translational", "elastic_normal", "dissipated_friction", "total"):
        assert e_a[name] == pytest.approx(e_b[name], rel=1e-9, abs=1e-15)


def test_planar_spheres_lie_in_the_plane_exactly():
    sim = _planar_scene(y=0.01)
    sim.run(until=0.02)
    y = sim.sphere_positions()[:, 1]
    np.testing.assert_array_equal(y, sim.bodies.pos[sim.sphere_body, 1])
    assert y == pytest.approx(0.01, rel=1e-15)


def test_state_saved_without_the_planar_setting_loads(tmp_path):
    """Checkpoints written before settings.planar existed still load and run."""
    sim = _planar_scene()
    sim.run(n_steps=100)
    state = {k: v for k, v in sim.get_state().items() if k != "settings.planar"}
    restored = Simulation.from_state(state)
    restored.set_state(state)
    restored.run(n_steps=100)
    sim.run(n_steps=100)
    np.testing.assert_array_equal(restored.bodies.pos, sim.bodies.pos)


angles = st.floats(-math.pi, math.pi)


@settings(deadline=None, max_examples=200)
@given(
    theta=angles,
    turn=st.floats(-0.05, 0.05),
    s=st.floats(-1e-3, 1e-3).filter(lambda x: x == 0.0 or abs(x) > 1e-100),  # (|s|^2 > 0)
    kt=st.floats(1.0, 1e6),
    mu=st.one_of(st.just(0.0), st.floats(1e-6, 1.0)),
    fn=st.one_of(st.just(0.0), st.floats(1e-9, 10.0)),
)
def test_validate_planar_shear_law_is_the_general_one_in_the_plane(theta, turn, s, kt, mu, fn):
    """Carry a shear ``s t_old`` to a normal turned by ``turn`` in the xz plane and apply
    the Coulomb limit: the planar law's ``s_new t_new`` equals contact.rotate_shear then
    contact.cundall_strack on the 3-vector (spin 0) to round-off."""
    n_old = (math.cos(theta), 0.0, math.sin(theta))
    n_new = (math.cos(theta + turn), 0.0, math.sin(theta + turn))
    t_old = (n_old[2], 0.0, -n_old[0])  # e_y x n
    t_new = (n_new[2], 0.0, -n_new[0])
    u = [s * t for t in t_old]
    general = rotate_shear(*u, *n_new, 0.0)
    general = cundall_strack(*general, kt, mu, fn)
    s_new = carry_shear_planar(u[0], u[2], t_new[0], t_new[2])
    s_new = coulomb_limit_planar(s_new, kt, mu, fn)
    planar = [s_new * t for t in t_new]
    np.testing.assert_allclose(planar, general, rtol=0, atol=4e-16 * abs(s) + 1e-300)
    assert abs(s_new) <= abs(s) * (1 + 1e-15)
    assert kt * abs(s_new) <= mu * fn * (1 + 1e-12) or abs(s_new) == pytest.approx(abs(s))
