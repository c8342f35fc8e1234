"""Engine behaviour: contact events, held bodies, stop conditions, neighbour search,
checkpoints, bad input and aborts."""

from collections import namedtuple

import numpy as np
import pytest
from dem_scenes import RHO, R, column
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

from dominowave.dem import END, ONSET, Material, Scene, Simulation, StopCondition, engine, integrate
from dominowave.dem.contact import (
    _candidate_pairs,
    build_verlet_list,
    needs_rebuild,
    pair_properties,
)
from dominowave.dem.energy import ENERGY_NAMES, N_MECHANICAL


def _box_scene(n=60, seed=0, friction=0.3, damping=0.0, restitution=0.5, **build):
    """Spheres dropped into a box of 5 walls (settling packing)."""
    rng = np.random.default_rng(seed)
    scene = Scene()
    m = scene.add_material(
        Material(density=RHO, kn=1e4, friction=friction, restitution=restitution)
    )
    L = 0.06
    scene.add_wall((0, 0, 0), (0, 0, 1), m)
    scene.add_wall((0, 0, 0), (1, 0, 0), m)
    scene.add_wall((L, 0, 0), (-1, 0, 0), m)
    scene.add_wall((0, 0, 0), (0, 1, 0), m)
    scene.add_wall((0, L, 0), (0, -1, 0), m)
    grid = np.stack(np.meshgrid(*[np.arange(5)] * 3, indexing="ij"), -1).reshape(-1, 3)
    for k in range(n):
        radius = R * rng.uniform(0.7, 1.0)
        centre = (grid[k] + 0.5) * 2.4 * R + np.array([0.0, 0.0, 0.001])
        scene.add_sphere(centre, radius, m, velocity=rng.normal(size=3) * 0.05)
    return scene.build(safety=0.1, damping=damping, **build)


def test_validate_neighbour_list_finds_every_contact():
    """During settling, the active contacts equal the brute-force overlaps.

    Contacts refer to the positions before the last drift; pairs whose gap is within the
    last step's relative displacement are left out of the comparison."""
    sim = _box_scene(n=100, damping=0.2)
    compared = 0
    for k in range(5):
        sim.run(until=0.1 * (k + 1))
        pos = sim.sphere_positions()
        r = sim.spheres.radius
        pairs = cKDTree(pos).query_pairs(2.5 * r.max(), output_type="ndarray")
        gap = np.linalg.norm(pos[pairs[:, 0]] - pos[pairs[:, 1]], axis=1) - r[pairs].sum(axis=1)
        speed = np.linalg.norm(sim.bodies.vel, axis=1)[sim.sphere_body]
        margin = 2.0 * speed[pairs].sum(axis=1) * sim.dt
        clear = np.abs(gap) > margin
        overlapping = {tuple(p) for p in pairs[clear & (gap < 0)]}
        c = sim.contacts
        n = c.n[0]
        active = {
            (int(i), int(j))
            for i, j, a in zip(c.i[:n], c.j[:n], c.overlap[:n] > 0.0, strict=True)
            if a and j >= 0
        }
        assert overlapping <= active
        assert not ({tuple(p) for p in pairs[clear & (gap > 0)]} & active)
        compared += len(overlapping)
    assert compared > 50


def _random_walled_scene(seed):
    """Random clumps of 1-4 spheres of mixed radii in 3D (some layers flat in y) with 1-3
    walls of random orientation; skin of the order of the radii."""
    rng = np.random.default_rng(seed)
    scene = Scene()
    mats = [
        scene.add_material(Material(density=RHO, kn=rng.uniform(1e3, 1e5), friction=0.3))
        for _ in range(2)
    ]
    L = 0.03
    for _ in range(rng.integers(1, 4)):
        normal = rng.normal(size=3)
        normal /= np.linalg.norm(normal)
        scene.add_wall(-normal * L * rng.uniform(0.7, 1.1), normal, mats[0])
    for _ in range(rng.integers(40, 100)):
        k = int(rng.integers(1, 5))
        base = rng.uniform(-L, L, 3)
        if rng.uniform() < 0.3:
            base[1] = 0.0
        centres = base + rng.normal(size=(k, 3)) * 0.8 * R
        scene.add_clump(centres, R * rng.uniform(0.25, 1.2, k), mats[int(rng.integers(0, 2))])
    skin = R * rng.uniform(0.05, 2.0)
    return scene.build(skin=skin, overlap_tolerance=1e9, record_pairs=False), rng


