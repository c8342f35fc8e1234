"""Hertz box chains (``ChainParams(shape="box", normal_law="hertz", young=..., poisson=...)``):
parameters, the standing domino at its Hertz sink, the first collision against Hertz's
closed form, checkpoints, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from test_chain_stepper import assert_same_bits

from dominowave.chain.build import ChainParams
from dominowave.chain.presets import standard_domino
from dominowave.chain.scenario import DominoChain
from dominowave.io.checkpoint import load_checkpoint, save_checkpoint

E, NU = 2.5e9, 0.35  # a plastic (polystyrene-like)


def _standard(model: str, n: int = 2, **overrides) -> ChainParams:
    """Standard 48 x 24 x 7.5 mm dominoes (8 g, rounding 0.375 mm) of a plastic, Hertz."""
    return standard_domino(
        n_dominoes=n, gap=0.02, floor="hardwood", model=model, young=E,
        normal_law="hertz", poisson=NU, **overrides,
    )  # fmt: skip


def _hertz_K(young, poisson, radius):
    """K of F = K delta^{3/2} for two bodies of one material (Johnson 1985, sec. 4.2)."""
    modulus = 1.0 / (2.0 * (1.0 - poisson**2) / young)
    return 4.0 / 3.0 * modulus * math.sqrt(radius)


def _pair_rows(sim, a, b):
    """Indices of the contact rows between boxes a and b (b < 0: wall -(b + 1))."""
    rows = sim.boxes.rows
    n = rows.n[0]
    i, j = rows.i[:n], rows.j[:n]
    return np.flatnonzero(((i == a) & (j == b)) | ((i == b) & (j == a)))


# --- parameters ----------------------------------------------------------------------------
def test_hertz_params_defaults_and_coefficient():
    p = ChainParams(shape="box", young=E, normal_law="hertz")
    assert p.poisson is None and p.poisson_ratio == 0.3
    assert p.hertz_coefficient == pytest.approx(_hertz_K(E, 0.3, p.rounding_radius), rel=1e-14)
    # the tangential spring and the theory's spring stay the linear rule's, pi r E / 2
    assert p.contact_stiffness == pytest.approx(math.pi * p.rounding_radius * E / 2, rel=1e-14)
    assert ChainParams().normal_law == "linear"
    # back to the linear law: poisson goes with it
    assert p.with_(poisson=0.4).with_(normal_law="linear").poisson is None


@pytest.mark.parametrize(
    "changes, fragments",
    [
        ({"normal_law": "hooke"}, ["normal_law = 'hooke'", "'linear', 'hertz'"]),
        ({"normal_law": "hertz", "young": E}, ["normal_law = 'hertz' needs shape = 'box'"]),
        ({"shape": "box", "normal_law": "hertz"}, ["needs young", "(0, inf) Pa", "None"]),
        (
            {"shape": "box", "normal_law": "hertz", "kn": 1e5},
            ["kn = 100000.0", "normal_law = 'linear'", "give young"],
        ),
        (
            {"shape": "box", "normal_law": "hertz", "stiffness_ratio": 1e4},
            ["stiffness_ratio = 10000.0", "give young"],
        ),
        (
            {"shape": "box", "normal_law": "hertz", "young": E, "poisson": 0.5},
            ["poisson = 0.5", "[0, 0.5)"],
        ),
        (
            {"shape": "box", "normal_law": "hertz", "young": E, "poisson": -0.1},
            ["poisson = -0.1", "[0, 0.5)"],
        ),
        ({"shape": "box", "young": E, "poisson": 0.3}, ["poisson = 0.3", "'hertz' only"]),
        (
            {"shape": "box", "normal_law": "hertz", "young": E, "young_rule": "yade"},
            ["young_rule = 'yade'", "paper"],
        ),
    ],
)
def test_hertz_params_bad_input_names_parameter_value_and_range(changes, fragments):
    with pytest.raises(ValueError) as err:
        ChainParams(**changes)
    for fragment in fragments:
        assert fragment in str(err.value)


def test_safety_sets_the_step_from_the_engine_estimate():
    """``DominoChain(safety=S)``: dt = S x the critical estimate of the built scene; the
    default step of a Hertz chain (T_c / 50 with the spring pi r E / 2) lies below it."""
    p = _standard("3d")
    chain = DominoChain(p, safety=0.2)
    sim, _ = chain.build(chain.resolve(None))
    assert sim.dt == chain.dt == pytest.approx(0.2 * sim.critical_dt, rel=1e-14)
    default = DominoChain(p)
    assert default.dt < sim.critical_dt
    with pytest.raises(ValueError, match="give dt or safety, not both"):
        DominoChain(p, dt=1e-6, safety=0.2)
    with pytest.raises(ValueError, match=r"safety = 2"):
        DominoChain(p, safety=2.0)


# --- validation ----------------------------------------------------------------------------
@pytest.mark.parametrize("model", ["2d", "3d"])
def test_validate_hertz_domino_stands_at_its_hertz_sink(model):
    """Domino 1 of a Hertz chain, standing until the wave comes: its 4 corner points (a
    planar box: 2 rows, each counted twice) carry m g / 4 each at Hertz's overlap
    ``(m g / (4 K))^{2/3}``, ``K = 4/3 E* sqrt(r)`` with ``E* = E / (2 (1 - nu^2))``
    (computed here), and it does not move."""
    p = _standard(model)
    chain = DominoChain(p)
    sim, _ = chain.build(chain.resolve(None))
    start = sim.bodies.pos[1].copy()
    sim.run(until=0.02)  # domino 0 meets domino 1 at 0.030 s
    assert not np.isfinite(sim.rec.first_contact[0, 1])
    rows = sim.boxes.rows
    floor = _pair_rows(sim, 1, -1)
    assert floor.size == (2 if model == "2d" else 4)
    weight = p.density * p.height * p.width * p.thickness * p.g
    np.testing.assert_allclose(rows.fn[floor], weight / 4, rtol=1e-9)
    assert (rows.fn[floor] * rows.mult[floor]).sum() == pytest.approx(weight, rel=1e-9)
    K = _hertz_K(E, NU, p.thickness / 20)
    np.testing.assert_allclose(rows.overlap[floor], (weight / (4 * K)) ** (2 / 3), rtol=1e-9)
    assert np.abs(sim.bodies.pos[1] - start).max() < 1e-15
    assert np.abs(sim.bodies.vel_full[1]).max() < 1e-12


def test_validate_hertz_chain_first_collision_against_hertz_closed_form():
    """Domino 0's top edge meets domino 1's face (elastic, frictionless between dominoes):
    the two edge-end points, each ``K delta^{3/2}``, act as one Hertz contact ``2 K`` on the
    effective mass at the contact point (both bodies free, ``1/m + (r x n) I^-1 (r x n)``,
    from the state at onset); Hertz's closed forms at the onset speed v give the largest
    overlap ``(5 m v^2 / (8 K))^{2/5}``, the largest force and the duration
    ``2 delta_max / v int_0^1 (1 - s^{5/2})^{-1/2} ds`` (Johnson 1985, sec. 11.4).
    Measured (3D, default step): overlap +0.29 %, force +0.43 %, duration +1.6 % (+1.3 %
    at safety 0.02): the bodies turn and the floor pushes during the contact, which the
    closed form of a free central impact leaves out."""
    p = _standard("3d", restitution_dominoes=1.0, friction_dominoes=0.0)
    chain = DominoChain(p)
    sim, _ = chain.build(chain.resolve(None))
    while not (pair := _pair_rows(sim, 0, 1)).size:
        sim.run(n_steps=1)
    rows, b = sim.boxes.rows, sim.bodies
    point, normal = rows.point[pair].mean(axis=0), rows.normal[pair[0]].copy()
    assert pair.size == 2 and np.allclose(normal, [1.0, 0.0, 0.0], atol=1e-12)
    v = -float(rows.vn[pair[0]])
    K = 2.0 * _hertz_K(E, NU, p.thickness / 20)
    inverse = 0.0
    for k in (0, 1):
        inertia = b.rot[k] @ np.diag(b.inertia[k]) @ b.rot[k].T
        arm = np.cross(point - b.pos[k], normal)
        inverse += 1.0 / b.mass[k] + arm @ np.linalg.solve(inertia, arm)
    m_eff = 1.0 / inverse
    onset, overlap, force = sim.time, 0.0, 0.0
    while (pair := _pair_rows(sim, 0, 1)).size:
        overlap = max(overlap, rows.overlap[pair].max())
        force = max(force, (rows.fn[pair] * rows.mult[pair]).sum())
        sim.run(n_steps=1)
    duration = sim.time - onset
    delta = (5.0 * m_eff * v**2 / (4.0 * K)) ** 0.4
    assert overlap == pytest.approx(delta, rel=1e-2)
    assert force == pytest.approx(K * delta**1.5, rel=1e-2)
    closed = 2.0 * delta / v * quad(lambda s: (1.0 - s**2.5) ** -0.5, 0.0, 1.0)[0]
    assert duration == pytest.approx(closed, rel=3e-2)


# --- checkpoints ---------------------------------------------------------------------------
def test_hertz_chain_restored_from_a_checkpoint_ends_bit_identically(tmp_path):
    """A Hertz chain saved mid-wave (io.checkpoint, the file a CLI run writes) and restored
    into a fresh stepper keeps the Hertz law (the box state stores it) and retraces the
    uninterrupted run bit for bit."""
    p = _standard("2d", n=4)
    whole = DominoChain(p).stepper()
    while not whole.advance(10**9):
        pass
    first = DominoChain(p).stepper()
    first.advance(60_000)  # past the first collision: box-box and floor rows with history
    rows = first.sim.boxes.rows
    assert np.any(rows.j[: rows.n[0]] >= 0) or np.isfinite(first.sim.rec.first_contact[0, 1])
    path = tmp_path / "state.npz"
    save_checkpoint(path, first.get_state(), {"key": "hertz"}, history=first.history_keys)
    state, _ = load_checkpoint(path, key="hertz")
    assert int(np.asarray(state["sim.boxes.normal_law"]).reshape(-1)[0]) == 1
    resumed = DominoChain(p).stepper()
    resumed.set_state(state)
    assert resumed.sim.boxes.normal_law[0] == 1
    while not resumed.advance(54_321):
        pass
    assert_same_bits(resumed.result(keep_record=True), whole.result(keep_record=True))


def test_toml_study_takes_the_hertz_fields():
    """A TOML chain scenario with ``normal_law``/``poisson``: the same ChainParams; with
    the standard preset the preset's modulus is used."""
    from dominowave.io.config import scenario_from_dict

    given = {"kind": "chain", "shape": "box", "normal_law": "hertz", "young": E, "poisson": NU}
    p = scenario_from_dict(given).params()
    assert (p.normal_law, p.young, p.poisson) == ("hertz", E, NU)
    preset = {"kind": "chain", "preset": "standard", "gap": 0.02, "floor": "hardwood"}
    q = scenario_from_dict({**preset, "normal_law": "hertz", "poisson": NU}).params()
    assert q.normal_law == "hertz" and q.young == standard_domino(gap=0.02, floor="hardwood").young
