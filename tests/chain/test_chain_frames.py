"""The frames of a chain run stored per domino where it moves (chain.frames): every frame
rebuilt to the bit, whatever the pieces the run came in and whether they come dense or as
the engine's rows, and each domino's track holding its state at every frame."""

from __future__ import annotations

import itertools
import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from dominowave.chain import DominoChain, Push
from dominowave.chain.frames import FIELDS, SparseFrames
from dominowave.chain.presets import standard_domino
from dominowave.dem import FrameRows

WIDTH = dict(zip(FIELDS, (3, 4, 3, 3), strict=True))


def _frames(rng, n_frames: int, n_bodies: int) -> dict[str, np.ndarray]:
    """Random frames in which body k moves only in frames lo_k .. hi_k - 1 and holds its
    state before and after, as a domino held until touched and put to sleep does; a -0.0
    and a NaN where a bit-blind comparison would lose them."""
    out = {"times": np.arange(n_frames) * 1e-3}
    moves = [np.sort(rng.integers(0, n_frames + 1, 2)) for _ in range(n_bodies)]
    for k, width in WIDTH.items():
        a = rng.standard_normal((n_frames, n_bodies, width))
        for b, (lo, hi) in enumerate(moves):
            a[:lo, b] = a[lo, b] if lo < n_frames else 0.0
            a[hi:, b] = a[hi - 1, b] if hi > 0 else a[0, b]
        out[k] = a
    out["velocities"][-1, 0, 0] = -0.0
    out["angular_velocities"][-1, -1, 2] = np.nan
    return out


def _in_pieces(frames, cuts, rows=None) -> SparseFrames:
    """``frames`` appended in the pieces between the frame indices ``cuts``: dense, or
    as the engine records them if ``rows`` (a generator: :func:`_rows`)."""
    out = SparseFrames({k: v[:1] for k, v in frames.items()})
    edges = [1, *sorted(c for c in cuts if 1 <= c < len(frames["times"])), len(frames["times"])]
    for lo, hi in itertools.pairwise(edges):
        piece = {k: v[lo:hi] for k, v in frames.items()}
        if rows is None:
            out.append(piece)
        else:
            out.append_rows(_rows(piece, rows))
    return out


def _rows(piece, rng) -> FrameRows:
    """``piece`` as the engine records a run's frames: the first frame with every body,
    each other with the bodies of a range that holds every body whose state changed
    since the frame before, widened at random (engine._record_frame)."""
    n_frames, n_bodies = piece["positions"].shape[:2]
    first, count = [0][:n_frames], [n_bodies][:n_frames]
    for f in range(1, n_frames):
        moved = np.zeros(n_bodies, bool)
        for k in FIELDS:
            moved |= (piece[k][f].view(np.int64) != piece[k][f - 1].view(np.int64)).any(axis=1)
        lo, hi = (np.flatnonzero(moved)[[0, -1]] + (0, 1)) if moved.any() else (0, 0)
        lo, hi = rng.integers(0, lo + 1), rng.integers(hi, n_bodies + 1)
        first.append(lo)
        count.append(hi - lo)
    first, count = np.array(first, np.int64), np.array(count, np.int64)
    rows = FrameRows(
        n_bodies=n_bodies,
        times=piece["times"],
        first=first,
        start=np.concatenate(([0], np.cumsum(count))),
        **{k: np.zeros((count.sum(), piece[k].shape[2])) for k in FIELDS},
    )
    frame, body = rows.frame_and_body()
    for k in FIELDS:
        getattr(rows, k)[:] = piece[k][frame, body]
    return rows


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    n_frames=st.integers(1, 200),
    n_bodies=st.integers(1, 6),
    cuts=st.lists(st.integers(0, 200), max_size=5),
    engine_rows=st.booleans(),
)
def test_every_frame_is_rebuilt_to_the_bit_and_every_track_holds_its_state(
    seed, n_frames, n_bodies, cuts, engine_rows
):
    rng = np.random.default_rng(seed)
    frames = _frames(rng, n_frames, n_bodies)
    stored = _in_pieces(frames, cuts, rng if engine_rows else None)
    dense = stored.dense()
    assert stored.n_frames == n_frames
    np.testing.assert_array_equal(dense["times"], frames["times"])
    for k in FIELDS:
        np.testing.assert_array_equal(dense[k].view(np.int64), frames[k].view(np.int64))
    fields = ("com", "quat", "velocity", "angular_velocity")
    for b, track in enumerate(stored.tracks()):
        assert track.frames[0] == 0 and np.all(np.diff(track.frames) > 0)
        at = track.at(np.arange(n_frames))
        for name, k in zip(fields, FIELDS, strict=True):
            got = getattr(track, name)[at]
            np.testing.assert_array_equal(got.view(np.int64), frames[k][:, b].view(np.int64))


def test_a_domino_that_holds_still_is_not_stored():
    """Ten bodies over 257 frames, of which only body 3 moves, to a new state in frame 69
    and back in frame 73: it is stored in the first frame and those two, every other body
    in the first frame alone; from the engine's rows, in the frames that record it."""
    rng = np.random.default_rng(1)
    frames = _frames(rng, 257, 10)
    for k in FIELDS:
        frames[k][:] = frames[k][:1]
        frames[k][69:73, 3] += 1.0
    tracks = _in_pieces(frames, []).tracks()
    np.testing.assert_array_equal(tracks[3].frames, [0, 69, 73])
    assert all(tracks[b].frames.tolist() == [0] for b in range(10) if b != 3)
    piece = {k: v[1:] for k, v in frames.items()}
    rows = _rows(piece, rng)
    stored = SparseFrames({k: v[:1] for k, v in frames.items()})
    stored.append_rows(rows)
    recorded = rows.frame_and_body()
    for b, track in enumerate(stored.tracks()):
        expected = 1 + recorded[0][(recorded[1] == b) & (recorded[0] > 0)]
        np.testing.assert_array_equal(track.frames, [0, *expected])


def test_a_chain_keeps_from_the_engine_rows_every_frame_of_the_chain():
    """The standard 20-domino box chain, held until touched and asleep at rest: its
    frames kept from the engine's rows (advanced 2000 steps at a time) are, to the bit,
    those of the same chain advanced one frame at a time, whose every frame the engine
    records whole; and every domino's track holds its state at every frame."""
    chains = []
    for piece in (2000, None):
        p = standard_domino(
            gap=0.00938, floor="felt", n_dominoes=20, friction_dominoes=0.3, friction_floor=0.3
        )
        stepper = DominoChain(p).stepper(Push(omega=math.sqrt(p.g / p.height)))
        while not stepper.advance(piece or stepper.every):
            pass
        chains.append(stepper.frames)
    rows, whole = (frames.dense() for frames in chains)
    for k in ("times", *FIELDS):
        np.testing.assert_array_equal(rows[k].view(np.int64), whole[k].view(np.int64), k)
    frames = np.arange(chains[0].n_frames)
    for b, track in enumerate(chains[0].tracks()):
        for k, name in zip(FIELDS, ("com", "quat", "velocity", "angular_velocity"), strict=True):
            got = getattr(track, name)[track.at(frames)]
            np.testing.assert_array_equal(got.view(np.int64), whole[k][:, b].view(np.int64))
    assert sum(t.frames.size for t in chains[0].tracks()) < 0.6 * whole["positions"].shape[0] * 20
