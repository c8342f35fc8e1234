"""What a real-domino prediction rests on: measurements at the same gap, inferred friction."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dominowave.chain.reconcile import (
    compare_with_measurements,
    dem_friction_for_speed,
    leaning_friction_for_speed,
    reconcile_lines,
)
from dominowave.sweep.predict import _analyse, predict_points
from dominowave.theory import leaning

L, S = 0.048, 0.0075


def test_the_films_at_the_same_gap_and_floor_are_found():
    films = compare_with_measurements(0.00938, "hardwood")
    assert len(films.rows) == 7 and all(m.speed_kind == "asymptotic" for m in films.rows)
    assert films.mean == pytest.approx(np.mean([1.265, 1.193, 1.220, 1.274, 1.284, 1.285, 1.325]))
    assert films.difference_percent(films.mean / 2) == pytest.approx(-50.0)
    assert len(compare_with_measurements(0.00938, "felt").rows) == 6
    assert compare_with_measurements(0.02, "hardwood") is None
    assert compare_with_measurements(0.00938, "glass") is None


@pytest.mark.parametrize("friction", [0.0, 0.05, 0.3, 0.9])
def test_the_inferred_leaning_friction_gives_back_the_speed(friction):
    speed = leaning.limit_speed(height=L, thickness=S, gap=0.01509, friction=friction)
    mu, note = leaning_friction_for_speed(speed, height=L, thickness=S, gap=0.01509)
    assert note == "" and mu == pytest.approx(friction, abs=1e-5)


def test_no_friction_is_inferred_where_none_gives_the_speed():
    mu, note = leaning_friction_for_speed(3.0, height=L, thickness=S, gap=0.00938)
    assert mu is None and "faster than the frictionless leaning train" in note
    mu, note = leaning_friction_for_speed(0.01, height=L, thickness=S, gap=0.00938)
    assert mu is None and "slower than any steady leaning train" in note
    mu, note = leaning_friction_for_speed(0.8, height=L, thickness=S, gap=0.0432562)
    assert mu is None and note == "no steady leaning train at this gap"


def test_the_dem_friction_is_interpolated_in_the_shipped_scan():
    mu, note = dem_friction_for_speed(0.8895, gap=0.00938, floor="felt", model="3d")
    assert note == "" and mu == pytest.approx(0.3, abs=1e-9)
    mu, note = dem_friction_for_speed((1.1601 + 1.0058) / 2, gap=0.00938, floor="felt")
    assert mu == pytest.approx(0.15, abs=1e-9)
    assert dem_friction_for_speed(2.0, gap=0.00938, floor="felt")[0] is None
    mu, note = dem_friction_for_speed(1.0, gap=0.015, floor="felt")
    assert mu is None and "not run at this gap" in note


def test_the_lines_say_what_was_measured_and_what_was_inferred():
    lines = reconcile_lines(0.7, gap=0.00938, floor="felt", friction=0.525)
    assert lines[0].startswith("leaning train (rigid, inelastic; theory.leaning) at friction 0.525")
    assert "6 rows): 1.337 m/s" in lines[1] and "this run: 0.700 m/s, -48 %" in lines[1]
    assert "inferred from the measurement (not a material value)" in lines[2]
    assert "leaning train 0.01" in lines[2] and "box DEM (3d) 0.00" in lines[2]
    single = reconcile_lines(math.nan, gap=0.0150876, floor="hardwood")
    assert "1 row): 1.135 m/s" in single[0] and "this run" not in single[0]
    assert "box DEM (3d) none (the DEM friction scan was not run" in single[1]
    assert reconcile_lines(0.7, gap=0.02, floor="felt")[0].startswith("no shipped measurement")


def test_predict_gives_the_leaning_band_of_the_same_samples():
    _, problem, x, fixed = predict_points(0.00938, "felt", 4, n_dominoes=6, fit_from=2)
    pred = _analyse(0.00938, "felt", problem, x, np.ones(len(x)), fixed, None)
    friction = x[:, problem["names"].index("friction_dominoes")]
    expected = leaning.limit_speed(height=L, thickness=S, gap=0.00938, friction=friction)
    np.testing.assert_allclose(pred.leaning_speed, expected, rtol=1e-14)
    assert pred.leaning_band[1] == pytest.approx(np.median(expected))
