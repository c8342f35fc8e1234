"""The scenario adapters: rods and DEM chain runs become complete, consistent result files."""

from __future__ import annotations

import numpy as np
import pytest

from dominowave.io.models import ChainScenario, RodsScenario, TheoryScenario
from dominowave.sweep.execute import execute_point
from dominowave.sweep.registry import RunContext
from dominowave.sweep.run_chain import run_chain


@pytest.fixture(scope="module")
def chain_result():
    cfg = ChainScenario(n_dominoes=5)
    return cfg, run_chain(cfg, RunContext(vtk_every=1))


COMMON_DOMINO = {"height": 0.048, "thickness": 0.0075, "mass": 0.008, "d_over_l": 0.5}
"""A 48 x 7.5 mm, 8 g domino at d/l = 0.5."""


def test_rods_run_reaches_every_domino_and_conserves_energy():
    outcome = execute_point(RodsScenario(n_dominoes=8, stiffness_ratio=1e4, **COMMON_DOMINO))
    assert outcome.status == "ok", outcome.error
    s = outcome.result.summary
    assert s["status"] == "wave passed" and s["dominoes_toppled"] == 8
    assert abs(s["energy_drift"]) < 1e-3  # elastic contacts, no dashpot: a conservative run
    theory = TheoryScenario(n_dominoes=8, stiffness_ratio=1e4, **COMMON_DOMINO)
    assert s["speed_theory"] == pytest.approx(float(theory.theory_speed(0.5)), rel=1e-12)
    arrival = outcome.result.events["arrival_time"]
    assert np.all(np.diff(arrival) > 0)


def test_rods_stiffness_follows_the_papers_convention():
    """k/k* = 1e4 means a per-particle k; the rod model gets the contact spring k/2."""
    from dominowave.chain.theory_vs_rods import paper_chain

    cfg = RodsScenario(stiffness=500.0)
    assert cfg.contact_stiffness == 500.0
    chain = paper_chain(
        cfg.d_over_l, cfg.contact_stiffness / cfg.k_star, 2, l=cfg.height, m=cfg.mass, g=cfg.g
    )
    assert chain.k == pytest.approx(250.0, rel=1e-12)


def test_validate_chain_trajectory_contains_its_spheres(chain_result):
    """Every sphere centre lies inside its domino's drawn rectangle, inset by the radius.

    The rectangle comes from the pivot sphere and the tilt (``chain_trajectory``), the
    spheres from the initial scene and each clump's rotation (``sphere_trajectory``):
    two independent reconstructions of the same rigid bodies.
    """
    cfg, result = chain_result
    traj, spheres = result.trajectory, result.spheres
    assert np.array_equal(traj.time, spheres.time)
    r = cfg.thickness / 2
    for f in range(0, traj.n_frames, max(1, traj.n_frames // 25)):
        corners = traj.corners(f)  # (N, 4, 2): back-bottom, front-bottom, front-top, back-top
        for n in range(cfg.n_dominoes):
            c = corners[n]
            along = (c[3] - c[0]) / np.linalg.norm(c[3] - c[0])
            across = (c[1] - c[0]) / np.linalg.norm(c[1] - c[0])
            mine = spheres.centres[f, spheres.clump_ids == n][:, [0, 2]] - c[0]
            u, w = mine @ across, mine @ along
            np.testing.assert_allclose(u, r, atol=1e-9 * cfg.height)
            assert np.all(w > r - 1e-9) and np.all(w < cfg.height - r + 1e-9)


def test_chain_result_files(chain_result, tmp_path):
    from dominowave.io.results import read_events, read_trajectory
    from dominowave.io.vtk import write_result_vtk
    from dominowave.sweep.runner import store_outcome

    cfg, result = chain_result
    assert result.summary["dominoes_toppled"] == cfg.n_dominoes
    assert result.summary["stiffness_over_kstar"] == pytest.approx(1e4, rel=1e-12)
    outcome = execute_point(cfg)
    assert outcome.status == "ok", outcome.error
    assert store_outcome(tmp_path / "run", cfg, outcome, keep_trajectory=True)
    events = read_events(tmp_path / "run")
    np.testing.assert_array_equal(events["arrival_time"], outcome.result.events["arrival_time"])
    assert read_trajectory(tmp_path / "run").base_z is not None
    n = write_result_vtk(tmp_path / "vtk", result, every=50)
    assert len(list((tmp_path / "vtk").glob("spheres_*.vtu"))) == n
    assert len(list((tmp_path / "vtk").glob("dominoes_*.vtu"))) == n
