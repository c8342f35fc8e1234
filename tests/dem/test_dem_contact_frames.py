"""The contact-force recorder (``Simulation.run(record_contact_forces=True)``).

Each recorded force is checked against an independent quantity: the weight of a resting
sphere, ``k_n * overlap`` from the recorded positions of a head-on collision, and the
momentum and angular-momentum changes of toppling clumps between two frames.
"""

import numpy as np
from dem_scenes import RHO, R, column, sphere_mass

from dominowave.dem import Material, Scene

G = 9.81


def test_recorder_is_off_by_default_and_changes_nothing(two_sphere_scene):
    """Off: no contact frames.  On: the same trajectory bit for bit."""
    plain = two_sphere_scene().build().run(until=0.02, trajectory_every=7)
    assert plain.contact_frames is None
    recorded = (
        two_sphere_scene().build().run(until=0.02, trajectory_every=7, record_contact_forces=True)
    )
    np.testing.assert_array_equal(recorded.positions, plain.positions)
    np.testing.assert_array_equal(recorded.velocities, plain.velocities)
    frames = recorded.contact_frames
    assert frames.start.shape == (recorded.times.size + 1,)
    assert frames.start[-1] == frames.first.size > 0
    assert np.all(np.diff(frames.start) >= 0)


def test_validate_resting_sphere_carries_its_weight():
    """A sphere settled on the floor: the recorded floor force is m g up (1e-9 relative),
    at the contact point midway through the overlap below the centre."""
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=RHO, kn=1e4, restitution=0.1))
    wall = scene.add_wall((0, 0, 0), (0, 0, 1), m)
    scene.add_sphere((0.001, 0.002, R), R, m)
    sim = scene.build()
    res = sim.run(until=0.05, trajectory_every=100, record_contact_forces=True)
    cf = res.contact_frames
    rows = cf.frame(res.times.size - 1)
    assert rows.stop - rows.start == 1
    assert cf.first[rows][0] == -(wall + 1) and cf.second[rows][0] == 0
    weight = sphere_mass() * G
    np.testing.assert_allclose(cf.force[rows][0], [0.0, 0.0, weight], rtol=1e-9, atol=1e-12)
    centre = res.positions[-1, 0]
    overlap = R - centre[2]
    np.testing.assert_allclose(overlap, weight / 1e4, rtol=1e-9)
    np.testing.assert_allclose(cf.point[rows][0], [0.001, 0.002, -overlap / 2], atol=1e-15)


def test_validate_head_on_force_is_kn_times_overlap(two_sphere_scene):
    """Head-on elastic collision recorded every step: force on the second sphere is
    ``k_n (2R - |x2 - x1|)`` along +x from the recorded positions; at the onset frame it
    is k_n times the overlap averaged over the kick interval (laws.linear.onset_averaged_overlap,
    with the free-flight approach speed 2 v)."""
    v, kn = 0.1, 1e4
    sim = two_sphere_scene(velocity=v, kn=kn).build()
    res = sim.run(until=0.03, trajectory_every=1, record_contact_forces=True)
    cf = res.contact_frames
    counts = np.diff(cf.start)
    assert set(counts) == {0, 1}
    in_contact = np.flatnonzero(counts)
    assert in_contact.size > 20  # the collision is resolved by many steps
    assert np.all(np.diff(in_contact) == 1)  # one collision
    assert np.all(cf.first == 0) and np.all(cf.second == 1)
    rows = cf.start[in_contact]
    overlap = 2 * R - (res.positions[in_contact, 1, 0] - res.positions[in_contact, 0, 0])
    force = cf.force[rows]
    np.testing.assert_allclose(force[:, 1:], 0.0, atol=1e-15)
    np.testing.assert_allclose(force[1:, 0], kn * overlap[1:], rtol=1e-12)
    ramp = 2 * v * sim.dt
    weight = 0.5 + overlap[0] / ramp
    np.testing.assert_allclose(force[0, 0], kn * 0.5 * ramp * weight**2, rtol=1e-9)
    # contact point: midway through the overlap
    mid = res.positions[in_contact, 0, 0] + R - overlap / 2
    np.testing.assert_allclose(cf.point[rows, 0], mid, rtol=0, atol=1e-15)


