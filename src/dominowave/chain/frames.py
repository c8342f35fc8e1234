"""The trajectory frames of a chain run, each domino stored only where it moves.

The engine holds a held or sleeping body's state to the bit, so in a long chain most of
a frame repeats the frame before it: the dominoes ahead of the wave stand, those behind
it sleep. Dense frames (frames x dominoes) grow as the square of the chain's length
(about 270 MB for 300 standard dominoes), and so does every pass over them.

:class:`SparseFrames` keeps a row (frame, domino, state) for every domino at the first
frame, and after it for a domino in a frame where its state may have changed: from dense
frames, where any bit of its position, orientation, velocity or angular velocity differs
from the frame before; from the engine's frames (``dem.FrameRows``), where the engine
recorded it (the range of bodies not held at some step since the frame before, which may
hold a few held ones).  Every other domino
carries its last stored state. So :meth:`SparseFrames.dense` rebuilds every frame to
the bit, and each domino's :class:`Track` (its rows) holds every distinct state it went
through: a value that depends on one frame's state is, at any frame, its value at the
last frame of the track at or before it (:meth:`Track.at`).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from dominowave.dem.simulation import carried_rows

__all__ = ["FIELDS", "SparseFrames", "Track"]

FIELDS = ("positions", "quaternions", "velocities", "angular_velocities")
"""The per-body arrays of a frame (``dem`` run result names): (F, N, 3 or 4) each."""


@dataclass(frozen=True)
class Track:
    """One domino's stored frames: ``frames`` (K,) ascending frame indices, the first 0;
    ``com`` (K, 3) [m], ``quat`` (K, 4) (w, x, y, z), ``velocity`` (K, 3) [m/s],
    ``angular_velocity`` (K, 3) [rad/s] at those frames. At a frame not in ``frames``
    the domino is in the state of the last stored frame before it."""

    frames: np.ndarray
    com: np.ndarray
    quat: np.ndarray
    velocity: np.ndarray
    angular_velocity: np.ndarray

    def at(self, frame) -> np.ndarray:
        """Index into the track of the state at ``frame`` (int or array of frame
        indices >= 0): the last stored frame at or before it."""
        return np.searchsorted(self.frames, frame, side="right") - 1

    def last_frame_of(self, n_frames: int) -> np.ndarray:
        """(K,) the last frame index at which each stored state holds: the frame before
        the next stored one, or ``n_frames - 1``."""
        return np.append(self.frames[1:] - 1, n_frames - 1)


class SparseFrames:
    """The frames of a run, appended piece by piece; see the module doc.

    ``first``: the initial frame, ``times`` (1,) [s] and :data:`FIELDS` (1, N, d)."""

    def __init__(self, first: dict[str, np.ndarray]):
        self._times = [np.asarray(first["times"], float)]
        self._last = {k: np.array(first[k][0]) for k in FIELDS}  # (N, d) the latest state
        n = self._last[FIELDS[0]].shape[0]
        # pieces of rows, in frame order: (frame (R,), domino (R,), {field: (R, d)})
        self._rows = [
            (np.zeros(n, np.int64), np.arange(n), {k: np.array(first[k][0]) for k in FIELDS})
        ]
        self.n_frames = 1

    @classmethod
    def from_dense(cls, frames: dict[str, np.ndarray]) -> SparseFrames:
        """The frames ``frames`` (``times`` (F,) and :data:`FIELDS` (F, N, d))."""
        out = cls({k: frames[k][:1] for k in ("times", *FIELDS)})
        out.append({k: frames[k][1:] for k in ("times", *FIELDS)})
        return out

    @property
    def n_bodies(self) -> int:
        """The number of bodies (dominoes) of every frame."""
        return self._last[FIELDS[0]].shape[0]

    @property
    def times(self) -> np.ndarray:
        """(F,) [s] the time of every frame."""
        if len(self._times) > 1:
            self._times[:] = [np.concatenate(self._times)]
        return self._times[0]

    def append(self, piece: dict[str, np.ndarray]) -> None:
        """Add the frames of ``piece`` (``times`` (F,) and :data:`FIELDS` (F, N, d)): a
        row for each domino in each frame where its state differs from the frame before."""
        changed = np.zeros(piece[FIELDS[0]].shape[:2], bool)  # (F, N)
        for k in FIELDS:
            now = np.ascontiguousarray(piece[k])
            changed[:1] |= _differs(now[:1], self._last[k])
            changed[1:] |= _differs(now[1:], now[:-1])
        frame, body = np.nonzero(changed)
        self._add_rows(frame, body, {k: piece[k][frame, body] for k in FIELDS})
        self._add_times(piece["times"])

    def append_rows(self, rows) -> None:
        """Add the frames of one ``dem`` run as the engine records them
        (``dem.FrameRows``): its rows, but those of its first frame (which has every
        body) only where the state differs from the one before."""
        if rows.n_bodies != self.n_bodies:
            raise ValueError(f"frames of {rows.n_bodies} bodies, these have {self.n_bodies}")
        frame, body = rows.frame_and_body()
        n0 = rows.start[min(1, rows.times.size)]  # (the rows of the first frame)
        changed = np.zeros(n0, bool)
        for k in FIELDS:
            changed |= _differs(getattr(rows, k)[:n0], self._last[k][body[:n0]])
        kept = np.flatnonzero(changed)
        self._add_rows(frame[kept], body[kept], {k: getattr(rows, k)[kept] for k in FIELDS})
        self._add_rows(frame[n0:], body[n0:], {k: getattr(rows, k)[n0:].copy() for k in FIELDS})
        self._add_times(rows.times)

    def _add_rows(self, frame, body, values) -> None:
        """Add the rows ``frame`` (R,) (frame indices of the frames being added,
        ascending), ``body`` (R,) and ``values`` (:data:`FIELDS` (R, d))."""
        # each domino's latest state: its last row
        latest, last = np.unique(body[::-1], return_index=True)
        for k in FIELDS:
            self._last[k][latest] = values[k][body.size - 1 - last]
        self._rows.append((frame + self.n_frames, body, values))

    def _add_times(self, times) -> None:
        """Add frames at ``times`` (F,) [s], after their rows."""
        self._times.append(np.asarray(times, float))
        self.n_frames += len(times)

    def _joined(self) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
        """Every row: ``(frame, domino, values)``, in frame order."""
        if len(self._rows) > 1:
            frame, body, values = zip(*self._rows, strict=True)
            joined = {k: np.concatenate([v[k] for v in values]) for k in FIELDS}
            self._rows[:] = [(np.concatenate(frame), np.concatenate(body), joined)]
        return self._rows[0]

    def dense(self) -> dict[str, np.ndarray]:
        """Every frame: ``times`` (F,) and :data:`FIELDS` (F, N, d), as recorded."""
        frame, body, values = self._joined()
        source = carried_rows(frame, body, self.n_frames, self.n_bodies)
        # (np.take: a gather of whole rows, many times faster than fancy indexing)
        return {"times": self.times.copy(), **{k: np.take(values[k], source, 0) for k in FIELDS}}

    def tracks(self) -> list[Track]:
        """Each domino's :class:`Track`: its rows."""
        frame, body, values = self._joined()
        order = np.argsort(body, kind="stable")  # (by domino, each in frame order)
        bounds = np.searchsorted(body[order], np.arange(self.n_bodies + 1))
        frame, columns = frame[order], [np.take(values[k], order, 0) for k in FIELDS]
        return [
            Track(frame[lo:hi], *(c[lo:hi] for c in columns))
            for lo, hi in itertools.pairwise(bounds)
        ]


def _differs(now: np.ndarray, before: np.ndarray) -> np.ndarray:
    """Whether each state (the last axis) of ``now`` differs from ``before`` in any bit:
    -0.0 is not 0.0, and a NaN is itself.  Both C-contiguous along the last axis."""
    return (now.view(np.int64) != before.view(np.int64)).any(axis=-1)
