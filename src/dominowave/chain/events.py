"""What each domino did: contacts, toppling, base slip, rotations, mechanism (Fig 5A).

Engine-independent: the input is a ``ChainRecord`` of plain arrays that any
simulator (or a video tracker) can fill -- a trajectory of the dominoes' rigid
motion and the log of every contact onset and end between bodies.

Sign conventions: the wave runs along +x; the forward tilt ``theta`` of a domino is
the angle of its long axis from the vertical towards +x (positive = falling
forward, negative = leaning back); base slip is the displacement along x of the
centre of its pivot (front bottom) sphere.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dominowave.chain.frames import Track
from dominowave.theory import Regime

__all__ = [
    "ChainRecord",
    "DominoEvents",
    "analyse_events",
    "contact_intervals",
    "critical_tilt",
    "forward_tilt",
    "merge_contacts",
    "neighbour_intervals",
    "rotate_vectors",
]

ONSET, END = 1, 0


@dataclass(frozen=True)
class ChainRecord:
    """Plain-array record of a domino chain run (SI units).

    ``times`` (F,) [s]; ``com`` (F, N, 3) [m] centres of mass; ``quat`` (F, N, 4)
    orientations (w, x, y, z); ``velocity`` (F, N, 3) [m/s]; ``angular_velocity``
    (F, N, 3) [rad/s] (world frame); ``axis`` (N, 3) each domino's long axis in
    the world frame at frame 0 (unit vectors, upright = +z); ``base_offset`` /
    ``top_offset`` (N, 3) [m] world vectors from the centre of mass to the pivot
    (front bottom) sphere centre / to the top, at frame 0. The contact log:
    ``ev_time`` (E,) [s], ``ev_i``, ``ev_j`` (E,) domino indices (``i < j``; walls are
    negative), ``ev_kind`` (E,) ``ONSET`` = 1 / ``END`` = 0. ``end_time`` [s] is when
    the record stops (open contacts end there).

    ``tracks`` (optional): each domino's frames as stored by a chain run
    (``chain.frames.Track``, the frames in which it may differ from the frame before);
    a record with tracks may leave ``com``, ``quat``, ``velocity`` and
    ``angular_velocity`` None, and the analysis reads the tracks (:meth:`domino_tracks`).
    """

    times: np.ndarray
    com: np.ndarray
    quat: np.ndarray
    velocity: np.ndarray
    angular_velocity: np.ndarray
    axis: np.ndarray
    base_offset: np.ndarray
    top_offset: np.ndarray
    ev_time: np.ndarray
    ev_i: np.ndarray
    ev_j: np.ndarray
    ev_kind: np.ndarray
    end_time: float
    tracks: tuple[Track, ...] | None = None

    def domino_tracks(self) -> tuple[Track, ...]:
        """Each domino's :class:`~dominowave.chain.frames.Track`: ``tracks`` if given,
        else every frame of the trajectory arrays."""
        if self.tracks is not None:
            return self.tracks
        frames = np.arange(self.times.size)
        return tuple(
            Track(
                frames,
                self.com[:, k],
                self.quat[:, k],
                self.velocity[:, k],
                self.angular_velocity[:, k],
            )
            for k in range(self.com.shape[1])
        )


def _quat_matrices(q: np.ndarray) -> np.ndarray:
    """Rotation matrices (..., 3, 3) of unit quaternions (..., 4) (w, x, y, z)."""
    w, x, y, z = np.moveaxis(q, -1, 0)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        -2,
    )


def rotate_vectors(quat: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """Carry world vectors given at frame 0 along with each body's rotation.

    ``quat`` (F, N, 4) unit quaternions (w, x, y, z), ``vectors`` (N, 3) -> (F, N, 3):
    ``R(q_f) R(q_0)^T v``.  The vectors are taken into the body frames once, ``u =
    R(q_0)^T v``, and turned by each frame's quaternion with ``u + w t + q x t``, ``t = 2
    q x u`` (q the vector part): a few operations per frame and body on (F, N) arrays,
    where the rotation matrices of every frame would take nine such arrays and a
    matrix product.
    """
    quat = np.asarray(quat, dtype=float)
    return _turn(quat, _in_body(quat[0], vectors))


def _in_body(quat: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """``R(q)^T v``: world vectors (N, 3) in the frames of bodies at orientations (N, 4)."""
    return np.einsum("nji,nj->ni", _quat_matrices(quat), vectors)


def _turn(quat: np.ndarray, body: np.ndarray) -> np.ndarray:
    """``R(q) u`` for body vectors ``u`` (..., 3) and unit quaternions (..., 4), broadcast
    together: ``u + w t + q x t`` with ``t = 2 q x u`` (q the vector part)."""
    w, x, y, z = np.moveaxis(quat, -1, 0)
    u0, u1, u2 = np.moveaxis(body, -1, 0)
    t0 = 2.0 * (y * u2 - z * u1)
    t1 = 2.0 * (z * u0 - x * u2)
    t2 = 2.0 * (x * u1 - y * u0)
    out = np.empty((*np.broadcast_shapes(w.shape, u0.shape), 3))
    out[..., 0] = u0 + w * t0 + (y * t2 - z * t1)
    out[..., 1] = u1 + w * t1 + (z * t0 - x * t2)
    out[..., 2] = u2 + w * t2 + (x * t1 - y * t0)
    return out


def forward_tilt(record: ChainRecord) -> np.ndarray:
    """Forward tilt ``theta`` (F, N) [rad] of each domino's long axis (see module doc)."""
    return _tilt(rotate_vectors(record.quat, record.axis))


