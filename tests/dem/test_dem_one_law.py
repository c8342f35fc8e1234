"""One contact law for every pair of shapes (dem/laws/point.py).

A contact point is a sphere of radius ``r`` -- a sphere, or the rounded corner of a box
with rounding ``r`` -- pressed into a partner.  The same point, at the same place with
the same velocity, must get the same force whichever driver finds it:
``contact.compute_forces`` (sphere-wall, sphere-sphere), ``boxes.box_forces`` (box-wall,
box-box, and box-sphere in the same table).  The moving body slides at
a fixed overlap (its height and its rotations blocked, no gravity) until the tangential
spring reaches the Coulomb limit; against a plane the force is then known in closed form:
``k_n delta`` along the normal and ``mu k_n delta`` against the sliding direction
(Cundall & Strack, Geotechnique 29, 47 (1979)).  And step by step: the same point
striking a plane while it slides and spins about the normal -- the onset, the dashpot,
the sticking spring turned by the spin -- gets the same force at every step through the
sphere-wall, box-wall and box-box drivers.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from dominowave.dem import Material, Scene

R = 0.003  # radius of the contact point's sphere [m]
DELTA = 1e-4  # overlap [m]
KN, MU = 1e4, 0.5  # [N/m], [1]
V = np.array([0.3, 0.4, 0.0])  # sliding velocity [m/s]
DT, STEPS = 1e-5, 60  # the spring reaches the limit after about 10 steps
HALF = np.array([0.012, 0.008, 0.006])  # half-extents of the moving box [m]
TILT = Rotation.from_rotvec([0.3, 0.2, 0.1]).as_matrix()  # generic: one corner lowest
MASS = 0.05  # of every moving body [kg]


def _scene():
    scene = Scene(gravity=(0.0, 0.0, 0.0))
    # restitution 1: no dashpot, so that the force does not depend on the bodies' inertia;
    # the density gives a sphere of radius R the mass MASS (the box is given it)
    density = MASS / (4.0 / 3.0 * np.pi * R**3)
    mat = scene.add_material(Material(density=density, kn=KN, friction=MU, restitution=1.0))
    return scene, mat


def _lowest_corner():
    """Offset [m] (3,) from the centre of the box of :data:`HALF` turned by :data:`TILT`
    to the centre of its lowest corner's rounding sphere."""
    corners = [TILT @ ((2 * np.array(s) - 1) * (HALF - R)) for s in np.ndindex(2, 2, 2)]
    return min(corners, key=lambda c: c[2])


def _moving(scene, mat, shape, at):
    """The moving body: a sphere, or a box whose lowest corner sphere is centred at ``at``."""
    options = {"velocity": V, "blocked": "z rx ry rz"}
    if shape == "sphere":
        return scene.add_sphere(at, R, mat, **options)
    centre = at - _lowest_corner()
    return scene.add_box(centre, HALF, R, mat, orientation=TILT, mass=MASS, **options)


def _force(moving_shape, partner):
    """Force [N] (3,) on the moving body after :data:`STEPS` steps, and the simulation."""
    scene, mat = _scene()
    fixed = "x y z rx ry rz"
    if partner == "wall":
        scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), mat)
    elif partner == "box":  # a large fixed box, its top face at z = 0
        scene.add_box((0.0, 0.0, -0.01), (0.05, 0.05, 0.01), R, mat, blocked=fixed)
    else:  # a fixed sphere of radius 2 R, its top at z = 0
        scene.add_sphere((0.0, 0.0, -2 * R), 2 * R, mat, blocked=fixed)
    b = _moving(scene, mat, moving_shape, np.array([0.0, 0.0, R - DELTA]))
    sim = scene.build(dt=DT, overlap_tolerance=2 * DELTA / R)  # (it starts pressed in)
    sim.planar_kernels = False
    sim.run(n_steps=STEPS)
    return sim.bodies.force[b].copy(), sim


def _coulomb_on_a_plane():
    """The sliding point's force on a plane z = 0 [N] (3,): ``k_n delta`` up (two bodies
    of one material given ``k_n``: the pair's spring is ``k_n``), ``mu k_n delta`` against
    the velocity."""
    fn = KN * DELTA
    return np.array([*(-MU * fn * V[:2] / np.linalg.norm(V[:2])), fn])


