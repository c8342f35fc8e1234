"""The frames of a chain run stored per domino where it moves (chain.frames): every frame
rebuilt to the bit, whatever the pieces the run came in, and each domino's track holding
its state at every frame."""

from __future__ import annotations

import itertools

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from dominowave.chain.frames import BLOCK, FIELDS, SparseFrames

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


def _in_pieces(frames, cuts) -> SparseFrames:
    """``frames`` appended in the pieces between the frame indices ``cuts``."""
    out = SparseFrames({k: v[:1] for k, v in frames.items()})
    edges = [1, *sorted(c for c in cuts if 1 <= c < len(frames["times"])), len(frames["times"])]
    for lo, hi in itertools.pairwise(edges):
        out.append({k: v[lo:hi] for k, v in frames.items()})
    return out


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    n_frames=st.integers(1, 3 * BLOCK + 5),
    n_bodies=st.integers(1, 6),
    cuts=st.lists(st.integers(0, 3 * BLOCK + 5), max_size=5),
)
def test_every_frame_is_rebuilt_to_the_bit_and_every_track_holds_its_state(
    seed, n_frames, n_bodies, cuts
):
    frames = _frames(np.random.default_rng(seed), n_frames, n_bodies)
    stored = _in_pieces(frames, cuts)
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
    """Ten bodies over the first frame and four blocks, of which only body 3 moves, in the
    second block and back: it is stored in the first frame and that block, every other
    body in the first frame alone."""
    rng = np.random.default_rng(1)
    frames = _frames(rng, 4 * BLOCK + 1, 10)
    for k in FIELDS:
        frames[k][:] = frames[k][:1]
        frames[k][BLOCK + 5 : BLOCK + 9, 3] += 1.0
    tracks = _in_pieces(frames, []).tracks()
    np.testing.assert_array_equal(tracks[3].frames, [0, *range(BLOCK + 1, 2 * BLOCK + 1)])
    assert all(tracks[b].frames.tolist() == [0] for b in range(10) if b != 3)