def _tilt(axis: np.ndarray) -> np.ndarray:
    """Forward tilt [rad] of long axes ``axis`` (..., 3): from the vertical towards +x."""
    return np.arctan2(axis[..., 0], axis[..., 2])


def contact_intervals(record: ChainRecord, i: int, j: int) -> tuple[np.ndarray, np.ndarray]:
    """Onset and end times [s] of every contact between bodies ``i`` and ``j``.

    Returns two arrays of equal length ``K`` (one entry per contact, in time order);
    a contact still open at the end of the record ends at ``record.end_time``.
    """
    a, b = (i, j) if i < j else (j, i)
    sel = (record.ev_i == a) & (record.ev_j == b)
    t, kind = record.ev_time[sel], record.ev_kind[sel]
    order = np.argsort(t, kind="stable")
    return _intervals(t[order], kind[order], record.end_time)


def neighbour_intervals(record: ChainRecord, n: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """``contact_intervals(record, k, k + 1)`` for ``k = 0 .. n - 2``: the same arrays,
    from one sort of the event log by pair and time (stable: events at one time keep
    their order in the log), where a call per pair would scan the whole log each, a cost
    that grows as the square of the chain."""
    i, j = record.ev_i, record.ev_j
    sel = (i >= 0) & (j == i + 1) & (j < n)
    t, kind, pair = record.ev_time[sel], record.ev_kind[sel], i[sel]
    order = np.lexsort((t, pair))
    t, kind, pair = t[order], kind[order], pair[order]
    start = np.searchsorted(pair, np.arange(n))  # (the first event of each pair)
    return [
        _intervals(t[start[k] : start[k + 1]], kind[start[k] : start[k + 1]], record.end_time)
        for k in range(n - 1)
    ]


def _intervals(t: np.ndarray, kind: np.ndarray, end_time: float):
    """Onsets and ends [s] of the contacts of one pair from its events in time order
    (times ``t``, kinds ``kind``); a contact still open ends at ``end_time``."""
    onsets, ends = t[kind == ONSET], t[kind == END]
    if ends.size < onsets.size:  # still touching when the record stopped
        ends = np.append(ends, end_time)
    return onsets, ends[: onsets.size]


def merge_contacts(
    onsets: np.ndarray, ends: np.ndarray, min_gap: float
) -> tuple[np.ndarray, np.ndarray]:
    """Merge contacts separated by less than ``min_gap`` [s] into one collision.

    Two elastic bodies leaning on each other without dissipation chatter: the log
    shows many short separations that are one physical collision. Returns the
    onsets and ends of the merged collisions (``min_gap = 0``: unchanged).
    """
    if onsets.size == 0:
        return onsets, ends
    keep = np.concatenate([[True], onsets[1:] - ends[:-1] >= min_gap])
    last = np.concatenate([keep[1:], [True]])
    return onsets[keep], ends[last]


@dataclass(frozen=True)
class DominoEvents:
    """Per-domino events of one run; every array has shape (N,).

    Attributes
    ----------
    arrival : first contact with any lower-numbered domino [s] (0 for the pushed
        domino 0; NaN if never touched) -- the wave's arrival time.
    n_hits_from_prev, n_hits_on_next : number of collisions with domino ``n-1`` /
        ``n+1`` (multiple collisions counted; contacts closer than ``min_gap`` merged
        into one collision; 0 at the chain ends).
    n_contacts_on_next : number of raw contact onsets with ``n+1`` (chatter included).
    n_hits_in_passage : collisions of ``n`` on ``n+1`` that begin before the wave
        reaches ``n+2`` -- more than one is the paper's multiple collision within one
        cycle (Fig 6E); NaN-free, 0 where not defined.
    touched_two_ahead : whether domino ``n`` ever touched domino ``n+2``.
    first_hit_end : end of the first collision with domino ``n+1`` [s].
    topple_time : first time ``theta > critical_angle`` [s] (NaN: never).
    floor_time : first time the top comes within ``floor_tolerance`` of the floor
        height it would have lying flat (NaN: never) [s].
    rest_time : from this time on the domino stays below ``rest_speed`` [s] (NaN: moving
        at the end of the record).
    slip_final, slip_max : final and largest-magnitude (signed) displacement of the
        base along x [m]; positive = forward.
    max_forward, max_backward : largest forward tilt and largest backward lean
        (>= 0) [rad].
    rebound_angle : smallest tilt after the first collision with ``n+1`` ends and
        before the next collision with it begins [rad] (NaN if no such collision);
        0 = back to vertical as in the conservative EJ chain (eq 9a).
    mechanism : ``theory.Regime`` code of the motion right after the first hit
        (Fig 5A: 1 pure rotation, 2 forward rotation with slip, 3 backward rotation
        with slip, 4 translation; 0 = not hit).
    """

    arrival: np.ndarray
    n_hits_from_prev: np.ndarray
    n_hits_on_next: np.ndarray
    n_contacts_on_next: np.ndarray
    n_hits_in_passage: np.ndarray
    touched_two_ahead: np.ndarray
    first_hit_end: np.ndarray
    topple_time: np.ndarray
    floor_time: np.ndarray
    rest_time: np.ndarray
    slip_final: np.ndarray
    slip_max: np.ndarray
    max_forward: np.ndarray
    max_backward: np.ndarray
    rebound_angle: np.ndarray
    mechanism: np.ndarray

    def table(self) -> dict[str, np.ndarray]:
        """The attributes as a column dict (for CSV / rich tables)."""
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


def _mechanism(v_base: float, v_top: float, slip_tol: float) -> int:
    """Fig 5A class from the horizontal velocities of base and top just after a hit.

    Rotation rate ~ ``v_top - v_base``: no base velocity -> pure rotation; base
    moving with the top -> translation; top faster -> forward rotation with slip;
    top slower (leaning back) -> backward rotation with slip.
    """
    scale = max(abs(v_top), abs(v_base), 1e-300)
    if abs(v_base) <= slip_tol * scale:
        return int(Regime.PURE_ROTATION)
    if abs(v_top - v_base) <= slip_tol * scale:
        return int(Regime.TRANSLATION)
    if v_top > v_base:
        return int(Regime.FORWARD_ROTATION_SLIP)
    return int(Regime.BACKWARD_ROTATION_SLIP)


@dataclass(frozen=True)
class _Motion:
    """One domino's motion at the frames of its track (each (K,) or (K, 3)): the tilt
    ``theta`` [rad], the base's slip along x since frame 0 [m], whether the top is below
    the floor tolerance, the speed of the top [m/s], and for the mechanism class the
    base [m] and the top's velocity [m/s]."""

    theta: np.ndarray
    slip: np.ndarray
    below_floor: np.ndarray
    top_speed: np.ndarray
    base: np.ndarray
    v_top: np.ndarray


def _motions(tracks: tuple[Track, ...], axis, base_offset, top_offset, floor_height):
    """The motion of every domino from its track (a :class:`_Motion` each), computed on the
    tracks joined end to end; ``axis``, ``base_offset``, ``top_offset`` (N, 3) as in
    ``ChainRecord``, ``floor_height`` (N,) [m]."""
    sizes = np.array([track.frames.size for track in tracks])
    owner = np.repeat(np.arange(sizes.size), sizes)  # (K,) the domino of each row
    first = np.cumsum(sizes) - sizes  # (N,) each track's row of frame 0
    com, quat, v, w = (
        np.concatenate([getattr(track, k) for track in tracks])
        for k in ("com", "quat", "velocity", "angular_velocity")
    )
    # the three vectors of each domino in its body frame at frame 0: (N, 3 vectors, 3)
    vectors = np.stack([axis, base_offset, top_offset], axis=1)
    body = _in_body(np.repeat(quat[first], 3, axis=0), vectors.reshape(-1, 3))
    # (np.take: a gather of whole rows, many times faster than fancy indexing)
    turned = _turn(quat[:, None], np.take(body.reshape(-1, 3, 3), owner, 0))  # (K, 3, 3)
    base = com + turned[:, 1]
    top_rel = turned[:, 2]
    v_top = np.empty_like(top_rel)
    for a, b, c in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        v_top[:, a] = v[:, a] + (w[:, b] * top_rel[:, c] - w[:, c] * top_rel[:, b])
    columns = (
        _tilt(turned[:, 0]),  # theta
        base[:, 0] - base[first, 0][owner],  # slip
        (com + top_rel)[:, 2] < np.asarray(floor_height)[owner],  # below_floor
        np.linalg.norm(v_top, axis=-1),  # top_speed
        base,
        v_top,
    )
    split = np.cumsum(sizes)[:-1]
    return [
        _Motion(*rows)
        for rows in zip(*(np.split(column, split) for column in columns), strict=True)
    ]


def _first_time(times: np.ndarray, track: Track, mask: np.ndarray) -> float:
    """First time [s] at which ``mask`` (K,) of the track's frames holds; NaN if never.
    A state that holds on after its frame cannot hold there first."""
    return float(times[track.frames[np.argmax(mask)]]) if mask.any() else math.nan


def _rest_time(times: np.ndarray, track: Track, moving: np.ndarray) -> float:
    """The time [s] of the frame after the last one in which ``moving`` (K,) holds
    (NaN: moving at the last frame; the first frame's time if never moving)."""
    if not moving.any():
        return float(times[0])
    last = moving.size - 1 - np.argmax(moving[::-1])
    after = track.last_frame_of(times.size)[last] + 1
    return float(times[after]) if after < times.size else math.nan


def _lowest_tilt(times: np.ndarray, track: Track, theta, after: float, before: float):
    """Smallest tilt ``theta`` (K,) [rad] in the frames with ``after < time < before``
    [s] (NaN if there are none)."""
    lo = np.searchsorted(times, after, side="right")
    hi = np.searchsorted(times, before, side="left")
    if lo >= hi:
        return math.nan
    return float(theta[track.at(lo) : track.at(hi - 1) + 1].min())


def _frame_events(times, tracks, motion, critical_angle, rest_speed) -> dict:
    """The events of ``DominoEvents`` that the frames give, (N,) each, from every
    domino's track and motion: the first toppled and floor times, the rest time, the
    final and largest slip, the largest forward and backward tilt."""
    rows = [
        {
            "topple_time": _first_time(times, track, m.theta > critical_angle),
            "floor_time": _first_time(times, track, m.below_floor),
            "rest_time": _rest_time(times, track, m.top_speed >= rest_speed),
            "slip_final": m.slip[-1],
            "slip_max": m.slip[np.argmax(np.abs(m.slip))],
            # (np.maximum: max(-0.0, 0.0) would keep the -0.0 of an upright domino)
            "max_forward": float(np.maximum(m.theta.max(), 0.0)),
            "max_backward": float(np.maximum(-m.theta.min(), 0.0)),
        }
        for track, m in zip(tracks, motion, strict=True)
    ]
    return {key: np.array([row[key] for row in rows]) for key in rows[0]}


def analyse_events(
    record: ChainRecord,
    critical_angle: float,
    rest_speed: float = 1e-3,
    floor_tolerance: float = 0.1,
    slip_tol: float = 0.05,
    min_gap: float = 0.0,
) -> DominoEvents:
    """Events of every domino from a ``ChainRecord`` (see ``DominoEvents``).

    The motion is read from each domino's frames (``ChainRecord.domino_tracks``): with
    the tracks of a chain run, only the frames in which that domino may have moved, which
    give every event exactly as every frame would.

    Parameters
    ----------
    critical_angle : tilt [rad] past which a domino topples under gravity alone.
    rest_speed : speed of the top [m/s] below which a domino counts as at rest.
    floor_tolerance : fraction of the domino's height: "hit the floor" when the top
        is lower than that fraction of the height above the floor.
    slip_tol : relative velocity tolerance of the mechanism classification.
    min_gap : contacts of a pair separated by less than this [s] are one collision
        (``merge_contacts``); a collision time is a natural choice.
    """
    times = np.asarray(record.times, dtype=float)
    tracks = record.domino_tracks()
    n = len(tracks)
    height = record.top_offset[:, 2] - record.base_offset[:, 2]
    motion = _motions(
        tracks, record.axis, record.base_offset, record.top_offset, floor_tolerance * height
    )
    intervals = neighbour_intervals(record, n)  # (each domino's contacts with the next)

    ev_i, ev_j = record.ev_i, record.ev_j
    body = (ev_i >= 0) & (ev_j >= 0) & (record.ev_kind == ONSET)
    # the arrival: the first onset with a lower-numbered domino
    behind = body & (ev_i < ev_j) & (ev_j < n)
    first = np.full(n, np.inf)
    np.minimum.at(first, ev_j[behind], record.ev_time[behind])
    arrival = np.where(np.isfinite(first), first, np.nan)
    arrival[0] = 0.0
    two_ahead = np.zeros(n, bool)
    two_ahead[ev_i[body & (ev_j == ev_i + 2) & (ev_j < n)]] = True
    hits_prev = np.zeros(n, int)
    hits_next = np.zeros(n, int)
    contacts_next = np.zeros(n, int)
    in_passage = np.zeros(n, int)
    first_end = np.full(n, np.nan)
    rebound = np.full(n, np.nan)
    mechanism = np.zeros(n, int)
    for k in range(1, n):
        # the mechanism, at the first frame after the end of the first hit on k
        on, off = intervals[k - 1]
        f = int(np.searchsorted(times, off[0])) if on.size else times.size
        if f < times.size:
            m, i = motion[k], tracks[k].at(f)
            r = m.base[i] - tracks[k].com[i]
            v, w = tracks[k].velocity[i], tracks[k].angular_velocity[i]
            v_base = v[0] + (w[1] * r[2] - w[2] * r[1])
            mechanism[k] = _mechanism(v_base, m.v_top[i, 0], slip_tol)
    for k in range(n - 1):
        on, off = intervals[k]
        contacts_next[k] = on.size
        on, off = merge_contacts(on, off, min_gap)
        hits_next[k] = on.size
        if k + 2 < n and np.isfinite(arrival[k + 2]):
            in_passage[k] = int(np.sum(on < arrival[k + 2]))
        hits_prev[k + 1] = on.size
        if on.size:
            first_end[k] = off[0]
            later = on[1] if on.size > 1 else record.end_time
            rebound[k] = _lowest_tilt(times, tracks[k], motion[k].theta, off[0], later)
    return DominoEvents(
        arrival=arrival,
        n_hits_from_prev=hits_prev,
        n_hits_on_next=hits_next,
        n_contacts_on_next=contacts_next,
        n_hits_in_passage=in_passage,
        touched_two_ahead=two_ahead,
        first_hit_end=first_end,
        **_frame_events(times, tracks, motion, critical_angle, rest_speed),
        rebound_angle=rebound,
        mechanism=mechanism,
    )


def critical_tilt(half_base: float, com_height: float) -> float:
    """Tilt [rad] at which the centre of mass passes over the front support point."""
    return math.atan2(half_base, com_height)
