"""Rounded-cuboid geometry (dem/shapes): mass properties and contact manifolds against
independent calculations (quadrature, bounded least squares for the distance of two
boxes, the support function), symmetry, rotation invariance, the planar reduction."""

import numpy as np
import pytest
from dem_scenes import at_core_gap, core_distance, manifold_buffers
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import lsq_linear
from scipy.spatial.transform import Rotation

from dominowave.dem.shapes.cuboid import (
    box_box,
    box_plane,
    box_sphere,
    cuboid_mass_properties,
    faces_separate,
    separating_axes,
)
from dominowave.dem.shapes.rectangle import rect_plane, rect_rect

H_I = np.array([0.012, 0.004, 0.024])  # a domino-like core [m]
H_J = np.array([0.010, 0.006, 0.020])


def _box_box(xi, Ri, hi, ri, xj, Rj, hj, rj, margin=0.0):
    normal, point, overlap, key = manifold_buffers()
    work = np.zeros((2, 9, 4))
    n = box_box(xi, Ri, hi, ri, xj, Rj, hj, rj, margin, work, normal, point, overlap, key)
    return normal[:n], point[:n], overlap[:n], key[:n]


def _random_pair(rng, gap):
    """Box j placed in a random direction from box i with its core at distance ``gap``."""
    Ri = Rotation.random(random_state=rng).as_matrix()
    Rj = Rotation.random(random_state=rng).as_matrix()
    xi = rng.normal(size=3) * 0.01
    u = rng.normal(size=3)
    u /= np.linalg.norm(u)
    return xi, Ri, at_core_gap(xi, Ri, H_I, Rj, H_J, u, gap, steps=50), Rj


# ----------------------------------------------------------------------- mass properties


def test_validate_cuboid_inertia_against_quadrature():
    """m and I of a uniform cuboid vs Gauss-Legendre quadrature (exact for quadratics)."""
    half = np.array([0.024, 0.012, 0.0375]) / 2
    rho = 1100.0
    mass, moments = cuboid_mass_properties(half, rho)
    g, w = np.polynomial.legendre.leggauss(3)
    X, Y, Z = np.meshgrid(g * half[0], g * half[1], g * half[2], indexing="ij")
    W = np.einsum("i,j,k->ijk", w, w, w) * np.prod(half)
    assert mass == pytest.approx(rho * W.sum(), rel=1e-13)
    expected = rho * np.array(
        [(W * (Y**2 + Z**2)).sum(), (W * (X**2 + Z**2)).sum(), (W * (X**2 + Y**2)).sum()]
    )
    np.testing.assert_allclose(moments, expected, rtol=1e-13)


# ----------------------------------------------------------------------- box and plane


def test_box_flat_on_plane_gets_four_corners():
    normal, point, overlap, key = manifold_buffers()
    r = 0.001
    x = np.array([0.0, 0.0, H_I[2] + r - 1e-5])
    up = np.array([0, 0, 1.0])
    n = box_plane(x, np.eye(3), H_I, r, np.zeros(3), up, 0.0, normal, point, overlap, key)
    assert n == 4
    np.testing.assert_allclose(overlap[:n], 1e-5, rtol=1e-9)
    np.testing.assert_allclose(normal[:n], [[0, 0, -1.0]] * 4)
    np.testing.assert_allclose(point[:n, 2], -0.5e-5, atol=1e-15)
    assert sorted(key[:n]) == [0, 1, 2, 3]
    np.testing.assert_allclose(point[:n, :2].mean(axis=0), 0.0, atol=1e-15)


def test_validate_box_plane_deepest_point_is_support_function():
    """The largest overlap is the depth of the support point of the rounded box along -n:
    ``h(-n) = sum_k h_k |n . R_k| + r`` (support function of a Minkowski sum)."""
    rng = np.random.default_rng(1)
    for _ in range(200):
        R = Rotation.random(random_state=rng).as_matrix()
        nw = rng.normal(size=3)
        nw /= np.linalg.norm(nw)
        p0 = rng.normal(size=3) * 0.01
        r = 0.002
        support = np.sum(H_I * np.abs(nw @ R)) + r
        depth = rng.uniform(1e-6, 2e-3)
        x = p0 + nw * (support - depth)
        normal, point, overlap, key = manifold_buffers()
        n = box_plane(x, R, H_I, r, p0, nw, 0.0, normal, point, overlap, key)
        assert n >= 1
        assert overlap[:n].max() == pytest.approx(depth, rel=1e-9, abs=1e-15)
        # every point midway through its overlap, on the plane's side
        np.testing.assert_allclose((point[:n] - p0) @ nw, -0.5 * overlap[:n], atol=1e-15)


