"""Rounded-cuboid contacts in the engine (dem/boxes.py), validations 5-7 of issue 13:
a contact whose touching feature pair changes (an edge or corner sliding over a corner),
stacks and rows of boxes at rest, and the limit of sharp edges r -> 0."""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from dominowave.dem import Material, Scene
from reference.sliding_contact import sliding_contact

G = 9.81
RHO = 1000.0

# ----------------------------------------------------------------- 5. feature changes

KN, KT_RATIO, MU = 1e4, 0.8, 0.3
HALF_B, R_B = np.array([0.02, 0.01, 0.01]), 0.001  # the fixed box
HALF_A, R_A = np.array([0.01, 0.01, 0.005]), 0.001  # the driven one
SPEED = 1.0  # [m/s] along +x
DEPTH = 2e-4  # overlap while A's lowest feature is over B's top face [m]


def _corners(half):
    return np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * half


def _sliding_scene(planar):
    """Box B fixed at the origin; box A, turned so that a corner (planar: the edge along
    y, i.e. a corner of the rectangle) is lowest, driven at SPEED along +x with all its
    DOFs blocked, that corner at depth DEPTH into B's top face, 10 mm before B's edge."""
    if planar:
        R = Rotation.from_rotvec([0.0, math.radians(30.0), 0.0]).as_matrix()
    else:
        R = (Rotation.from_rotvec([0.0, 0.0, math.radians(20.0)])
             * Rotation.from_rotvec([0.5, 0.6, 0.0])).as_matrix()  # fmt: skip
    core_a, core_b = HALF_A - R_A, HALF_B - R_B
    lowest = (_corners(core_a) @ R.T)[:, 2].min()
    height = core_b[2] + R_A + R_B - DEPTH - lowest
    scene = Scene(gravity=(0.0, 0.0, 0.0))
    m = scene.add_material(Material(density=RHO, kn=KN, kt_ratio=KT_RATIO, friction=MU))
    every = "x y z rx ry rz"
    scene.add_box((0.0, 0.0, 0.0), HALF_B, R_B, m, blocked=every)
    scene.add_box((-0.01, 0.0, height), HALF_A, R_A, m, orientation=R, blocked=every,
                  velocity=(SPEED, 0.0, 0.0))  # fmt: skip
    return scene, R, core_a, core_b


@pytest.mark.parametrize(
    "planar",
    [
        True,
        pytest.param(
            False,
            marks=pytest.mark.xfail(
                strict=True,
                reason="3D: when a vertex crosses the side plane of the reference face, the "
                "clipped incident face gains two corners at nearly full depth (1 point -> 2): "
                "the normal force jumps by ~80 % for a few steps (docs/dem.md)",
            ),
        ),
    ],
)
def test_validate_corner_sliding_over_a_corner_keeps_force_and_energy_smooth(planar):
    """A corner of box A slides at constant velocity, in full slip, along B's top face and
    over B's rounded edge until the bodies part: the touching feature pair changes from
    corner-face to corner-corner (the clip point, then the exact vertex-edge point; the
    contact's feature key changes twice).  Against the quasi-static force of the exact core
    distance (reference.sliding_contact, eq F; planar: twice, for the two ends of the
    edge along y): every step's contact force and stored energy to 1e-6 of their maxima,
    and no step changes the force by more than the reference does (the shear history is
    carried across the key changes)."""
    scene, R, core_a, core_b = _sliding_scene(planar)
    sim = scene.build(safety=0.05)
    assert sim.planar == planar
    dt = sim.dt
    kt = KT_RATIO * KN
    count = 2.0 if planar else 1.0
    force, ref_force, energy, ref_energy, keys = [], [], [], [], []
    while True:
        x = sim.bodies.pos[1].copy()  # the step's forces act at these positions
        f_ref, e_ref, delta = sliding_contact(x, R, core_a, R_A, np.zeros(3), np.eye(3), core_b,
                                              R_B, (SPEED, 0.0, 0.0), KN, kt, MU)  # fmt: skip
        sim.run(n_steps=1)
        if delta <= 0.0 and len(force) > 0:
            break
        e = sim.energy()
        force.append(sim.bodies.force[1].copy())
        energy.append(e["elastic_normal"] + e["elastic_tangential"])
        ref_force.append(count * f_ref)
        ref_energy.append(count * e_ref)
        rows = sim.boxes.rows
        keys.append(tuple(rows.key[: rows.n[0]]))
    force, ref_force = np.array(force), np.array(ref_force)
    energy, ref_energy = np.array(energy), np.array(ref_energy)
    n_changes = sum(keys[k] != keys[k - 1] for k in range(1, len(keys)))
    assert n_changes >= 2  # the feature pair did change
    # (the tangential spring loads to the Coulomb limit in the first steps: from then on)
    loaded = math.ceil(MU * KN * DEPTH / (kt * SPEED * dt)) + 1
    scale = np.abs(ref_force).max()
    err = np.abs(force - ref_force)[loaded:].max()
    assert err < 1e-6 * scale
    assert np.abs(energy - ref_energy)[loaded:].max() < 1e-6 * ref_energy.max()
    jump = np.abs(np.diff(force[loaded:], axis=0)).max()
    ref_jump = np.abs(np.diff(ref_force[loaded:], axis=0)).max()
    assert jump <= ref_jump * (1 + 1e-6)
