"""Box chains held until touched against the same chains with every box free.

A box starts in equilibrium on its flat base, so holding it until it is first touched
must change nothing but the cost: the reference is the free chain, run by the same
engine (docs/shape.md, "Holding a box until it is touched"). The tolerance is the
chain's own sensitivity to round-off: a push changed by one part in 1e12 moves the
arrival times of these short chains by less than 1e-10 (docs/shape/held_vs_free.csv),
where the release step of an earlier engine (half kick, no floor) moved domino 2's by
3.8e-5.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from dominowave.chain import ChainParams, DominoChain, Push

COMMON = dict(n_dominoes=8, shape="box", friction_dominoes=0.3, friction_floor=0.5)


def _arrivals(held: bool, **case) -> np.ndarray:
    p = ChainParams(held=held, **COMMON, **case)
    chain = DominoChain(p, sleep=False)  # (a free domino at rest would fall asleep: held)
    return np.asarray(chain.run(Push(omega=1.2 * math.sqrt(p.g / p.height))).arrival)


@pytest.mark.parametrize(
    "case",
    [dict(model="2d"), dict(model="3d", placement_along=0.002, placement_across=0.002)],
    ids=["2d", "3d-shifted"],
)
def test_validate_held_box_chain_arrives_as_the_free_one(case):
    """Every domino is reached, held or free, at the same time to 1e-9 (relative)."""
    free, held = _arrivals(False, **case), _arrivals(True, **case)
    assert np.all(np.isfinite(free[1:]))
    np.testing.assert_allclose(held[1:], free[1:], rtol=1e-9, atol=0)


def test_box_chains_are_held_by_default():
    assert ChainParams(shape="box").held and ChainParams().held


def test_a_held_box_stands_on_the_floor_once_a_moving_box_is_near():
    """The held box next to the pushed one has its floor rows before it is touched (so
    that the step of its first touch has the floor's support); a held box far from any
    moving box has none, and neither moves."""
    p = ChainParams(held=True, **COMMON)
    sim, _ = DominoChain(p, sleep=False).build(Push(omega=1.2 * math.sqrt(p.g / p.height)))
    start = sim.positions()
    sim.run(n_steps=20)
    rows = sim.boxes.rows
    on_floor = set(rows.i[: rows.n[0]][rows.j[: rows.n[0]] == -1])
    assert {0, 1} <= on_floor and p.n_dominoes - 1 not in on_floor
    assert sim.bodies.held[1] and sim.bodies.held[p.n_dominoes - 1]
    np.testing.assert_array_equal(sim.positions()[1:], start[1:])