def test_validate_box_sphere_against_least_squares():
    rng = np.random.default_rng(2)
    r, radius = 0.001, 0.003
    for _ in range(200):
        R = Rotation.random(random_state=rng).as_matrix()
        x = rng.normal(size=3) * 0.01
        u = rng.normal(size=3)
        u /= np.linalg.norm(u)
        c = x + u * rng.uniform(0.0, 0.05)
        res = lsq_linear(R, c - x, bounds=(-H_I, H_I), method="bvls", tol=1e-14)
        dist = np.linalg.norm(R @ res.x - (c - x))
        normal, point, overlap, key = manifold_buffers()
        n = box_sphere(x, R, H_I, r, c, radius, 1.0, normal, point, overlap, key)
        assert n == 1
        local = R.T @ (c - x)
        if np.all(np.abs(local) < H_I):  # inside the core: depth below the nearest face
            assert overlap[0] == pytest.approx(r + radius + np.min(H_I - np.abs(local)), abs=1e-13)
        else:
            assert overlap[0] == pytest.approx(r + radius - dist, abs=1e-13)
            # the point lies midway through the overlap, along the normal from the box
            surface_sphere = c - radius * normal[0]
            midway = surface_sphere + 0.5 * overlap[0] * normal[0]
            np.testing.assert_allclose(point[0], midway, atol=1e-13)


# ----------------------------------------------------------------------- box and box


def test_stacked_boxes_get_the_corners_of_the_overlap():
    r = 0.001
    R = np.eye(3)
    xi = np.zeros(3)
    xj = np.array([0.005, 0.002, H_I[2] + H_J[2] + 2 * r - 1e-5])
    normal, point, overlap, key = _box_box(xi, R, H_I, r, xj, R, H_J, r)
    assert len(overlap) == 4
    np.testing.assert_allclose(overlap, 1e-5, rtol=1e-9)
    np.testing.assert_allclose(normal, [[0, 0, 1.0]] * 4)
    # the overlap rectangle of the two footprints
    xs = sorted(set(np.round(point[:, 0], 12)))
    ys = sorted(set(np.round(point[:, 1], 12)))
    np.testing.assert_allclose(xs, [0.005 - H_J[0], H_I[0]], atol=1e-12)
    np.testing.assert_allclose(ys, [-H_I[1], H_I[1]], atol=1e-12)
    assert len(set(key)) == 4


@pytest.mark.parametrize("seed", range(4))
def test_validate_box_box_deepest_point_against_exact_distance(seed):
    """The largest overlap of the manifold is ``r_i + r_j - d`` with d the exact core
    distance (bounded least squares), over random orientations and directions."""
    rng = np.random.default_rng(10 + seed)
    ri, rj = 0.002, 0.0015
    for _ in range(40):
        gap = rng.uniform(0.0002, ri + rj - 1e-5)
        xi, Ri, xj, Rj = _random_pair(rng, gap)
        d = core_distance(xi, Ri, H_I, xj, Rj, H_J)
        normal, _, overlap, _ = _box_box(xi, Ri, H_I, ri, xj, Rj, H_J, rj)
        assert len(overlap) >= 1
        assert overlap.max() == pytest.approx(ri + rj - d, abs=1e-10)
        np.testing.assert_allclose(np.linalg.norm(normal, axis=1), 1.0, rtol=1e-12)
        # the normal points from i to j
        assert np.all(normal @ (xj - xi) > 0.0)


