"""Fig 6 with box dominoes: the box preset, its plots, and the clump preset unchanged."""

from __future__ import annotations

import csv
import subprocess
import sys

import pytest

from dominowave.chain.build import ChainParams
from dominowave.chain.paper_fig6 import CONFIGS, MEMBER_FIELDS, fig6_params
from dominowave.plots.fig6 import plot_fig6, plot_fig6_beside
from dominowave.sweep.fig6 import (
    FIELDS,
    FULL,
    FULL_BOX,
    QUICK,
    QUICK_BOX,
    Fig6Preset,
    fig6_points,
    preset_fields,
    read_rows,
    run_fig6,
    summarise,
)

TINY_BOX = Fig6Preset(
    "tiny-box", d_over_l=(0.5,), members=2, n_dominoes=6, configs=("2d", "mu0.6"), shape="box"
)


@pytest.mark.parametrize("config", sorted(CONFIGS))
def test_the_clump_configurations_are_the_chains_they_always_were(config):
    """The shape option leaves the paper's (clump) chains as they were built before it."""
    for d in FULL.d_over_l:
        old = ChainParams(n_dominoes=30, d_over_l=d, **CONFIGS[config])
        assert fig6_params(config, d, 30) == old
        assert fig6_params(config, d, 30, "clump") == old


def test_the_clump_presets_keep_their_points_and_columns():
    assert FIELDS == ["config", "d_over_l", "member", *MEMBER_FIELDS]
    for preset in (QUICK, FULL):
        assert preset.shape == "clump" and preset_fields(preset) == FIELDS
        assert {p.shape for p in fig6_points(preset)} == {"clump"}
    assert (QUICK.d_over_l, QUICK.members, QUICK.n_dominoes) == ((0.3, 0.6), 2, 12)
    assert (FULL.members, FULL.n_dominoes, len(FULL.d_over_l)) == (8, 30, 8)
    # summaries of clump rows have no shape column, as before
    row = {"config": "2d", "d_over_l": 0.4, "member": 0} | dict.fromkeys(MEMBER_FIELDS, 1.0)
    assert "shape" not in summarise([row])[0]


@pytest.mark.parametrize("config", sorted(CONFIGS))
def test_a_box_configuration_is_the_clump_chain_made_of_cuboids(config):
    clump, box = fig6_params(config, 0.4, 30), fig6_params(config, 0.4, 30, "box")
    assert box.shape == "box" and not box.held and clump.held  # (as the data were measured)
    same = (
        "n_dominoes d_over_l height thickness width density stiffness_ratio kt_ratio "
        "friction_floor friction_dominoes damping model lateral_asymmetry restitution g"
    ).split()
    for name in same:
        assert getattr(box, name) == getattr(clump, name), name
    assert box.rounding is None and box.rounding_radius == box.thickness / 20


def test_the_box_presets_are_the_clump_presets_with_boxes():
    for box, clump in ((QUICK_BOX, QUICK), (FULL_BOX, FULL)):
        assert box.shape == "box"
        assert (box.d_over_l, box.n_dominoes, box.configs) == (
            clump.d_over_l,
            clump.n_dominoes,
            clump.configs,
        )
        assert (box.seed, box.jitter) == (clump.seed, clump.jitter)
        assert {p.shape for p in fig6_points(box)} == {"box"}
    assert preset_fields(FULL_BOX) == ["config", "shape", *FIELDS[1:]]


def test_a_box_sweep_writes_its_shape_summarises_and_draws_beside_the_clumps(tmp_path):
    run_fig6(TINY_BOX, tmp_path / "box", workers=1)
    rows = read_rows(tmp_path / "box" / "runs.csv")
    assert len(rows) == 4 and {r["shape"] for r in rows} == {"box"}
    assert all(int(r["reached"]) == 6 for r in rows)  # every wave ran to the end
    box = summarise(rows)
    assert [s["shape"] for s in box] == ["box", "box"] and all(s["members"] == 2 for s in box)
    # eq 34 of a box uses the box's mapped parameters, not the clump's
    box_p = fig6_params("2d", 0.5, 6, "box")
    from dominowave.chain.compare import theory_speed

    assert float(box[0]["theory_speed"]) == theory_speed(box_p)
    assert theory_speed(box_p) != theory_speed(fig6_params("2d", 0.5, 6))
    # the same rows with and without the clump rows: summarised apart
    clump_row = {"config": "2d", "d_over_l": 0.5, "member": 0} | dict.fromkeys(MEMBER_FIELDS, 1.0)
    mixed = summarise([clump_row, *rows])
    assert sorted(s.get("shape", "clump") for s in mixed) == ["box", "box", "clump"]
    written = plot_fig6(box, tmp_path / "fig")
    assert {"fig6C.png", "fig6D.csv"} <= {p.name for p in written}
    clump = [dict(s) for s in summarise([clump_row])]
    beside = plot_fig6_beside(clump, box, tmp_path / "beside")
    names = {p.name for p in beside}
    assert {"fig6B_beside.png", "fig6D_beside.csv", "fig6E_beside.png"} <= names
    with (tmp_path / "beside" / "fig6D_beside.csv").open() as fh:
        shapes = [r["shape"] or "clump" for r in csv.DictReader(fh)]
    assert sorted(shapes) == ["box", "box", "clump"]


def _cli(*args):
    return subprocess.run(
        [sys.executable, "-m", "dominowave", *args], capture_output=True, text=True, timeout=900
    )


def test_paper_fig6_refuses_an_unknown_shape(tmp_path):
    res = _cli("paper-fig6", "--shape", "cube", "--quick", "--out", str(tmp_path))
    assert res.returncode == 2
    assert res.stderr.strip() == "dominowave: error: shape = 'cube' is not one of 'clump', 'box'"


@pytest.mark.slow
def test_paper_fig6_quick_box_preset(tmp_path):
    res = _cli("paper-fig6", "--shape", "box", "--quick", "--workers", "1", "--out", str(tmp_path))
    assert res.returncode == 0, res.stderr
    for panel in "BCDE":
        assert (tmp_path / f"fig6{panel}.png").stat().st_size > 0
    rows = read_rows(tmp_path / "runs.csv")
    assert len(rows) == 2 * 2 * 8 and {r["shape"] for r in rows} == {"box"}
    # every box wave of the quick preset reaches the end of its 12 dominoes
    assert all(int(r["reached"]) == 12 for r in rows)
