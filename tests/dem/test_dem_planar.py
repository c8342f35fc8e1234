"""The planar kernels (contact.compute_forces_planar, engine._advance_planar;
integrate.kick_body_planar, drift_body_planar, advance_body_planar): which scenes are
planar (dem/planar.py), and that the planar kernels are the general ones to the bit."""

import numpy as np
import pytest
from dem_scenes import RHO, R, column
from older_states import older_state

from dominowave.dem import ONSET, Material, Scene, Simulation
from dominowave.dem.engine import _advance_bodies
from dominowave.dem.integrate import drift, kick
from dominowave.dem.planar import planar_violation


def _planar_scene(
    y=0.0, sphere_blocked="y rx rz", damping=0.0, shear_kinematics="contact_point", **build
):
    """Four frictional columns in the plane ``y``, two tilted and spinning so that they
    topple onto their neighbours, and a sphere rolling with spin on a frictional floor."""
    scene = Scene(shear_kinematics=shear_kinematics)
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
            _advance_bodies(sim.bodies, s, 0, sim.bodies.mass.shape[0])
        power = kick(sim.bodies, s.gravity, s.dt, damping, True, planar)
        drift(sim.bodies, s.dt, planar)
        states.append((sim.bodies, power))
    (a, power_a), (b, power_b) = states
    assert power_a == power_b
    for name in a._fields:
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)


PHYSICAL = ("pos", "vel", "quat", "omega")  # (force y, torque x/z: round-off, unused)


def _assert_same_physics(a, b):
    """Bit-identical bodies and in-plane contact state; the components that are zero in a
    planar scene may differ by round-off (~1e-30) in the general kernel."""
    for name in PHYSICAL:
        np.testing.assert_array_equal(getattr(a.bodies, name), getattr(b.bodies, name), name)
    n = a.contacts.n[0]
    assert n == b.contacts.n[0]
    for name in ("i", "j", "overlap", "vn", "fn", "fn_viscous"):
        np.testing.assert_array_equal(getattr(a.contacts, name)[:n], getattr(b.contacts, name)[:n])
    np.testing.assert_array_equal(a.contacts.shear[:n, ::2], b.contacts.shear[:n, ::2])


@pytest.mark.parametrize(
    ("y", "track_energy", "shear_kinematics"),
    [
        (0.0, True, "contact_point"),
        (0.0, False, "contact_point"),
        (0.0123, False, "contact_point"),
        (0.0, True, "yade"),
        (0.0123, False, "yade"),
    ],
)
def test_validate_planar_kernels_are_the_general_ones_to_the_bit(y, track_energy, shear_kinematics):
    """The planar kernels are the general ones with the y components dropped (they are
    zero, or round-off of ~1e-17 m in the general kernels' sphere positions, which no
    in-plane result feels): a run with colliding, sliding and rolling frictional bodies,
    dashpots and local damping (body-body onsets, sliding bases, frictional pairs) has the
    general kernels' trajectory bit for bit -- with the energy ledger (planar contact
    power, separate kick and drift) and without it (the fused planar body pass), in the
    plane y = 0 and off it; with either shear kinematics."""
    runs = []
    for planar in (True, False):
        sim = _planar_scene(
            y=y,
            damping=0.05,
            shear_kinematics=shear_kinematics,
            record_pairs=True,
            track_energy=track_energy,
        )
        sim.planar_kernels = planar
        res = sim.run(until=0.2)
        runs.append(sim)
    a, b = runs
    assert a.settings.planar and not b.settings.planar
    assert np.sum((res.events.body_j >= 0) & (res.events.kind == ONSET)) >= 40
    c = b.contacts
    assert (c.overlap[: c.n[0]] > 0.0).sum() > 0 and np.abs(c.shear[: c.n[0], ::2]).max() > 0
    _assert_same_physics(a, b)
    e_a, e_b = a.energy(), b.energy()
    assert e_a.keys() == e_b.keys()
    for name in e_a:  # (nan: dissipated energies without the ledger)
        assert e_a[name] == e_b[name] or (np.isnan(e_a[name]) and np.isnan(e_b[name]))


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
    restored = Simulation.from_state(older_state(sim.get_state(), 1))
    assert restored.planar_kernels
    restored.run(n_steps=100)
    sim.run(n_steps=100)
    np.testing.assert_array_equal(restored.bodies.pos, sim.bodies.pos)


def test_planar_kernels_switch_is_checkpointed():
    sim = _planar_scene()
    sim.planar_kernels = False
    restored = Simulation.from_state(sim.get_state())
    assert not restored.planar_kernels
    restored.run(n_steps=10)
    assert not restored.settings.planar


def test_coplanarity_is_to_round_off_only():
    """Bodies count as coplanar to a few ulp of y (the centre of mass of spheres at y0),
    spheres as in their body's plane to 1e-13 of its size: a real tilt is not planar, a
    single sphere off y = 0 is."""
    sim = _planar_scene(y=0.7)
    assert sim.planar
    sim.bodies.pos[2, 1] += 1e-12  # a real offset, felt by the general kernels
    assert "body 2 lies in the plane" in planar_violation(sim.bodies, sim.spheres, sim.walls)
    scene = Scene()
    m = scene.add_material(Material(density=RHO, kn=1e4))
    for k in range(7):  # (a sphere's centre of mass is its centre to 1 ulp only)
        scene.add_sphere((0.03 * k, 0.3, R), R, m, blocked="y rx rz")
    single = scene.build()
    assert single.planar, planar_violation(single.bodies, single.spheres, single.walls)