@pytest.mark.parametrize("seed", range(3))
def test_validate_box_box_face_contacts_deepest_point_against_exact_distance(seed):
    """Near-parallel faces (a box leaning on a face, resting on it, tilted across it):
    where the manifold's deepest corner is as deep as the separating-axis bound allows,
    box_box skips the search for the exact deepest point; the largest overlap must still
    be ``r_i + r_j - d`` with d the exact core distance (bounded least squares)."""
    rng = np.random.default_rng(40 + seed)
    ri, rj = 0.0005, 0.0005
    tested = skipped = 0
    for k in range(400):
        Ri = Rotation.from_rotvec(rng.normal(0.0, 0.3, 3)).as_matrix()
        Rj = Ri @ Rotation.from_rotvec(rng.normal(0.0, (0.8, 0.05, 0.005)[k % 3], 3)).as_matrix()
        axis = int(rng.integers(3))
        lateral = rng.uniform(-1.0, 1.0, 3) * H_J * (np.arange(3) != axis)
        xi = rng.normal(size=3) * 0.01
        xj = xi + Ri[:, axis] * (H_I[axis] + H_J[axis] + rng.uniform(-2e-4, 8e-4))
        xj += Ri @ lateral
        d = core_distance(xi, Ri, H_I, xj, Rj, H_J)
        if d < 1e-7 or d >= ri + rj:  # (cores apart, rounded bodies touching)
            continue
        _, _, overlap, _ = _box_box(xi, Ri, H_I, ri, xj, Rj, H_J, rj)
        assert overlap.max() == pytest.approx(ri + rj - d, abs=1e-10)
        tested += 1
        sure = separating_axes(xi, Ri, H_I, xj, Rj, H_J, np.inf, np.zeros((2, 9, 4)))[11]
        skipped += bool(sure > 0.0 and overlap.max() >= ri + rj - sure - 1e-12)
    assert tested >= 100
    assert skipped >= 0.5 * tested  # (the configurations of the skip)


@pytest.mark.parametrize("seed", range(3))
def test_validate_separating_axes_bound_the_core_distance(seed):
    """The largest gap over the 15 axes is a lower bound of the exact core distance
    (bounded least squares) -- what box_box's skip of the deepest-point search rests on
    -- and equals it where a face axis realises the distance (a box resting on the face
    of another, turned about that face's normal); an axis separating by ``reach`` says
    apart, and so does faces_separate for exactly the pairs a face axis separates."""
    rng = np.random.default_rng(70 + seed)
    work = np.zeros((2, 9, 4))
    for _ in range(60):
        xi, Ri, xj, Rj = _random_pair(rng, rng.uniform(1e-4, 0.01))
        d = core_distance(xi, Ri, H_I, xj, Rj, H_J)
        got = separating_axes(xi, Ri, H_I, xj, Rj, H_J, np.inf, work)
        assert not got[0]
        gap = max(got[1], got[3], got[5])
        assert 0.0 < gap <= d + 1e-12
        assert max(got[1], got[3]) <= got[11] <= gap  # (the bound of box_box's skip)
        assert separating_axes(xi, Ri, H_I, xj, Rj, H_J, 0.999 * gap, work)[0]
        faces = max(got[1], got[3])
        for reach in (0.999 * faces, 1.001 * faces):
            assert faces_separate(xi, Ri, H_I, xj, Rj, H_J, reach, work) == (faces >= reach)
    for _ in range(20):  # face on face: the gap is the distance
        turn = Rotation.from_rotvec([0.0, 0.0, rng.uniform(-np.pi, np.pi)]).as_matrix()
        Ri = Rotation.random(random_state=rng).as_matrix()
        lateral = rng.uniform(-0.5, 0.5, 2) * H_J[:2]
        gap = rng.uniform(1e-5, 1e-3)
        xj = Ri @ np.array([*lateral, H_I[2] + H_J[2] + gap])
        got = separating_axes(np.zeros(3), Ri, H_I, xj, Ri @ turn, H_J, np.inf, work)
        assert max(got[1], got[3], got[5]) == pytest.approx(gap, abs=1e-15)


def test_box_box_takes_the_frame_left_by_faces_separate():
    """The engine's order -- faces_separate, then box_box(..., frame_ready=True) on the
    frame it left in ``work[0]`` -- gives the manifold of a fresh box_box to the bit, for
    touching, near and interpenetrating pairs (work[0] is scrubbed in between for the
    fresh call, so a frame that were not recomputed would show)."""
    rng = np.random.default_rng(11)
    ri, rj = 0.001, 0.0015
    touching = 0
    for gap in rng.uniform(-0.002, 0.004, 80):
        xi, Ri, xj, Rj = _random_pair(rng, max(gap, 1e-6))
        if gap < 0:  # (cores interpenetrating: box j moved towards box i)
            xj = xi + (xj - xi) * (1 + gap / np.linalg.norm(xj - xi))
        margin = 0.5 * (ri + rj)
        work = np.zeros((2, 9, 4))
        if faces_separate(xi, Ri, H_I, xj, Rj, H_J, ri + rj + margin, work):
            continue
        shared = manifold_buffers()
        n = box_box(xi, Ri, H_I, ri, xj, Rj, H_J, rj, margin, work, *shared, True)
        fresh = manifold_buffers()
        work[:] = np.nan
        assert box_box(xi, Ri, H_I, ri, xj, Rj, H_J, rj, margin, work, *fresh) == n
        for a, b in zip(shared, fresh, strict=True):
            np.testing.assert_array_equal(a[:n], b[:n])
        touching += n > 0
    assert touching > 20