def _brute_force_keys(spheres, walls, skin):
    """Keys ``i * (ns + nw) + jj`` of all pairs closer than the skin, by testing every pair
    (the arithmetic of the cell search: centre distance squared, wall distance summed)."""
    pos, radius, body = spheres.pos, spheres.radius, spheres.body
    ns, nw = pos.shape[0], walls.point.shape[0]
    i, j = np.triu_indices(ns, 1)
    d = pos[j] - pos[i]
    reach = radius[i] + radius[j] + skin
    close = (d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1] + d[:, 2] * d[:, 2] < reach * reach) & (
        body[i] != body[j]
    )
    keys = [i[close] * (ns + nw) + j[close]]
    for w in range(nw):
        off = (pos - walls.point[w]) * walls.normal[w]
        s = np.flatnonzero(off[:, 0] + off[:, 1] + off[:, 2] < radius + skin)
        keys.append(s * (ns + nw) + ns + w)
    return np.sort(np.concatenate(keys))


@pytest.mark.parametrize("seed", range(6))
def test_validate_verlet_build_matches_brute_force(seed):
    """The Verlet list (cell search, counting sort by first index, in-place merge) holds
    exactly the brute-force pairs in key order, and a rebuild after the bodies moved keeps
    the whole history of every pair listed before (its row's point and normal too) and
    starts new pairs inactive, without overlap."""
    sim, rng = _random_walled_scene(seed)
    spheres, walls, bodies, c = sim.spheres, sim.walls, sim.bodies, sim.contacts
    ns, nw = spheres.pos.shape[0], walls.point.shape[0]

    def listed_keys():
        n = c.n[0]
        j = c.j[:n]
        return c.i[:n] * (ns + nw) + np.where(j >= 0, j, ns - j - 1), n

    keys, n = listed_keys()
    np.testing.assert_array_equal(keys, _brute_force_keys(spheres, walls, sim.settings.skin))
    assert n > 20 and (c.j[:n] < 0).any()
    # an arbitrary history for the listed pairs
    fields = ("shear", "kn", "kt", "mu", "cn", "overlap", "vn", "fn", "fn_viscous", "point",
              "normal")  # fmt: skip
    for f in fields:
        getattr(c, f)[:n] = rng.normal(size=getattr(c, f)[:n].shape)
    before = {f: getattr(c, f)[:n].copy() for f in fields}
    for _ in range(3):  # pairs enter and leave the list
        bodies.pos[:] += rng.normal(size=bodies.pos.shape) * 2.0 * sim.settings.skin
        integrate.update_sphere_positions(bodies, spheres, False)
        old_keys = keys
        assert build_verlet_list(spheres, walls, bodies, sim.mats, c, sim.settings.skin) > 0
        keys, n = listed_keys()
        np.testing.assert_array_equal(keys, _brute_force_keys(spheres, walls, sim.settings.skin))
        kept, new_at, old_at = np.intersect1d(keys, old_keys, return_indices=True)
        assert 0 < kept.size < keys.size
        for f in fields:
            np.testing.assert_array_equal(getattr(c, f)[new_at], before[f][old_at])
        fresh = np.setdiff1d(np.arange(n), new_at)
        assert fresh.size > 0
        assert not c.shear[fresh].any()
        assert not c.fn_viscous[fresh].any() and not c.overlap[fresh].any()
        props = np.empty(4)
        for k in fresh:  # a new pair's properties from the materials
            pair_properties(c.i[k], c.j[k], spheres, walls, bodies, sim.mats, props)
            assert (c.kn[k], c.kt[k], c.mu[k], c.cn[k]) == tuple(props)
        before = {f: getattr(c, f)[:n].copy() for f in fields}


