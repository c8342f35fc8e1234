"""The contact geometry of one pair of fallen dominoes: ns per box-box pair.

The 3D standard-domino Hertz chain of ``hertz_chain.py`` (--n dominoes, held, safety 0.7)
is run to each of --times; at each, every box-box pair within reach of the engine's
bounding tests (``boxes._within_reach``: fallen dominoes leaning on each other, the
falling ones touching) is taken with its positions, orientations and margin.  The
contact manifold of all of them (``shapes.cuboid.box_box``) is then timed in a compiled
loop (CPU time per pair, median of --repeat loops of --loops passes over the pairs), and
the share of the pairs whose exact-deepest-point search the separating axes let
box_box skip (``separating_axes``' ``sep_sure``, ``manifold_is_deepest``) is counted.
A second loop times what the engine does for such a pair: the face test of
``_within_reach`` (``faces_separate``) and then ``box_box`` on the relative frame that
test left (``frame_ready=True``); and, for comparison, the same two calls with the frame
computed again by box_box.

Run:  python benchmarks/box_pair_geometry.py [--n 30] [--times 0.25 0.5 1.0 1.5]
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np
from hertz_chain import build, chain_params, hertz_chain
from numba import njit

from dominowave.dem.boxes import _within_reach
from dominowave.dem.shapes.cuboid import (
    MAX_POINTS,
    box_box,
    faces_separate,
    manifold_is_deepest,
    separating_axes,
)
from dominowave.kernel_cache import install

# the compiled loop below inlines the package's kernels: stale with any change of it
install(Path(__file__).parent)


def pairs_within_reach(sim) -> list[tuple]:
    """(x_i, R_i, h_i, r_i, x_j, R_j, h_j, r_j, margin) of every box-box pair of ``sim``
    that passes the engine's bounding tests now (copies)."""
    b, x, w = sim.bodies, sim.boxes, sim.walls
    out = []
    for a in range(x.body.shape[0]):
        for j in range(a + 1, x.body.shape[0]):
            margin = _within_reach(b, x, w, a, j, False)
            if margin >= 0.0:
                bi, bj = x.body[a], x.body[j]
                out.append(
                    (b.pos[bi].copy(), b.rot[bi].copy(), x.half[a].copy(), x.radius[a],
                     b.pos[bj].copy(), b.rot[bj].copy(), x.half[j].copy(), x.radius[j], margin)
                )  # fmt: skip
    return out


@njit(cache=True, error_model="numpy", _nrt=False)
def _manifolds(xs, Rs, hs, rs, margins, passes, work, normal, point, overlap, key):
    """``passes`` times the manifold of every pair k (xs[k, 0] with xs[k, 1], ...)."""
    points = 0
    for _ in range(passes):
        for k in range(xs.shape[0]):
            points += box_box(
                xs[k, 0], Rs[k, 0], hs[k, 0], rs[k, 0], xs[k, 1], Rs[k, 1], hs[k, 1], rs[k, 1],
                margins[k], work, normal, point, overlap, key,
            )  # fmt: skip
    return points


@njit(cache=True, error_model="numpy", _nrt=False)
def _engine_pairs(xs, Rs, hs, rs, margins, passes, shared, work, normal, point, overlap, key):
    """``passes`` times the engine's work on every pair k: the face test, then the
    manifold (``shared``: on the frame the test left)."""
    points = 0
    for _ in range(passes):
        for k in range(xs.shape[0]):
            reach = rs[k, 0] + rs[k, 1] + margins[k]
            if faces_separate(xs[k, 0], Rs[k, 0], hs[k, 0], xs[k, 1], Rs[k, 1], hs[k, 1],
                              reach, work):  # fmt: skip
                continue
            points += box_box(
                xs[k, 0], Rs[k, 0], hs[k, 0], rs[k, 0], xs[k, 1], Rs[k, 1], hs[k, 1], rs[k, 1],
                margins[k], work, normal, point, overlap, key, shared,
            )  # fmt: skip
    return points


def _median_ns(run, loops, repeat, n_pairs):
    """Median over ``repeat`` of the CPU time [ns] per pair of ``run(loops)``."""
    times = []
    for _ in range(repeat):
        t0 = time.process_time()
        run(loops)
        times.append((time.process_time() - t0) / loops / n_pairs)
    return 1e9 * statistics.median(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=30)
    parser.add_argument("--times", type=float, nargs="+", default=[0.25, 0.5, 1.0, 1.5])
    parser.add_argument("--loops", type=int, default=200)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    ns = argparse.Namespace(n=args.n, gap=0.02, floor="hardwood", young=2.5e9, poisson=0.35)
    sim = build(hertz_chain(chain_params(ns, held=True), None, 0.7))
    pairs = []
    for t in args.times:
        sim.run(until=t)
        pairs += pairs_within_reach(sim)
    xs = np.array([[p[0], p[4]] for p in pairs])
    Rs = np.array([[p[1], p[5]] for p in pairs])
    hs = np.array([[p[2], p[6]] for p in pairs])
    rs = np.array([[p[3], p[7]] for p in pairs])
    margins = np.array([p[8] for p in pairs])
    work = np.zeros((2, 9, 4))
    out = (np.zeros((MAX_POINTS, 3)), np.zeros((MAX_POINTS, 3)), np.zeros(MAX_POINTS),
           np.zeros(MAX_POINTS, np.int64))  # fmt: skip
    skipped = 0
    for p in pairs:
        n = box_box(*p, work, *out)
        sure = separating_axes(p[0], p[1], p[2], p[4], p[5], p[6], np.inf, work)[11]
        tol = 1e-9 * (p[2].max() + p[6].max() + p[3] + p[7])
        skipped += manifold_is_deepest(out[2], n, p[3] + p[7], sure, tol)
    args_ = (xs, Rs, hs, rs, margins)
    _manifolds(*args_, 1, work, *out)  # (compilation)
    _engine_pairs(*args_, 1, True, work, *out)
    timing = (args.loops, args.repeat, len(pairs))
    alone = _median_ns(lambda k: _manifolds(*args_, k, work, *out), *timing)
    engine = {}
    for shared in (True, False):
        engine[shared] = _median_ns(
            lambda k, s=shared: _engine_pairs(*args_, k, s, work, *out), *timing
        )
    print(
        f"{len(pairs)} box-box pairs within reach ({args.n} dominoes at t = {args.times} s); "
        f"deepest-point search skipped for {skipped}; median of {args.repeat}, ns per pair: "
        f"box_box {alone:.0f}; face test + box_box on its frame {engine[True]:.0f} "
        f"(frame computed twice: {engine[False]:.0f})"
    )


if __name__ == "__main__":
    main()
