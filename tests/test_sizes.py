"""Runs too large for the machine are refused up front, with one line naming the sizes.

Each case used to allocate until a MemoryError (rods: a 194 GiB traceback) or grow
silently to gigabytes. The machine's memory is pinned at 8 GiB here so that the
verdicts do not depend on the machine that runs the tests.
"""

from __future__ import annotations

import pytest

from dominowave import checks

GIB = 2**30


@pytest.fixture(autouse=True)
def eight_gib(monkeypatch):
    monkeypatch.setattr(checks, "available_memory", lambda: 8 * GIB)


@pytest.mark.parametrize(
    ("args", "fragments"),
    [
        (["rods", "--n", "10000000"], ["n = 10000000", "GiB for its state and records"]),
        (
            ["theory", "--d-over-l", "0.01:0.99:10000000"],
            ["d_over_l (10000000 values) x stiffness_ratio (3 values)", "GiB for a table"],
        ),
        (["chain", "--n", "30000"], ["--n = 30000", "trajectory frames"]),
    ],
    ids=["rods", "theory-grid", "chain"],
)
def test_oversized_runs_are_refused_in_one_line(cli, args, fragments):
    code, _, err = cli(*args)
    assert code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err
    for fragment in fragments:
        assert fragment in err
    assert "6.4 GiB, 80% of the memory available now" in err


def test_a_theory_study_too_large_fails_before_allocating(tmp_path, cli):
    study = tmp_path / "big.toml"
    study.write_text('[scenario]\nkind = "theory"\nn_dominoes = 100000\nn_frames = 100000\n')
    code, _, err = cli("run", study, "--out", tmp_path / "out")
    assert code == 2
    assert "n_dominoes = 100000, n_frames = 100000" in err and "GiB for its trajectory" in err


def test_check_memory_accepts_what_fits():
    checks.check_memory(6 * GIB, "a test", "x = 1")
    with pytest.raises(ValueError, match=r"x = 2: the run needs about 7 GiB for a test"):
        checks.check_memory(7 * GIB, "a test", "x = 2")


def test_a_prediction_design_larger_than_the_machine_is_refused_before_it_is_built():
    from dominowave.sweep.predict import predict_points

    # (building the design first would take hours and 195 GiB: the refusal comes first)
    with pytest.raises(ValueError, match=r"samples = 1048576 \(8388608 chains\): the run needs"):
        predict_points(0.00938, "felt", 2**20)
    with pytest.raises(ValueError, match=r"samples = 1073741824 \(8589934592 chains\)"):
        predict_points(0.00938, "felt", 2**30)


def test_a_study_sweep_larger_than_the_machine_is_refused_before_it_is_built():
    from dominowave.io.config import parse_study

    grid = {
        "d_over_l": [0.1 + 1e-6 * i for i in range(1000)],
        "stiffness_ratio": [1.0 + i for i in range(1000)],
        "height": [0.01 + 1e-5 * i for i in range(100)],
    }
    study = {"scenario": {"kind": "theory"}, "sweep": {"grid": grid}}
    with pytest.raises(ValueError, match=r"sweep of 100000000 points: the run needs about"):
        parse_study(study, "big.toml")
