"""The trajectory frames of a chain run, each domino stored only where it moves.

The engine holds a held or sleeping body's state to the bit, so in a long chain most of
a frame repeats the frame before it: the dominoes ahead of the wave stand, those behind
it sleep. Dense frames (frames x dominoes) grow as the square of the chain's length
(about 270 MB for 300 standard dominoes), and so does every pass over them.

:class:`SparseFrames` keeps the frames in blocks of at most :data:`BLOCK` consecutive
frames. A block stores the dominoes whose state (any bit of position, orientation,
velocity or angular velocity) differs in one of its frames from their state before the
block; every other domino carries its last stored state through the block. So
:meth:`SparseFrames.dense` rebuilds every frame to the bit, and each domino's
:class:`Track` (the frames of the blocks that store it) holds every distinct state it
went through: a value that depends on one frame's state is, at any frame, its value at
the last frame of the track at or before it (:meth:`Track.at`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["BLOCK", "FIELDS", "SparseFrames", "Track"]

FIELDS = ("positions", "quaternions", "velocities", "angular_velocities")
"""The per-body arrays of a frame (``dem`` run result names): (F, N, 3 or 4) each."""

BLOCK = 64
"""Frames per block: a domino that moves in one frame of a block is stored for the whole
block, so short blocks store less and long ones cost less bookkeeping."""


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
        # blocks: (first frame, stored dominoes (C,), {field: (frames, C, d)})
        self._blocks = [(0, np.arange(n), {k: np.array(first[k]) for k in FIELDS})]
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
        """Add the frames of ``piece`` (``times`` (F,) and :data:`FIELDS` (F, N, d))."""
        times = np.asarray(piece["times"], float)
        for lo in range(0, times.size, BLOCK):
            hi = min(times.size, lo + BLOCK)
            self._add_block(times[lo:hi], {k: piece[k][lo:hi] for k in FIELDS})

    def _add_block(self, times: np.ndarray, block: dict[str, np.ndarray]) -> None:
        """Store the frames ``block`` (at most :data:`BLOCK`) of the dominoes that changed."""
        changed = np.zeros(self.n_bodies, bool)
        for k in FIELDS:
            # bit for bit: -0.0 is not 0.0, and a NaN is itself
            now = np.ascontiguousarray(block[k]).view(np.int64)
            # (over the frames first: that reduction runs along contiguous memory)
            changed |= (now != self._last[k].view(np.int64)).any(axis=0).any(axis=1)
        cols = np.flatnonzero(changed)
        self._blocks.append((self.n_frames, cols, {k: block[k][:, cols] for k in FIELDS}))
        for k in FIELDS:
            self._last[k] = np.array(block[k][-1])
        self._times.append(times)
        self.n_frames += times.size

    def dense(self) -> dict[str, np.ndarray]:
        """Every frame: ``times`` (F,) and :data:`FIELDS` (F, N, d), as recorded."""
        out = {"times": self.times.copy()}
        for k in FIELDS:
            arr = np.empty((self.n_frames, *self._last[k].shape))
            for start, cols, data in self._blocks:
                stop = start + data[k].shape[0]
                if start > 0:
                    arr[start:stop] = arr[start - 1]  # (the dominoes not stored carry on)
                arr[start:stop, cols] = data[k]
            out[k] = arr
        return out

    def tracks(self) -> list[Track]:
        """Each domino's :class:`Track`: the frames of the blocks that store it."""
        # (block, column in it) of every block that stores each domino
        parts: list[list[tuple[int, int]]] = [[] for _ in range(self.n_bodies)]
        for b, (_, cols, _) in enumerate(self._blocks):
            for j, k in enumerate(cols):
                parts[k].append((b, j))
        out = []
        for k in range(self.n_bodies):
            blocks = [self._blocks[b] for b, _ in parts[k]]
            frames = np.concatenate([np.arange(s, s + d[FIELDS[0]].shape[0]) for s, _, d in blocks])
            arrays = [
                np.concatenate(
                    [d[f][:, j] for (_, _, d), (_, j) in zip(blocks, parts[k], strict=True)]
                )
                for f in FIELDS
            ]
            out.append(Track(frames, *arrays))
        return out