def test_validate_box_box_no_contact_beyond_reach():
    rng = np.random.default_rng(5)
    ri, rj = 0.002, 0.0015
    for _ in range(60):
        gap = rng.uniform(ri + rj + 1e-6, 0.02)
        xi, Ri, xj, Rj = _random_pair(rng, gap)
        assert len(_box_box(xi, Ri, H_I, ri, xj, Rj, H_J, rj)[2]) == 0


def _rotation(draw_angles):
    return Rotation.from_rotvec(draw_angles).as_matrix()


vectors = st.lists(st.floats(-3.0, 3.0), min_size=3, max_size=3).map(np.array)


@settings(max_examples=30, deadline=None)
@given(vectors, vectors, vectors, st.floats(0.0, 1.0), st.floats(1e-5, 0.003))
def test_box_box_symmetric_and_rotation_invariant(ai, aj, q, direction, gap):
    Ri, Rj = _rotation(ai), _rotation(aj)
    u = np.array([np.cos(6.0 * direction), np.sin(6.0 * direction), 0.5])
    u /= np.linalg.norm(u)
    xi = np.zeros(3)
    xj = at_core_gap(xi, Ri, H_I, Rj, H_J, u, gap)  # j along u
    r = 0.002
    ab = _box_box(xi, Ri, H_I, r, xj, Rj, H_J, r)
    ba = _box_box(xj, Rj, H_J, r, xi, Ri, H_I, r)
    if len(ab[2]) == len(ba[2]) and len(ab[2]) > 0:
        # the same physical contact: the same deepest overlap, normals opposite -- up to
        # the choice of the reference face where a face of i and one of j are nearly
        # parallel (either face normal is the contact normal then; they differ by the
        # angle between the two faces)
        assert ab[2].max() == pytest.approx(ba[2].max(), abs=1e-12)
        n_ab = ab[0].sum(axis=0) / len(ab[2])
        n_ba = -ba[0].sum(axis=0) / len(ba[2])
        face_angle = np.arccos(np.clip(np.abs(Ri.T @ Rj).max(), -1.0, 1.0))
        nearly_parallel = face_angle < 1e-6
        assert np.linalg.norm(n_ab - n_ba) <= 1e-9 + (face_angle if nearly_parallel else 0.0)
    assert (len(ab[2]) > 0) == (len(ba[2]) > 0)
    # rotation of the whole scene
    Q = _rotation(q)
    rot = _box_box(Q @ xi, Q @ Ri, H_I, r, Q @ xj, Q @ Rj, H_J, r)
    assert len(rot[2]) == len(ab[2])
    np.testing.assert_allclose(np.sort(rot[2]), np.sort(ab[2]), atol=1e-12)
    order_a, order_r = np.argsort(ab[3]), np.argsort(rot[3])
    np.testing.assert_array_equal(ab[3][order_a], rot[3][order_r])
    np.testing.assert_allclose(rot[1][order_r], ab[1][order_a] @ Q.T, atol=1e-12)
    np.testing.assert_allclose(rot[0][order_r], ab[0][order_a] @ Q.T, atol=1e-9)


