"""The contact-force recorder for box contacts (``record_contact_forces=True`` with boxes,
dem.boxes.box_contact_forces) and the peak force per body pair: each recorded force
checked against an independent quantity (the weight of a resting box, the momentum a
collision transfers)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from dominowave.dem import Material, Scene

G = 9.81
RHO = 1000.0


@pytest.mark.parametrize("planar", [False, True])
def test_validate_resting_box_rows_carry_its_weight(planar):
    """A box settled flat on the floor: its floor rows (first = -(wall + 1), second =
    the box) sum to m g up (1e-9 relative), at points on the floor below its corners; a
    planar row is the sum of the two corners it stands for."""
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=RHO, kn=2e4, friction=0.5, restitution=0.3))
    wall = scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    half = np.array([0.012, 0.004, 0.024])
    scene.add_box((0.0, 0.0, half[2] + 0.002), half, 0.001, m, blocked="y rx rz" if planar else "")
    sim = scene.build(safety=0.05)
    assert sim.planar == planar
    res = sim.run(until=0.5, trajectory_every=1000, record_contact_forces=True)
    cf = res.contact_frames
    rows = cf.frame(res.times.size - 1)
    assert rows.stop - rows.start == (2 if planar else 4)
    assert np.all(cf.first[rows] == -(wall + 1)) and np.all(cf.second[rows] == 0)  # no spheres
    weight = sim.bodies.mass[0] * G
    total = cf.force[rows].sum(axis=0)
    np.testing.assert_allclose(total, [0.0, 0.0, weight], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(cf.force[rows][:, 2], weight / (2 if planar else 4), rtol=1e-9)
    core = half - 0.001
    np.testing.assert_allclose(np.abs(cf.point[rows][:, 0]), core[0], rtol=1e-9)
    assert np.all(np.abs(cf.point[rows][:, 2]) < 1e-5)  # midway through a micron overlap


def _collision(planar):
    """Two boxes, no gravity, the Hertz law: box 0 (tilted) hits box 1 at rest,
    off-centre, with friction and damping."""
    scene = Scene(gravity=(0.0, 0.0, 0.0), normal_law="hertz")
    m = scene.add_material(
        Material(density=RHO, young=2e7, poisson=0.3, friction=0.3, restitution=0.6)
    )
    half = np.array([0.01, 0.008, 0.015])
    blocked = "y rx rz" if planar else ""
    tilt = [0.0, 0.2, 0.0] if planar else [0.2, 0.3, -0.1]
    R = Rotation.from_rotvec(tilt).as_matrix()
    scene.add_box((0.0, 0.0, 0.0), half, 0.001, m, orientation=R, velocity=(0.4, 0.0, 0.05),
                  blocked=blocked)  # fmt: skip
    scene.add_box((0.035, 0.0, 0.004), half, 0.0015, m, blocked=blocked)
    return scene.build(safety=0.05, record_peak_force=True)


@pytest.mark.parametrize("planar", [False, True])
def test_validate_recorded_impulse_equals_the_momentum_change(planar):
    """Recorded every step, the forces on box 1 summed times dt equal its momentum change
    m (v_after - v_before) to round-off (the Hertz law: its force vanishes at zero
    overlap, so no end impulse of the linear law's onset/end averaging, which is not a
    row, laws.linear.end_impulse, is missing); the torque about its centre from the recorded
    points likewise equals the change of its angular momentum; the peak normal force of
    the pair is the largest recorded normal force of one point."""
    sim = _collision(planar)
    b = sim.bodies
    m1 = b.mass[1]
    res = sim.run(n_steps=20_000, trajectory_every=1, record_contact_forces=True)
    cf = res.contact_frames
    assert np.all(cf.first >= 0) and set(np.unique(cf.second)) == {1}  # box 0 on box 1 only
    assert cf.first.size > 50  # the collision lasted
    dp = m1 * b.vel_full[1]  # box 1 started at rest
    impulse = cf.force.sum(axis=0) * sim.dt
    np.testing.assert_allclose(impulse, dp, rtol=1e-9, atol=1e-9 * np.abs(dp).max())
    # angular momentum about box 1's centre: the force at the point, lever from the
    # centre at that frame
    frame = np.repeat(np.arange(res.times.size), np.diff(cf.start))
    arm = cf.point - res.positions[frame, 1]
    torque_impulse = np.cross(arm, cf.force).sum(axis=0) * sim.dt
    dL = b.angmom_full[1]
    scale = np.abs(dp).max() * 0.02
    np.testing.assert_allclose(torque_impulse, dL, atol=1e-9 * scale)
    # the peak normal force of one point: |F| of a row is between mult fn and
    # mult fn sqrt(1 + mu^2) (the Coulomb cone), mult = 2 for a planar row
    peak = sim.pairs.peak_normal_force[0, 1]
    assert peak == sim.pairs.peak_normal_force[1, 0]
    mult = 2.0 if planar else 1.0
    largest = np.linalg.norm(cf.force, axis=1).max()
    assert mult * peak <= largest * (1 + 1e-12) <= mult * peak * np.sqrt(1 + 0.3**2) * (1 + 1e-9)
    assert abs(dp).max() > 0.1 * m1 * 0.4  # a real collision