@pytest.mark.parametrize(
    "moving, partner",
    [("sphere", "wall"), ("box", "wall"), ("box", "box")],
)
def test_validate_a_point_sliding_on_a_plane_gets_the_coulomb_force(moving, partner):
    np.testing.assert_allclose(_force(moving, partner)[0], _coulomb_on_a_plane(), rtol=1e-9)


def test_a_point_on_a_sphere_gets_the_same_force_from_both_drivers():
    on_sphere, sim = _force("sphere", "sphere")
    on_box, _ = _force("box", "sphere")
    # sliding: the tangential force is mu times the normal one, whatever the normal's turn
    (c,) = np.flatnonzero(sim.contacts.overlap[: sim.contacts.n[0]] > 0.0)
    fn = sim.contacts.fn[c]
    assert np.linalg.norm(on_sphere) == pytest.approx(fn * np.hypot(1.0, MU), rel=1e-9)
    np.testing.assert_allclose(on_box, on_sphere, rtol=1e-9, atol=1e-12)


def _striking(partner, moving_shape):
    """Force [N] (F, 3) on a point striking the plane z = 0 (a wall, or a fixed box's
    face) at every step, sliding and spinning about the normal, and the simulation.  The
    box stands on a corner right below its centre (a body diagonal vertical), so that a
    force at the point has no torque about the normal, as on the sphere."""
    scene = Scene(gravity=(0.0, 0.0, 0.0))
    density = MASS / (4.0 / 3.0 * np.pi * R**3)
    mat = scene.add_material(Material(density=density, kn=KN, friction=MU, restitution=0.5))
    if partner == "wall":
        scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), mat)
    else:
        scene.add_box((0.0, 0.0, -0.01), (0.05, 0.05, 0.01), R, mat, blocked="x y z rx ry rz")
    at = np.array([0.0, 0.0, R + 1e-6])  # (a micrometre above: the onset within a step)
    options = {
        "velocity": (0.03, 0.04, -0.2), "angular_velocity": (0.0, 0.0, 20.0),
        "blocked": "rx ry",
    }  # fmt: skip
    if moving_shape == "sphere":
        b = scene.add_sphere(at, R, mat, **options)
    else:
        diagonal = (HALF - R) / np.linalg.norm(HALF - R)
        down, _ = Rotation.align_vectors([[0.0, 0.0, -1.0]], [diagonal])
        centre = at + np.array([0.0, 0.0, np.linalg.norm(HALF - R)])
        b = scene.add_box(centre, HALF, R, mat, orientation=down.as_matrix(), mass=MASS, **options)
    sim = scene.build(dt=DT)
    sim.planar_kernels = False
    forces = []
    for _ in range(150):
        sim.run(n_steps=1)
        forces.append(sim.bodies.force[b].copy())
    return np.array(forces), sim


@pytest.mark.parametrize("partner", ["wall", "box"])
def test_a_striking_spinning_point_gets_the_same_force_at_every_step(partner):
    """On a wall: contact.compute_forces (sphere) and boxes.box_forces (box); on a fixed
    box's face (a wall to the dashpot too: boxes.inverse_mass_at):
    boxes.box_forces both (its box-sphere rows and its box-box rows)."""
    on_sphere, sim = _striking(partner, "sphere")
    on_box, _ = _striking(partner, "box")
    # the run holds an onset, the dashpot and a shear spring turned by the spin
    touching = np.flatnonzero(on_sphere[:, 2] > 0.0)
    assert 0 < touching[0] < 5 and touching.size == on_sphere.shape[0] - touching[0]
    rows = sim.contacts if partner == "wall" else sim.boxes.rows
    assert np.any(rows.fn_viscous[: rows.n[0]] != 0.0)
    first, last = on_sphere[touching[0], :2], on_sphere[-1, :2]
    turn = np.arctan2(first[0] * last[1] - first[1] * last[0], first @ last)
    assert abs(turn) > 1e-3
    scale = np.abs(on_sphere).max()
    np.testing.assert_allclose(on_box, on_sphere, rtol=1e-9, atol=1e-12 * scale)