@pytest.mark.parametrize("seed", range(4))
def test_validate_search_of_the_active_spheres_matches_brute_force(seed):
    """The search around active spheres only (contact._scan_cells with ``active``: every
    neighbour cell of each active sphere) lists exactly the brute-force pairs with an
    active member -- two spheres of which one is active, an active sphere and a wall --
    in key order."""
    sim, rng = _random_walled_scene(seed)
    spheres, walls = sim.spheres, sim.walls
    ns, nw = spheres.pos.shape[0], walls.point.shape[0]
    skin = sim.settings.skin
    full = _brute_force_keys(spheres, walls, skin)
    for share in (0.0, 0.1, 0.5, 1.0):
        active = (rng.random(ns) < share).astype(np.uint8)
        i, j = full // (ns + nw), full % (ns + nw)
        partner_active = np.where(j < ns, active[np.minimum(j, ns - 1)], 0)
        expected = full[(active[i] == 1) | (partner_active == 1)]
        keys, first = _candidate_pairs(spheres, walls, skin, active)
        np.testing.assert_array_equal(keys, expected)
        np.testing.assert_array_equal(first, keys // (ns + nw))
    np.testing.assert_array_equal(_candidate_pairs(spheres, walls, skin)[0], full)


def test_validate_energy_balance_with_friction_and_damping():
    """Settling with friction, dashpots and local damping: kinetic + potential + elastic
    + dissipated stays constant to 1e-4 of the dissipated energy at the default safety
    0.02, and the error is second order in dt."""
    errors = []
    for safety in (0.04, 0.02):
        sim = _box_scene(damping=0.1)
        sim.settings = sim.settings._replace(dt=safety * sim.critical_dt)
        res = sim.run(until=0.2, energy_every=50)
        e = res.energy
        assert e["dissipated_friction"][-1] > 0 and e["dissipated_damping"][-1] > 0
        assert e["dissipated_viscous"][-1] > 0
        dissipated = sum(
            e[k][-1] for k in ("dissipated_friction", "dissipated_viscous", "dissipated_damping")
        )
        errors.append(np.max(np.abs(e["total"] - e["total"][0])) / dissipated)
    assert errors[1] < 1e-4
    assert errors[0] / errors[1] > 3.0  # ~4 for a second-order balance


@pytest.mark.parametrize("seed", [3, 4, 5])
def test_validate_energy_conserved_elastic_chain(seed):
    """A row of 10 spheres between two walls, no friction, no damping, 1e5 steps at the
    default time step: the total energy changes by less than 1e-5."""
    rng = np.random.default_rng(seed)
    scene = Scene(gravity=(0, 0, 0))
    m = scene.add_material(Material(density=RHO, kn=1e4))
    n = 10
    L = n * 3 * R
    scene.add_wall((0, 0, 0), (1, 0, 0), m)
    scene.add_wall((L, 0, 0), (-1, 0, 0), m)
    for k in range(n):
        scene.add_sphere(((k + 0.5) * 3 * R, 0, 0), R, m, velocity=(rng.normal() * 0.1, 0, 0))
    sim = scene.build()
    res = sim.run(n_steps=100_000, energy_every=1000)
    assert res.events.time.size > 40
    e = res.energy["total"]
    assert abs(e[-1] / e[0] - 1) < 1e-5


def _bodies_moved(pos0, quat0, pos1, quat1, extent):
    """A one-body ``Bodies``-like tuple for :func:`needs_rebuild` (COM, orientation, and
    the same at the last list build)."""
    from collections import namedtuple

    B = namedtuple("B", "pos pos_at_build quat quat_at_build extent mass")
    return B(
        pos=np.array([pos1], float),
        pos_at_build=np.array([pos0], float),
        quat=np.array([quat1], float),
        quat_at_build=np.array([quat0], float),
        extent=np.array([extent], float),
        mass=np.ones(1),
    )


@settings(max_examples=200, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    shift=st.floats(0.0, 1e-3),
    angle=st.floats(0.0, 0.3),
)
def test_validate_displacement_bound_covers_every_member_sphere(seed, shift, angle):
    """The per-body rebuild test bounds the largest displacement of any member sphere,
    ``|x1 - x0 + (R1 - R0) u|`` computed directly, for random rigid motions; and it is
    tight: for a pure rotation the farthest sphere on the circle of the rotation moves by
    exactly the bound ``2 sin(theta/2) |u|``."""
    rng = np.random.default_rng(seed)
    members = rng.normal(size=(12, 3)) * 0.01
    extent = np.linalg.norm(members, axis=1).max()
    r0 = Rotation.random(random_state=rng)
    turn = Rotation.from_rotvec(angle * Rotation.random(random_state=rng).apply([1, 0, 0]))
    r1 = turn * r0
    x0 = rng.normal(size=3)
    x1 = x0 + shift * rng.normal(size=3) / np.sqrt(3)
    moved = np.linalg.norm(x1 + r1.apply(members) - x0 - r0.apply(members), axis=1).max()

    def quat(r):  # scipy (x, y, z, w) -> (w, x, y, z)
        x, y, z, w = r.as_quat()
        return [w, x, y, z]

    bodies = _bodies_moved(x0, quat(r0), x1, quat(r1), extent)
    assert needs_rebuild(bodies, 2.0 * (moved * (1.0 - 1e-9) - 1e-15), 1) or moved < 1e-15
    # pure rotation: the sphere at |u| = extent perpendicular to the axis moves by the bound
    axis = turn.as_rotvec() / angle if angle > 1e-12 else np.array([1.0, 0.0, 0.0])
    u = np.cross(axis, rng.normal(size=3))
    u *= extent / np.linalg.norm(u)
    exact = np.linalg.norm(turn.apply(u) - u)
    bodies = _bodies_moved(x0, quat(r0), x0, quat(r1), extent)
    assert not needs_rebuild(bodies, 2.0 * (exact * (1.0 + 1e-6) + 1e-12), 1)
    if angle > 1e-6:
        assert needs_rebuild(bodies, 2.0 * exact * (1.0 - 1e-6), 1)


def test_validate_results_independent_of_verlet_skin():
    """The skin changes only how often the list is rebuilt and how many inactive pairs it
    holds: inactive pairs contribute nothing and active ones keep their key order, so the
    trajectory is bit-identical for skins from 0.1 to 3 sphere radii, and with the
    recorders on or off (on, the loop hands back to Python to grow its buffers).  Between builds
    the engine moves only the spheres of the list; after a run every sphere is placed."""
    final = []
    for skin, record in ((0.1 * R, True), (0.3 * R, True), (3.0 * R, True), (0.3 * R, False)):
        sim = _box_scene(n=60, damping=0.2, skin=skin, record_pairs=record)
        sim.run(until=0.05)
        final.append((sim.positions(), sim.sphere_positions(), sim.rec.n_rebuilds[0]))
        local = sim.spheres.local
        rot = sim.bodies.rot[sim.sphere_body]
        placed = sim.bodies.pos[sim.sphere_body] + np.einsum("nij,nj->ni", rot, local)
        np.testing.assert_allclose(sim.sphere_positions(), placed, rtol=0, atol=1e-16)
    for pos, spheres, _ in final[1:]:
        np.testing.assert_array_equal(pos, final[0][0])
        np.testing.assert_array_equal(spheres, final[0][1])
    assert final[0][2] > final[1][2] > final[2][2]  # the skins did change the builds
    # (the last run, without recorders, never hands back to Python before its first step)


def test_validate_recorders_do_not_change_a_clump_trajectory():
    """Toppling planar columns (clumps: member centres are placed from COM + R u, which
    differ from the scene's given centres by round-off) give bit-identical trajectories
    with the recorders on (the loop hands back to Python to grow its buffers, even before
    the first step) and off."""
    runs = []
    for record in (True, False):
        scene = Scene()
        floor = scene.add_material(Material(density=RHO, kn=1e4, friction=0.3))
        face = scene.add_material(Material(density=RHO, kn=1e4, friction=0.0))
        scene.add_wall((0, 0, 0), (0, 0, 1), floor)
        for c in range(4):
            tilt = 0.3 if c % 2 == 0 else 0.0
            scene.add_clump(
                column(6, base=(0.04 * c, 0.0, R), tilt=tilt),
                R,
                [floor] + [face] * 5,
                blocked="y rx rz",
                angular_velocity=(0.0, 2.0 if c % 2 == 0 else 0.0, 0.0),
            )
        sim = scene.build(record_pairs=record)
        sim.run(n_steps=4000)
        runs.append(sim)
    assert runs[0].rec.ev_n[0] > 0  # contacts were logged
    np.testing.assert_array_equal(runs[0].bodies.pos, runs[1].bodies.pos)
    np.testing.assert_array_equal(runs[0].bodies.omega, runs[1].bodies.omega)


@pytest.mark.parametrize(("blocked", "dy"), [("y rx rz", 0.002), ("y rx rz", 0.0), ("", 0.002)])
def test_validate_fused_body_pass_is_the_separate_kick_and_drift(blocked, dy):
    """Steps in which nothing reads the state between kick and drift take one fused pass
    over the bodies (engine._advance_bodies); steps with a check take kick, checks, drift.
    With a check every step (check_every=1) every step is separate: the trajectories of
    fixed-axis clumps in parallel planes (general kernels), in one plane (a planar scene:
    integrate.advance_body_planar) and of free clumps must be bit-identical either way."""
    runs = []
    for check_every in (100, 1):
        scene = Scene()
        floor = scene.add_material(Material(density=RHO, kn=1e4, friction=0.3))
        face = scene.add_material(Material(density=RHO, kn=1e4, friction=0.2))
        scene.add_wall((0, 0, 0), (0, 0, 1), floor)
        for c in range(4):
            scene.add_clump(
                column(6, base=(0.04 * c, dy * c, R), tilt=0.3 if c % 2 == 0 else 0.0),
                R,
                [floor] + [face] * 5,
                blocked=blocked,
                angular_velocity=(0.0, 2.0 if c % 2 == 0 else 0.0, 0.0),
            )
        sim = scene.build(record_pairs=False, track_energy=False, check_every=check_every)
        sim.run(until=0.05)
        assert sim.settings.planar == (blocked != "" and dy == 0.0)
        runs.append(sim)
    assert runs[0].rec.n_rebuilds[0] > 1  # bodies moved: the Verlet test was exercised
    np.testing.assert_array_equal(runs[0].bodies.pos, runs[1].bodies.pos)
    np.testing.assert_array_equal(runs[0].bodies.quat, runs[1].bodies.quat)
    np.testing.assert_array_equal(runs[0].bodies.omega, runs[1].bodies.omega)
    assert runs[0].rec.n_rebuilds[0] == runs[1].rec.n_rebuilds[0]


def test_event_log_sees_repeated_collisions_and_pair_stats():
    """A ball bouncing between two walls and a second ball: every onset/end is logged."""
    scene = Scene(gravity=(0, 0, 0))
    m = scene.add_material(Material(density=RHO, kn=1e4))
    scene.add_wall((0, 0, 0), (1, 0, 0), m)
    scene.add_sphere((0.02, 0, 0), R, m, velocity=(-0.2, 0, 0))
    scene.add_sphere((0.05, 0, 0), R, m)
    scene.add_wall((0.07, 0, 0), (-1, 0, 0), m)
    sim = scene.build(safety=0.1, record_peak_force=True)
    res = sim.run(until=1.0)
    ev = res.events
    body_pair = (ev.body_i == 0) & (ev.body_j == 1)
    onsets = np.flatnonzero(body_pair & (ev.kind == ONSET))
    ends = np.flatnonzero(body_pair & (ev.kind == END))
    assert onsets.size >= 3 and onsets.size == ends.size
    assert np.all(np.diff(ev.time) >= 0)
    assert np.any(ev.body_j == -1) and np.any(ev.body_j == -2)
    p = sim.pairs
    assert p.n_contacts[0, 1] == p.n_contacts[1, 0] == onsets.size
    assert p.first_contact[0, 1] == ev.time[onsets[0]]
    assert p.last_separation[1, 0] == ev.time[ends[-1]]
    assert np.isnan(p.first_contact[0, 0])
    # elastic head-on impact of equal masses: peak force = v sqrt(k m_r)
    m_r = RHO * 4 / 3 * np.pi * R**3 / 2
    assert p.peak_normal_force[0, 1] == pytest.approx(0.2 * np.sqrt(1e4 * m_r), rel=1e-3)


def test_contact_passing_between_member_spheres_is_one_body_contact():
    """A sphere slides (x only, no friction, no gravity) over a row clump whose members'
    contact zones just touch: at each crevice the contact with member k ends and the one
    with member k+1 starts in the same step (END at the lower contact index).  The body
    pair stays in contact: one onset, no end, one distinct contact (the END-first order
    logged END + ONSET and counted a new contact at every crevice)."""
    scene = Scene(gravity=(0, 0, 0))
    m = scene.add_material(Material(density=RHO, kn=1e4))
    height = 1.99 * R  # centre height above the row: the largest overlap is 0.01 R
    reach = np.sqrt((2 * R) ** 2 - height**2)  # half width of one member's contact zone
    members = np.zeros((6, 3))
    members[:, 0] = 2 * reach * np.arange(6)
    row = scene.add_clump(members, R, m, blocked="x y z rx ry rz")
    ball = scene.add_sphere((0, 0, height), R, m, velocity=(0.5, 0, 0), blocked="y z rx ry rz")
    sim = scene.build(overlap_tolerance=0.02)
    res = sim.run(until=9 * reach / 0.5)
    assert sim.bodies.pos[ball, 0] > members[4, 0]  # four crevices crossed
    assert list(res.events.kind) == [ONSET]
    assert sim.pairs.n_contacts[row, ball] == 1
    assert np.isnan(sim.pairs.last_separation[row, ball])


def test_held_body_released_when_touched():
    """A held single-sphere column stays put (it would topple) until a moving body hits it."""
    scene = Scene()
    floor = scene.add_material(Material(density=RHO, kn=1e5, friction=0.5))
    scene.add_wall((0, 0, 0), (0, 0, 1), floor)
    standing = scene.add_clump(
        column(5, base=(0.05, 0, R), tilt=0.01), R, floor, blocked="y rx rz", held=True
    )
    other = scene.add_clump(
        column(5, base=(0.08, 0, R), tilt=0.01), R, floor, blocked="y rx rz", held=True
    )
    ball = scene.add_sphere((0.0, 0, 0.03), R, floor, velocity=(0.5, 0, 0), blocked="y rx rz")
    sim = scene.build(safety=0.1)
    with pytest.raises(ValueError, match="held"):
        sim.set_velocity(standing, velocity=(1, 0, 0))
    start = sim.positions()
    res = sim.run(until=0.05, trajectory_every=100)
    np.testing.assert_array_equal(
        res.positions[:, standing],
        np.broadcast_to(start[standing], res.positions[:, standing].shape),
    )
    res = sim.run(until=1.0, stop=StopCondition(touched_body=standing))
    assert res.stop_reason == "touched"
    t_touch = sim.pairs.first_contact[standing, ball]
    # the onset time is interpolated inside the step; the body is released at that step
    assert t_touch <= sim.release_time[standing] < t_touch + sim.dt
    assert np.isnan(sim.release_time[other]) and sim.bodies.held[other] == 1
    sim.run(n_steps=2000)
    assert np.linalg.norm(sim.positions()[standing] - start[standing]) > 0
    np.testing.assert_array_equal(sim.positions()[other], start[other])


def test_stop_when_no_new_onset():
    scene = Scene(gravity=(0, 0, 0))
    m = scene.add_material(Material(density=RHO, kn=1e4))
    scene.add_sphere((0, 0, 0), R, m, velocity=(0.1, 0, 0))
    scene.add_sphere((0.012, 0, 0), R, m)
    sim = scene.build(safety=0.1)
    res = sim.run(until=10.0, stop=StopCondition(no_onset_for=0.05))
    assert res.stop_reason == "no_onset"
    onset = res.events.time[0]
    assert res.time == pytest.approx(onset + 0.05, abs=2 * sim.dt)


def test_stop_when_kinetic_energy_small():
    sim = _box_scene(damping=0.3, restitution=0.3)
    res = sim.run(until=5.0, stop=StopCondition(kinetic_below=1e-7))
    assert res.stop_reason == "kinetic"
    e = sim.energy()
    assert e["kinetic_translational"] + e["kinetic_rotational"] < 1e-7


def test_checkpoint_resume_is_bit_identical(tmp_path):
    """get_state / set_state and save / load reproduce an uninterrupted run exactly."""
    sim = _box_scene(n=40, damping=0.05)
    sim.run(n_steps=3000)
    state = sim.get_state()
    sim.save(tmp_path / "chk.npz")
    sim.run(n_steps=4000)
    reference = sim.get_state()
    fresh = _box_scene(n=40, damping=0.05)
    fresh.set_state(state)
    for restored in (Simulation.load(tmp_path / "chk.npz"), fresh):
        restored.run(n_steps=4000)
        again = restored.get_state()
        for key, value in reference.items():
            np.testing.assert_array_equal(again[key], value, err_msg=key)


def test_trajectory_recorder_frames():
    sim = _box_scene(n=10)
    res = sim.run(n_steps=1000, trajectory_every=100, energy_every=250)
    assert res.positions.shape == (10, 10, 3)
    assert res.quaternions.shape == (10, 10, 4)
    np.testing.assert_allclose(res.times, np.arange(10) * 100 * sim.dt, rtol=1e-12)
    assert res.energy_times.size == 4
    # frames continue the time axis in the next run; the buffer grows when needed
    res2 = sim.run(n_steps=5000, trajectory_every=10)
    assert res2.times.size == 500 and res2.times[0] == pytest.approx(1000 * sim.dt, rel=1e-12)


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda s, m: s.add_sphere((0, 0, 0), 0.0, m), "radius"),
        (lambda s, m: s.add_sphere((0, 0, 0), -1.0, m), "radius"),
        (lambda s, m: s.add_sphere((0, 0, 0), R, 7), "material"),
        (lambda s, m: s.add_clump([[0, 0, 0], [0.01, 0, 0]], R, m, blocked="rx"), "blocked"),
        (lambda s, m: s.add_sphere((0, 0, 0), R, m, blocked="w"), "blocked"),
    ],
)
def test_bad_input_scene(make, match):
    scene = Scene()
    m = scene.add_material(Material(density=RHO, kn=1e4))
    with pytest.raises(ValueError, match=match):
        make(scene, m)
        scene.build()


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"density": 0.0, "kn": 1.0}, "density"),
        ({"density": 1.0, "kn": -1.0}, "kn"),
        ({"density": 1.0, "young": 0.0}, "young"),
        ({"density": 1.0}, "exactly one"),
        ({"density": 1.0, "kn": 1.0, "friction": -0.1}, "friction"),
        ({"density": 1.0, "kn": 1.0, "restitution": 0.0}, "restitution"),
    ],
)
def test_bad_material(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Material(**kwargs)


def test_initial_overlaps_are_rejected():
    scene = Scene()
    m = scene.add_material(Material(density=RHO, kn=1e4))
    scene.add_wall((0, 0, 0), (0, 0, 1), m)
    scene.add_sphere((0, 0, 0.5 * R), R, m)
    with pytest.raises(ValueError, match=r"body 0 .* overlaps wall 0"):
        scene.build()
    scene = Scene()
    m = scene.add_material(Material(density=RHO, kn=1e4))
    scene.add_sphere((0, 0, 0), R, m)
    scene.add_sphere((1.5 * R, 0, 0), R, m)
    with pytest.raises(ValueError, match=r"body 0 .* overlaps body 1"):
        scene.build()


def test_time_step_above_critical_is_rejected():
    scene = Scene()
    m = scene.add_material(Material(density=RHO, kn=1e4))
    scene.add_sphere((0, 0, 0), R, m)
    dt_crit = scene.build().critical_dt
    with pytest.raises(ValueError, match=r"dt = .* critical"):
        scene.build(dt=1.01 * dt_crit)


def _confined_fcc(safety, kt_ratio):
    """108 spheres on an FCC lattice (3 x 3 x 3 cells, pre-compressed by 1e-4 of the
    spacing) between 6 walls, friction 0.5: 12 simultaneous contacts per sphere."""
    scene = Scene(gravity=(0, 0, 0))
    m = scene.add_material(Material(density=RHO, kn=1e4, kt_ratio=kt_ratio, friction=0.5))
    a = 2 * np.sqrt(2) * R * (1 - 1e-4)
    basis = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
    cells = np.stack(np.meshgrid(*[np.arange(3)] * 3, indexing="ij"), -1).reshape(-1, 3)
    centres = ((cells[:, None, :] + basis[None]) * a).reshape(-1, 3)
    lo, hi = centres.min(0), centres.max(0)
    for d in range(3):
        e = np.eye(3)[d]
        scene.add_wall(lo - R * (1 - 1e-4) * e, e, m)
        scene.add_wall(hi + R * (1 - 1e-4) * e, -e, m)
    rng = np.random.default_rng(0)
    for c in centres:
        scene.add_sphere(c, R, m, velocity=rng.normal(size=3) * 1e-6)
    return scene.build(safety=safety, overlap_tolerance=1e-3)


@pytest.mark.parametrize("kt_ratio", [1.0, 0.0])
def test_validate_critical_step_estimate_holds_for_a_confined_packing(kt_ratio):
    """At 0.99 of the critical-step estimate a confined FCC packing stays stable: the
    estimate counts the contacts present at start (Gershgorin bound on the stiffness
    sums) and the translation-rotation coupling of a contact.  The former single-contact
    estimate min(sqrt(m/k), sqrt(I/(k rho^2))) was accepted at 0.99 and aborted with an
    energy breakdown (stable only at 0.8)."""
    sim = _confined_fcc(0.99, kt_ratio)
    e0 = sim.energy()["total"]  # the pre-compression
    res = sim.run(n_steps=3000, energy_every=50)
    # bounded (large at this step: the shadow-energy error of leapfrog near its limit)
    assert np.max(np.abs(res.energy["total"] - e0)) < 0.2 * e0


def test_unstable_step_aborts_with_cause():
    """A step far above the critical one (forced past the check) blows up -> RuntimeError."""
    sim = _box_scene(n=30, restitution=None)
    sim.settings = sim.settings._replace(dt=50 * sim.critical_dt)
    with pytest.raises(RuntimeError, match="time step"):
        sim.run(n_steps=100_000)


def test_unstable_step_whose_energy_overflows_aborts():
    """At 5x the critical step the packing's velocities reach ~1e160 m/s: finite, but the
    kinetic energy overflows to inf and the total reads NaN.  A NaN excess must abort the
    run (a plain ``excess > slack`` is False for NaN and let this run end as if fine)."""
    sim = _box_scene(n=30)
    sim.settings = sim.settings._replace(dt=5 * sim.critical_dt)
    with pytest.raises(RuntimeError, match="energy balance broke down"):
        sim.run(n_steps=20_000)


def test_energy_excess_sees_work_booked_as_negative_dissipation():
    """An unstable dashpot books the energy it creates as negative dissipation, so the
    ledger's total stays balanced while the mechanical energy grows: the excess is that
    growth, and a negative dissipation does not widen the energy scale."""
    ref = np.zeros(len(ENERGY_NAMES))
    ref[ENERGY_NAMES.index("gravitational")] = 1.0
    ref[ENERGY_NAMES.index("total")] = 1.0
    now = ref.copy()
    now[ENERGY_NAMES.index("kinetic_translational")] = 5.0  # created
    now[ENERGY_NAMES.index("dissipated_viscous")] = -5.0  # booked as negative dissipation
    assert now[:N_MECHANICAL].sum() - ref[:N_MECHANICAL].sum() == 5.0
    assert engine.energy_excess(now, ref, True) == 5.0
    assert engine.energy_excess(now, ref, False) == 5.0
    assert engine.active_energy(now, True) == 5.0  # kinetic only, not |-5| more
    now[ENERGY_NAMES.index("kinetic_rotational")] = np.inf
    assert np.isnan(engine.energy_excess(now, ref, True))


def test_energy_tracking_off_keeps_the_trajectory_and_reports_nan():
    """``track_energy=False`` (YADE's default) skips the dissipation ledger only: the
    trajectory is bit-identical, the dissipated energies and the total read nan, and the
    mechanical energy still is what it is with tracking."""
    runs = []
    for track in (True, False):
        sim = _box_scene(n=40, damping=0.2, track_energy=track)
        sim.run(until=0.03)
        runs.append(sim)
    np.testing.assert_array_equal(runs[0].positions(), runs[1].positions())
    e_on, e_off = runs[0].energy(), runs[1].energy()
    for name in ("dissipated_friction", "dissipated_viscous", "dissipated_damping", "total"):
        assert np.isnan(e_off[name]) and np.isfinite(e_on[name])
    for name in ("kinetic_translational", "gravitational", "elastic_normal"):
        assert e_off[name] == e_on[name]


def test_unstable_step_aborts_without_energy_tracking():
    """Without the ledger a blow-up is caught as growth of the mechanical energy (at 3x
    the critical step, at the same step as the ledger catches it)."""
    sim = _box_scene(n=30, restitution=None, track_energy=False)
    sim.settings = sim.settings._replace(dt=3 * sim.critical_dt)
    with pytest.raises(RuntimeError, match="mechanical energy grew"):
        sim.run(n_steps=100_000)


def test_run_needs_a_limit():
    sim = _box_scene(n=2)
    with pytest.raises(ValueError, match="n_steps"):
        sim.run()


def test_spin_about_a_blocked_axis():
    """Spheres keep a blocked angular-velocity component (YADE); an aspherical clump
    given a spin about a blocked axis is rejected instead of silently zeroed."""
    scene = Scene(gravity=(0, 0, 0))
    m = scene.add_material(Material(density=RHO, kn=1e4))
    sphere = scene.add_sphere((0, 0, 0), R, m, blocked="rx", angular_velocity=(2.0, 1.0, 0))
    planar = scene.add_clump(column(3, base=(0.1, 0, 0)), R, m, blocked="rx rz")
    fixed = scene.add_clump(column(3, base=(0.2, 0, 0)), R, m, blocked="rx ry rz")
    sim = scene.build()
    res = sim.run(n_steps=10, trajectory_every=5)
    np.testing.assert_array_equal(res.angular_velocities[:, sphere], [[2.0, 1.0, 0.0]] * 2)
    for body, spin in ((planar, (0.5, 1.0, 0.0)), (fixed, (0.0, 1.0, 0.0))):
        with pytest.raises(ValueError, match=f"body {body} turns about a blocked axis"):
            sim.set_velocity(body, angular_velocity=spin)
    sim.set_velocity(planar, angular_velocity=(0.0, 1.0, 0.0))
    bad = Scene(gravity=(0, 0, 0))
    m = bad.add_material(Material(density=RHO, kn=1e4))
    bad.add_clump(column(3), R, m, blocked="y rx rz", angular_velocity=(1.0, 3.0, 0.0))
    with pytest.raises(ValueError, match="angular_velocity"):
        bad.build()


def test_energy_indices_name_the_energy_vector():
    """The named indices of the energy vector point at the entries ENERGY_NAMES gives
    them, and the total the kernel writes at E_TOTAL is the sum of the others."""
    from dominowave.dem import energy

    for name in energy.ENERGY_NAMES:
        assert energy.ENERGY_NAMES.index(name) == getattr(energy, f"E_{name.upper()}")
    assert len(energy.ENERGY_NAMES) == energy.N_ENERGIES == energy.E_TOTAL + 1
    assert energy.ENERGY_NAMES[: energy.N_MECHANICAL] == (
        "kinetic_translational",
        "kinetic_rotational",
        "gravitational",
        "elastic_normal",
        "elastic_tangential",
    )
    sim = _box_scene(n=8, seed=1)
    sim.run(n_steps=200)
    e = sim.energy()
    assert e["kinetic_translational"] > 0.0 and e["gravitational"] != 0.0
    assert e["total"] == pytest.approx(sum(e[name] for name in energy.ENERGY_NAMES[:-1]))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.integers(0, 1), min_size=1, max_size=40))
def test_moving_range_holds_every_body_that_is_not_held(flags):
    """The fused body pass looks only at ``range(first, stop)`` (engine._moving_range):
    every body that is not held lies in it, and it is the tightest such range."""
    held = np.array(flags, dtype=np.uint8)
    first, stop = engine._moving_range(namedtuple("HeldFlags", ["held"])(held))
    free = np.flatnonzero(held == 0)
    if free.size == 0:
        assert first >= stop
    else:
        assert (first, stop) == (free[0], free[-1] + 1)
