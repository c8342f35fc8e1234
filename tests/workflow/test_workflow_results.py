"""Result folders: every file reads back exactly; writes are atomic."""

from __future__ import annotations

import json
import tomllib

import numpy as np
import pytest

from dominowave.io.atomic import atomic_dir, atomic_path, write_text
from dominowave.io.models import TheoryScenario
from dominowave.io.results import (
    read_events,
    read_summary,
    read_trajectory,
    result_status,
    write_failure_folder,
)
from dominowave.sweep.execute import execute_point
from dominowave.sweep.hashing import config_dict, point_key
from dominowave.sweep.runner import store_outcome


@pytest.fixture(scope="module")
def theory_outcome():
    return execute_point(TheoryScenario(stiffness_ratio=1e4, n_dominoes=12, n_frames=50))


def test_result_folder_reads_back_bit_exact(theory_outcome, tmp_path):
    cfg = TheoryScenario(stiffness_ratio=1e4, n_dominoes=12, n_frames=50)
    folder = tmp_path / "run"
    assert store_outcome(folder, cfg, theory_outcome, keep_trajectory=True)
    result = theory_outcome.result
    assert result_status(folder) == "ok"
    summary = read_summary(folder)
    assert summary["speed"] == result.summary["speed"]
    events = read_events(folder)
    for name, column in result.events.items():
        np.testing.assert_array_equal(events[name], column)  # NaN == NaN here
    traj = read_trajectory(folder)
    np.testing.assert_array_equal(traj.angle, result.trajectory.angle)
    np.testing.assert_array_equal(traj.time, result.trajectory.time)
    resolved = tomllib.loads((folder / "config.toml").read_text())["scenario"]
    assert TheoryScenario.model_validate(resolved) == cfg
    prov = json.loads((folder / "provenance.json").read_text())
    assert prov["key"] == point_key(cfg)
    for field in ("version", "numpy", "numba", "machine", "wall_time_s", "seed", "git_commit"):
        assert field in prov


def test_provenance_times_the_run(theory_outcome):
    assert 0 < theory_outcome.provenance["wall_time_s"] < 60


def test_existing_folder_is_never_overwritten(theory_outcome, tmp_path):
    cfg = TheoryScenario()
    folder = tmp_path / "p"
    write_failure_folder(folder, config_dict(cfg), {}, "E: x", "tb")
    before = (folder / "failure.json").read_bytes()
    assert not store_outcome(folder, cfg, theory_outcome, keep_trajectory=False)
    assert (folder / "failure.json").read_bytes() == before
    assert result_status(folder) == "failed"
    assert [p.name for p in tmp_path.iterdir()] == ["p"]  # no temporary left behind


def test_atomic_write_keeps_the_old_file_when_interrupted(tmp_path):
    path = tmp_path / "summary.json"
    write_text(path, "old")
    with pytest.raises(KeyboardInterrupt), atomic_path(path) as tmp:
        tmp.write_text("half")
        raise KeyboardInterrupt
    assert path.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["summary.json"]


def test_atomic_dir_discards_a_failed_fill(tmp_path):
    def fill(folder):
        (folder / "a").write_text("x")
        raise RuntimeError("boom")

    with pytest.raises(RuntimeError):
        atomic_dir(tmp_path / "d", fill)
    assert list(tmp_path.iterdir()) == []


def test_nan_in_a_summary_is_a_failure_not_a_result(monkeypatch):
    from dominowave.sweep import run_theory as rt

    original = rt.run_theory

    def broken(cfg, ctx=None):
        result = original(cfg, ctx)
        result.summary["speed"] = float("nan")
        return result

    outcome = execute_point(TheoryScenario(), runner=broken)
    assert outcome.status == "failed"
    assert "speed = NaN" in outcome.error
    assert "FloatingPointError" in outcome.traceback