# Dominoes 0 and 1 of the symmetric 3D box chain of Fig 6 (d/l = 0.4, member 0 of
# docs/fig6/box/planarity.py) at t = 0.2149224 s, lying on each other: cores of equal
# width, the side edges of the incident face on the side planes of the reference face to
# the round-off of the 1e-16 entries of the rotations.
CHAIN_PAIR = (
    np.array([-0.0027057493375580244, 1.4059334419439555e-19, 0.008475534938664602]),
    np.array([[0.2207942435076975, 1.5357340863195826e-17, 0.9753204099340168],
              [-1.494000112064257e-16, 1.0, 1.8075415434360387e-17],
              [-0.9753204099340168, -1.497038278509152e-16, 0.2207942435076975]]),
    np.array([0.028732307747715864, -3.0394467070759915e-20, 0.010396083256927894]),
    np.array([[0.21256497004934538, 3.2876478180612552e-18, 0.977146935474873],
              [-1.929582145811433e-17, 1.0, 8.330046001371423e-19],
              [-0.977146935474873, -1.9031920403145662e-17, 0.21256497004934538]]),
)  # fmt: skip
CHAIN_CORE = np.array([0.00225, 0.01225, 0.02475])  # 5 x 25 x 50 mm, r = 0.25 mm
CHAIN_R = 0.00025


def _mirror_pairs(n_random):
    """Pairs ``(xi, Ri, hi, ri, xj, Rj, hj, rj, y0)`` placed symmetrically about the plane
    y = y0: the chain pair, and ``n_random`` pairs of cores as wide as the chain's turned
    about y (any angle and direction, the cores 0 to ``2 r`` apart), each rotation
    perturbed by a random turn of about 1e-15 rad, as the integrated orientations of a
    planar chain are.  Every other pair varies one thing: j's other sizes, j turned over
    (about x by pi), j's rounding, or the plane (y0 = 0.1 m)."""
    yield (*CHAIN_PAIR[:2], CHAIN_CORE, CHAIN_R, *CHAIN_PAIR[2:], CHAIN_CORE, CHAIN_R, 0.0)
    rng = np.random.default_rng(3)
    flip = _rotation([np.pi, 0.0, 0.0])
    for case in range(n_random):
        ti, tj, direction = rng.uniform(-np.pi, np.pi, 3)
        hj, rj, y0, Rj = CHAIN_CORE, CHAIN_R, 0.0, _about_y(tj)
        variant = case % 8
        if variant == 1:
            hj = CHAIN_CORE * np.array([1.7, 1.0, 0.6])
        elif variant == 3:
            Rj = Rj @ flip
        elif variant == 5:
            rj = 0.6 * CHAIN_R
        elif variant == 7:
            y0 = 0.1
        gap = rng.uniform(1e-5, CHAIN_R + rj)
        Ri = _about_y(ti) @ _rotation(rng.normal(size=3) * 1e-15)
        Rj = Rj @ _rotation(rng.normal(size=3) * 1e-15)
        u = np.array([np.cos(direction), 0.0, np.sin(direction)])
        xj = at_core_gap(np.zeros(3), Ri, CHAIN_CORE, Rj, hj, u, gap)
        shift = np.array([0.0, y0, 0.0])
        yield shift, Ri, CHAIN_CORE, CHAIN_R, xj + shift, Rj, hj, rj, y0


def test_mirror_symmetric_pairs_give_mirror_symmetric_manifolds():
    """Two boxes of equal width placed symmetrically about a plane y = y0 (to round-off)
    touch with a manifold that is its own mirror image: every point (x, y0 + y, z) has a
    partner at (x, y0 - y, z) with the same overlap and the mirrored normal.  Where the
    side edges of the incident face lie on the side planes of the reference face,
    round-off decides on which side of a plane each end falls; a manifold that follows it
    exerts a torque about the chain's axis from nothing (one side of a line contact
    dropped for a step tipped the symmetric 3D chain of Fig 6 out of its plane)."""
    for xi, Ri, hi, ri, xj, Rj, hj, rj, y0 in _mirror_pairs(400):
        normal, point, overlap, _ = _box_box(xi, Ri, hi, ri, xj, Rj, hj, rj)
        mirror = point * np.array([1.0, -1.0, 1.0]) + np.array([0.0, 2.0 * y0, 0.0])
        gaps = np.linalg.norm(point[:, None, :] - mirror[None, :, :], axis=-1)
        partner = gaps.argmin(axis=1)
        assert np.all(gaps[np.arange(len(point)), partner] < 1e-12)
        assert sorted(partner) == list(range(len(point)))  # (a one-to-one pairing)
        np.testing.assert_allclose(overlap[partner], overlap, atol=1e-15)
        np.testing.assert_allclose(normal[partner] * [1.0, -1.0, 1.0], normal, atol=1e-12)