def _toppling_row():
    """Four planar clumps (columns of 5 spheres) on a frictional floor; the first is pushed."""
    scene = Scene(gravity=(0.0, 0.0, -G))
    m = scene.add_material(Material(density=RHO, kn=1e4, friction=0.3))
    scene.add_wall((0, 0, 0), (0, 0, 1), m)
    for k in range(4):
        scene.add_clump(
            column(5, base=(k * 6 * R, 0.0, R)),
            R,
            m,
            blocked="y rx rz",
            angular_velocity=(0.0, 12.0 if k == 0 else 0.0, 0.0),
        )
    return scene.build(safety=0.1)


def test_validate_recorded_forces_give_momentum_change_of_clumps():
    """Toppling clumps recorded every step.  Velocity Verlet gives, for every free body
    between frames n and n+1, ``m (v_{n+1} - v_n) = dt (F_n + F_{n+1}) / 2`` and
    ``I (omega_{n+1} - omega_n) = dt (T_n + T_{n+1}) / 2`` (about the free y axis), with
    F the sum of the recorded contact forces on the body plus its weight and T their
    torques about the centre of mass from the recorded contact points.  Intervals in which
    a contact of the body ends at step n or n+1 are skipped (the impulse that completes
    an ending contact, applied at the first step without overlap, is not recorded)."""
    sim = _toppling_row()
    body = sim.sphere_body
    nb = sim.n_bodies
    mass = sim.bodies.mass
    inertia = sim.bodies.axis_inertia
    res = sim.run(until=0.25, trajectory_every=1, record_contact_forces=True)
    cf = res.contact_frames
    nf = res.times.size
    force = np.zeros((nf, nb, 3))
    torque = np.zeros((nf, nb))
    keys = [[set() for _ in range(nb)] for _ in range(nf)]
    frame_of_row = np.repeat(np.arange(nf), np.diff(cf.start))
    for row, f in enumerate(frame_of_row):
        second = body[cf.second[row]]
        first = cf.first[row]
        on = [(second, cf.force[row])]
        if first >= 0:
            on.append((body[first], -cf.force[row]))
        for b, fvec in on:
            force[f, b] += fvec
            arm = cf.point[row] - res.positions[f, b]
            torque[f, b] += arm[2] * fvec[0] - arm[0] * fvec[2]  # y component of arm x F
            keys[f][b].add((int(first), int(cf.second[row])))
    force[..., 2] -= mass * G
    dt = sim.dt
    checked = clump_contacts = 0
    for f in range(nf - 1):
        for b in range(nb):
            ended = keys[f][b] - keys[f + 1][b] or (f > 0 and keys[f - 1][b] - keys[f][b])
            if ended:
                continue  # an end impulse (in F_n or F_{n+1}) is missing from the record
            dp = mass[b] * (res.velocities[f + 1, b] - res.velocities[f, b])
            impulse = 0.5 * dt * (force[f, b] + force[f + 1, b])
            scale = mass[b] * G * dt
            np.testing.assert_allclose(dp[[0, 2]], impulse[[0, 2]], rtol=0, atol=1e-9 * scale)
            dl = inertia[b] * (
                res.angular_velocities[f + 1, b, 1] - res.angular_velocities[f, b, 1]
            )
            np.testing.assert_allclose(
                dl, 0.5 * dt * (torque[f, b] + torque[f + 1, b]), rtol=0, atol=1e-9 * scale * R
            )
            checked += 1
            clump_contacts += any(k[0] >= 0 for k in keys[f][b])
    assert checked > 0.9 * (nf - 1) * nb
    assert clump_contacts > 100  # clump-clump collisions were among the checked intervals
