"""Contact forces of a DEM chain run as VTK force lines (``--vtk every=N``).

The chain stepper records the engine's contact forces at its frames
(``record_contact_forces``), keeps them across checkpoints and hands them to the chain
adapter, which turns them into line segments with the force on the first end.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest

from dominowave.chain.build import ChainParams
from dominowave.chain.scenario import DominoChain
from dominowave.cli import main
from dominowave.io.models import ChainScenario
from dominowave.io.vtk import SceneFrame, VtkSeries
from dominowave.sweep.registry import RunContext
from dominowave.sweep.run_chain import run_chain

SMALL = ChainParams(n_dominoes=4, d_over_l=0.5)


@pytest.fixture(scope="module")
def chain_spheres():
    cfg = ChainScenario(n_dominoes=4)
    return run_chain(cfg, RunContext(vtk_every=1)).spheres


def test_chain_result_carries_force_lines(chain_spheres):
    s = chain_spheres
    assert len(s.contact_segments) == s.time.size
    assert len(s.contact_segments) == len(s.contact_forces) == s.time.size
    counts = np.array([seg.shape[0] for seg in s.contact_segments])
    assert counts.max() > 0 and counts[0] == 0  # frame 0: the state before the first step
    for f in np.flatnonzero(counts)[:: max(1, counts.size // 20)]:
        seg, force = s.contact_segments[f], s.contact_forces[f]
        assert seg.shape == (counts[f], 2, 3) and force.shape == (counts[f], 3)
        # every segment starts at a sphere centre of that frame
        gap = np.linalg.norm(seg[:, 0, None, :] - s.centres[f][None], axis=2).min(axis=1)
        assert gap.max() < 1e-12
        # the normal part of a contact force pushes the first end away from the second
        assert np.all(np.einsum("ij,ij->i", force, seg[:, 0] - seg[:, 1]) > 0)


def test_validate_held_dominoes_rest_on_their_recorded_floor_forces():
    """At every frame, each domino that has not been touched yet is held at its static
    sink (``DominoChain._sink``: m g / (n_base k_n)), so its recorded floor forces add up
    to its weight m g, upward (independent: the chain's mass and g)."""
    chain = DominoChain(SMALL)
    stepper = chain.stepper(contact_forces=True)
    stepper.advance(20_000)
    cf = stepper.contact_frames()
    times = stepper.record().times
    body = stepper.sim.sphere_body
    release = stepper.sim.release_time
    weight = SMALL.mass * SMALL.g
    checked = 0
    for f in range(1, times.size):
        rows = cf.frame(f)
        for b in range(1, SMALL.n_dominoes):
            if not np.isnan(release[b]) and release[b] <= times[f]:
                continue  # touched: no longer at rest
            mine = rows.start + np.flatnonzero(body[cf.second[rows]] == b)
            assert np.all(cf.first[mine] < 0)  # only the floor touches it
            total = cf.force[mine].sum(axis=0)
            np.testing.assert_allclose(total, [0.0, 0.0, weight], rtol=1e-9, atol=1e-12 * weight)
            checked += 1
    assert checked > 10


def test_recorded_forces_survive_a_checkpoint_bit_for_bit():
    """advance(a), get_state, a new stepper, set_state, advance(b) == advance(a + b)."""
    one = DominoChain(SMALL).stepper(contact_forces=True)
    one.advance(30_000)
    first = DominoChain(SMALL).stepper(contact_forces=True)
    first.advance(12_345)
    second = DominoChain(SMALL).stepper(contact_forces=True)
    second.set_state(first.get_state())
    second.advance(30_000 - 12_345)
    a, b = one.contact_frames(), second.contact_frames()
    for name in ("start", "first", "second", "point", "force"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.first.size > 0


def test_write_force_lines_of_a_chain_frame(chain_spheres, tmp_path):
    """The adapter's lines go through the VTK writer: one line cell per contact."""
    import meshio

    s = chain_spheres
    f = int(np.argmax([seg.shape[0] for seg in s.contact_segments]))
    series = VtkSeries(tmp_path)
    series.write(
        SceneFrame(
            time=float(s.time[f]),
            contact_segments=s.contact_segments[f],
            contact_forces=s.contact_forces[f],
        )
    )
    mesh = meshio.read(tmp_path / "contacts_00000.vtu")
    assert mesh.cells[0].data.shape == (s.contact_segments[f].shape[0], 2)
    np.testing.assert_allclose(mesh.cell_data["force"][0], s.contact_forces[f])


def test_run_chain_with_vtk_writes_contact_lines(tmp_path, monkeypatch, capsys):
    import meshio

    monkeypatch.setattr(sys, "argv", ["dominowave", "config", "--example", "chain"])
    with _no_exit():
        main()
    text = capsys.readouterr().out
    study = tmp_path / "chain.toml"
    study.write_text(text.replace("n_dominoes = 30", "n_dominoes = 4"))
    out = tmp_path / "run"
    monkeypatch.setattr(
        sys, "argv", ["dominowave", "run", str(study), "--out", str(out), "--vtk", "every=5"]
    )
    with _no_exit():
        main()
    files = sorted((out / "vtk").glob("contacts_*.vtu"))
    assert files
    lines = [meshio.read(p).cells[0].data.shape[0] for p in files]
    assert max(lines) > 0


class _no_exit:
    """Treat ``SystemExit(0)`` of the CLI as success, any other exit as a failure."""

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        if kind is SystemExit:
            assert exc.code in (0, None), exc
            return True
        return False