def test_validate_edge_on_a_side_plane_is_a_line_contact_of_both_ends():
    """A box j over the top face of box i with the bottom edge of its -y face along i's +y
    side plane (within ``COINCIDENT`` of it, either side, the rotations perturbed by
    1e-15 rad): the contact is that edge's line contact, one point at each end, each as
    deep as the end's height above i's face says (the end lies over the face's border,
    so its core distance is that height).  Read as an edge leaving the face, its corner
    was replaced by the edge's other end, and the line contact lost one end."""
    from dominowave.dem.shapes.cuboid import COINCIDENT

    hi, hj, r = np.array([0.02, 0.01, 0.005]), np.array([0.01, 0.008, 0.005]), 0.0005
    close = COINCIDENT * (hi.max() + hj.max())
    rng = np.random.default_rng(0)
    for off in (0.0, 0.3, -0.3):
        Rj = Rotation.from_rotvec([0.0, 0.01, 0.0]).as_matrix()
        Rj = Rj @ Rotation.from_rotvec([0.02, 0.0, 0.0]).as_matrix()
        Rj = Rj @ _rotation(rng.normal(size=3) * 1e-15)
        ends = np.array([[sx * hj[0], -hj[1], -hj[2]] for sx in (1.0, -1.0)]) @ Rj.T
        y = hi[1] + off * close - ends[:, 1].mean()  # the edge on i's +y side plane
        xj = np.array([0.0, y, hi[2] + 2e-4 - ends[:, 2].max()])  # 0.2 mm over i's face
        _, point, overlap, _ = _box_box(np.zeros(3), np.eye(3), hi, r, xj, Rj, hj, r)
        ends += xj  # world positions of the two ends
        assert len(overlap) == 2
        order = np.argsort(point[:, 0])
        np.testing.assert_allclose(point[order, :2], ends[np.argsort(ends[:, 0]), :2], atol=close)
        depth = 2 * r - (ends[:, 2] - hi[2])
        np.testing.assert_allclose(overlap[order], depth[np.argsort(ends[:, 0])], atol=1e-12)


