"""The rod model against the theory, and the ``rods`` / ``compare-rods`` commands."""

import csv

import numpy as np
import pytest
from typer.testing import CliRunner

from dominowave import theory
from dominowave.chain import theory_vs_rods as tvr
from dominowave.cli import app
from dominowave.sweep import compare_rods


def test_paper_stiffness_maps_to_half_per_contact():
    """The paper's k is per particle; the model's contact spring is k_r = k/2 (eq 24)."""
    chain = tvr.paper_chain(0.4, 1e4, 5, l=2.0, m=3.0, g=9.81)
    assert chain.k == pytest.approx(0.5 * 1e4 * 3.0 * 9.81 / 2.0)


def test_validate_head_on_model_reproduces_eq20_without_gravity_in_contact():
    """With all the theory's assumptions switched on (point mass, head-on normal, no
    gravity during contact, linear spring) the model's steady speed is eq 20 to 0.5 %,
    its collisions last T_c (eq 31) and transfer f_+ (eq 3) to 0.1 %."""
    c = tvr.compare_point(0.4, 1e6, n=60, normal="head-on", gravity_in_contact=False)
    assert c.status == "wave passed"
    assert c.speed == pytest.approx(c.speed_theory, rel=5e-3)
    assert c.tc_first == pytest.approx(c.tc_theory, rel=1e-3)
    assert c.transfer_median == pytest.approx(c.f_plus, rel=1e-3)
    assert c.overlap_fraction == 0.0


def test_validate_omega_profile_follows_eq8():
    """Omega_n of the paper's model (head-on, stiff, no gravity in contact) follows eq 8
    from below and from above the limit (Fig 1D)."""
    for factor in (0.5, 1.5):
        prof = tvr.omega_profile(0.6, 1e6, factor, n=12, gravity_in_contact=False)
        np.testing.assert_allclose(prof.measured, prof.theory, rtol=3e-3)


def test_cli_rods_prints_a_table():
    result = CliRunner().invoke(app, ["rods", "--n", "8", "--rows", "3"])
    assert result.exit_code == 0, result.output
    assert "Omega_fn" in result.output
    assert "status: wave passed" in result.output


def test_cli_rods_rejects_bad_input():
    result = CliRunner().invoke(app, ["rods", "--d-over-l", "1.5"])
    assert result.exit_code != 0
    assert isinstance(result.exception, ValueError)
    assert "d_over_l = 1.5" in str(result.exception)


def test_cli_compare_rods_quick_writes_csv_and_figures(tmp_path):
    result = CliRunner().invoke(app, ["compare-rods", "--quick", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    with (tmp_path / "compare_rods.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 12  # 3 d/l x 2 k/k* x 2 normals
    assert {"slip_fraction", "regime_theory", "secondary_merged_pair"} <= set(rows[0])
    for name in ("collision.png", "collision_map.png", "speed.png"):
        assert (tmp_path / name).stat().st_size > 1000
    beta = np.arcsin(float(rows[0]["d_over_l"]))
    assert float(rows[0]["f_plus"]) == pytest.approx(float(theory.f_plus(beta)))
    back = compare_rods.read_csv(tmp_path / "compare_rods.csv")
    assert len(back) == 12 and isinstance(back[0].pair_regime_theory, bool)
    assert back[0].tc_first == pytest.approx(float(rows[0]["tc_first"]))
    assert (tmp_path / "omega_n.png").stat().st_size > 1000


def test_cli_compare_rods_resumes_from_its_stored_points(tmp_path):
    """compare-rods is a study on the sweep engine: a second run finds every point stored,
    runs none and writes the same CSV files to the last bit."""
    args = ["compare-rods", "--d-over-l", "0.5", "--stiffness-ratio", "1e3", "--normal", "head-on"]
    args += ["--n", "8", "--workers", "1", "--out", str(tmp_path)]
    first = CliRunner().invoke(app, args)
    assert first.exit_code == 0, first.output
    assert "sweep done: 5 points, 0 already stored, 5 run now" in first.output
    before = {name: (tmp_path / name).read_bytes() for name in ("compare_rods.csv", "omega_n.csv")}
    again = CliRunner().invoke(app, args)
    assert again.exit_code == 0, again.output
    assert "sweep done: 5 points, 5 already stored, 0 run now" in again.output
    for name, data in before.items():
        assert (tmp_path / name).read_bytes() == data


def test_speed_figure_marks_points_that_did_not_settle(tmp_path, monkeypatch):
    """A comparison without a settled speed is an open marker in speed.png, not a gap."""
    import dataclasses
    import math

    from matplotlib.figure import Figure

    from dominowave.plots.compare_rods import plot_comparisons
    from dominowave.plots.unsettled import UNSETTLED_LABEL

    measured = tvr.compare_point(0.4, 1e4, n=20)
    settled = dataclasses.replace(measured, speed=measured.speed_theory)
    unsettled = dataclasses.replace(measured, d_over_l=0.6, speed=math.nan)
    drawn = {}
    monkeypatch.setattr(Figure, "savefig", lambda fig, path, **kw: drawn.update({path.name: fig}))
    plot_comparisons([settled, unsettled], tmp_path)
    ax = drawn["speed.png"].axes[0]
    marks = [line for line in ax.get_lines() if line.get_label() == UNSETTLED_LABEL]
    assert len(marks) == 1
    np.testing.assert_array_equal(marks[0].get_xdata(), [0.6])
    assert marks[0].get_markerfacecolor() == "none"