def test_a_face_cut_down_to_one_vertex_keeps_the_vertex_key():
    """Box j turned 45 deg about z and tilted, one vertex of its bottom face over the +x
    edge of box i's top face, the rest beyond: as that vertex crosses i's side plane
    (2 x ``COINCIDENT`` inside, within it either side) the clipped face keeps the point of
    the vertex under the vertex's key (face key + edge labels 0, 1), so its shear history
    goes on; a polygon cut down to that one corner had the key of the side plane alone."""
    from dominowave.dem.shapes.cuboid import COINCIDENT, _face_manifold

    hi, hj, r = np.array([0.02, 0.02, 0.01]), np.array([0.01, 0.01, 0.005]), 0.0005
    close = COINCIDENT * (hi.max() + hj.max())
    Rj = Rotation.from_rotvec([0.0, 0.05, 0.0]).as_matrix()
    Rj = Rj @ Rotation.from_rotvec([0.0, 0.0, np.pi / 4]).as_matrix()
    bottom = np.array([[sx * hj[0], sy * hj[1], -hj[2]] for sx in (1, -1) for sy in (1, -1)])
    bottom = bottom @ Rj.T
    v = bottom[np.argsort(-bottom[:, 0])[3]]  # the vertex of least x
    keys = []
    for s in (-2.0 * close, -0.5 * close, 0.5 * close):
        xj = np.array([hi[0] + s - v[0], 0.003 - v[1], hi[2] + 2e-4 - v[2]])
        normal, point, overlap, key = manifold_buffers()
        n = _face_manifold(np.zeros(3), np.eye(3), hi, r, 2, xj, Rj, hj, r, 0.0, 1.0, 0,
                           np.zeros((2, 9, 4)), (normal, point, overlap, key))  # fmt: skip
        keys.append({(k % 64) // 8 * 10 + k % 8 for k in key[:n]})
    assert all(1 in k for k in keys), keys  # (labels 0, 1: the vertex)


def test_keys_persist_under_small_motion():
    """A face contact keeps its keys while the boxes slide and turn a little."""
    r = 0.001
    xi = np.zeros(3)
    base = np.array([0.004, 0.001, H_I[2] + H_J[2] + 2 * r - 2e-5])
    _, _, _, key0 = _box_box(xi, np.eye(3), H_I, r, base, np.eye(3), H_J, r)
    for k in range(1, 20):
        Rj = _rotation([1e-6 * k, -2e-6 * k, 3e-6 * k])
        xj = base + np.array([1e-5, -1e-5, 0.0]) * k
        _, _, _, key = _box_box(xi, np.eye(3), H_I, r, xj, Rj, H_J, r)
        assert sorted(key) == sorted(key0)


def test_validate_sharp_limit_of_the_rounding():
    """r -> 0 at a fixed outer size ``H`` (core ``H - r``): a tilted box over a plane.  By
    the support function the rounded body reaches ``r (sum_k |n . R_k| - 1)`` less deep
    than the sharp box (0 for a face parallel to the plane), which -> 0 with r."""
    outer = np.array([0.012, 0.004, 0.024])
    R = _rotation([0.0, 0.3, 0.0])
    nw = np.array([0.0, 0.0, 1.0])
    support = np.sum(outer * np.abs(nw @ R))
    x = np.array([0.0, 0.0, support - 1e-4])  # the sharp box dips 1e-4 m
    previous = np.inf
    for r in (2e-4, 2e-5, 2e-6, 2e-7):
        normal, point, overlap, key = manifold_buffers()
        n = box_plane(x, R, outer - r, r, np.zeros(3), nw, 0.0, normal, point, overlap, key)
        err = abs(overlap[:n].max() - 1e-4)
        exact = r * (np.sum(np.abs(nw @ R)) - 1.0)
        assert err == pytest.approx(exact, rel=1e-6, abs=1e-16)
        assert err < previous
        previous = err


# ----------------------------------------------------------------------- planar reduction

planar_angles = st.floats(-np.pi, np.pi)


def _about_y(angle):
    return Rotation.from_rotvec([0.0, angle, 0.0]).as_matrix()


@settings(max_examples=40, deadline=None)
@given(planar_angles, planar_angles, st.floats(-np.pi, np.pi), st.floats(1e-5, 0.0035))
def test_validate_planar_rectangles_are_the_cuboid_pairs(ti, tj, direction, gap):
    """In a planar scene the 3D manifold consists of point pairs at y = +-b, and the 2D
    kernel returns one of each pair: the same overlaps, normals and (x, z) points."""
    Ri, Rj = _about_y(ti), _about_y(tj)
    h_i = np.array([0.012, 0.004, 0.024])
    h_j = np.array([0.010, 0.004, 0.020])
    u = np.array([np.cos(direction), 0.0, np.sin(direction)])
    xi = np.zeros(3)
    xj = at_core_gap(xi, Ri, h_i, Rj, h_j, u, gap)
    r = 0.002
    n3, p3, o3, _ = _box_box(xi, Ri, h_i, r, xj, Rj, h_j, r)
    normal, point, overlap, key = manifold_buffers()
    n = rect_rect(xi, Ri, h_i, r, xj, Rj, h_j, r, 0.0, normal, point, overlap, key)
    assert overlap[:n].max() == pytest.approx(2 * r - gap, abs=1e-10)  # (exact distance)
    assert len(o3) == 2 * n
    rows3 = np.column_stack([p3[:, 0], p3[:, 2], n3[:, 0], n3[:, 2], o3])
    rows2 = np.column_stack([point[:n, 0], point[:n, 2], normal[:n, 0], normal[:n, 2], overlap[:n]])
    rows3 = rows3[np.lexsort(np.round(rows3.T, 9))]
    rows2 = np.repeat(rows2[np.lexsort(np.round(rows2.T, 9))], 2, axis=0)
    np.testing.assert_allclose(rows3, rows2, atol=1e-11)
    # and the same against a plane
    nw = np.array([np.sin(0.2), 0.0, np.cos(0.2)])
    x = nw * (np.sum(h_i * np.abs(nw @ Ri)) + r - 1e-4)
    n2 = rect_plane(x, Ri, h_i, r, np.zeros(3), nw, 0.0, normal, point, overlap, key)
    out3 = manifold_buffers()
    m3 = box_plane(x, Ri, h_i, r, np.zeros(3), nw, 0.0, *out3)
    assert m3 == 2 * n2
    np.testing.assert_allclose(np.sort(out3[2][:m3]), np.repeat(np.sort(overlap[:n2]), 2))
