"""Speed against pitch (docs/real_dominoes/speed_vs_pitch.py, plots.real_dominoes)."""

from __future__ import annotations

import csv
import importlib.util
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from dominowave.chain.measurements import COLUMNS
from dominowave.plots.real_dominoes import (
    compare_measurements,
    comparison_markdown,
    plot_speed_vs_pitch,
    read_study,
    speeds_markdown,
)
from dominowave.units import G_STANDARD

SCRIPT = Path(__file__).parents[2] / "docs/real_dominoes/speed_vs_pitch.py"
GAPS = (0.006, 0.012, 0.024)
S = 0.0075


def _script():
    spec = importlib.util.spec_from_file_location("speed_vs_pitch", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _write_csv(path: Path, rows: list[dict]) -> Path:
    with path.open("w", encoding="utf-8", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    return path


def _synthetic_study(folder: Path) -> None:
    """A band 0.5 v .. 1.5 v around a median v = 10 * gap [m/s], every model near it."""
    band = [
        {
            "gap_m": g,
            "pitch_m": g + S,
            "d_over_l": g / 0.048,
            "q05_m_s": 5 * g,
            "q50_m_s": 10 * g,
            "q95_m_s": 15 * g,
            "mean_m_s": 10 * g,
            "runs": 8,
            "waves_died": 0,
            "runs_failed": 0,
            "floor": "hardwood",
            "n_dominoes": 12,
            "fit_from": 3,
        }
        for g in GAPS
    ]
    models = []
    for name, factor in (("dem3d", 1.0), ("dem2d", 1.1), ("rods", 0.8), ("transient", 2.0)):
        for g in GAPS:
            dead = name == "dem2d" and g == GAPS[-1]  # a wave that died: NaN speed
            models.append(
                {
                    "model": name,
                    "gap_m": g,
                    "pitch_m": g + S,
                    "d_over_l": g / 0.048,
                    "speed_m_s": math.nan if dead else factor * 10 * g,
                    "speed_err_m_s": 0.01,
                    "toppled": 5 if dead else 12,
                    "n_dominoes": 12,
                    "fit_from": 3,
                    "note": "synthetic",
                }
            )
    theory = [
        {"gap_m": g, "pitch_m": g + S, "d_over_l": g / 0.048}
        | {"eq34_rigid_m_s": 100 * g, "eq34_tc_m_s": 90 * g}
        for g in np.linspace(0.004, 0.03, 5)
    ]
    _write_csv(folder / "speed_vs_pitch_band.csv", band)
    _write_csv(folder / "speed_vs_pitch_models.csv", models)
    _write_csv(folder / "speed_vs_pitch_theory.csv", theory)


def _measurement(**cells) -> dict:
    row = dict.fromkeys(COLUMNS, "")
    row.update(
        source="A. Author, J. Dominoes 1, 1 (2020), https://example.org/a2020",
        method="high-speed camera",
        material="ABS",
        floor="felt",
        speed_kind="asymptotic",
        where_printed="Table 1",
        height_m="0.048",
        thickness_m="0.0075",
        spacing_basis="gap",
    )
    row.update(cells)
    return row


def _synthetic_measurements(folder: Path) -> Path:
    rows = [
        _measurement(key="same_in", spacing_m="0.012", speed_m_s="0.15"),  # band 0.06 .. 0.18
        _measurement(key="same_pitch_out", spacing_m="0.0195", spacing_basis="pitch")
        | {"speed_m_s": "0.30"},  # gap 12 mm: above the band
        _measurement(key="half_size", spacing_m="0.006", height_m="0.024", thickness_m="0.00375")
        | {"speed_m_s": "0.03"},  # d/l = 0.25, as the standard domino at 12 mm
        _measurement(key="no_size", spacing_m="0.01", height_m="", thickness_m="")
        | {"speed_m_s": "0.8", "speed_kind": "average"},
        _measurement(key="too_wide", spacing_m="0.040", speed_m_s="0.5"),
        _measurement(key="no_height", spacing_m="0.024", height_m="", speed_m_s="0.2"),
    ]
    return _write_csv(folder / "measurements.csv", rows)


def test_the_figure_and_the_comparison_read_the_stored_csvs(tmp_path):
    _synthetic_study(tmp_path)
    measurements = _synthetic_measurements(tmp_path)
    study = read_study(tmp_path)
    assert set(study.models) == {"dem3d", "dem2d", "rods", "transient"}
    assert np.allclose(study.band["pitch_m"], np.array(GAPS) + S)

    png = plot_speed_vs_pitch(study, tmp_path / "fig.png", measurements=measurements)
    assert png.stat().st_size > 10_000

    table = {r["key"]: r for r in compare_measurements(study, measurements=measurements)}
    assert table["same_in"]["how"] == "same domino"
    assert table["same_in"]["median_m_s"] == "0.12"  # at a computed gap: the band itself
    assert table["same_in"]["diff_pct"] == f"{100 * (0.12 - 0.15) / 0.15:+.0f}"
    assert table["same_in"]["in_band"] == "yes"
    assert table["same_pitch_out"]["median_m_s"] == "0.12"  # pitch basis: gap = 19.5 - 7.5
    assert table["same_pitch_out"]["in_band"] == "no"
    # another stated size: the dimensionless band at its d/l, in its own sqrt(g l)
    half = table["half_size"]
    assert half["how"] == "scaled in d/l (other size)"
    expected = 0.12 * math.sqrt(G_STANDARD * 0.024) / math.sqrt(G_STANDARD * 0.048)
    assert half["median_m_s"] == f"{expected:.3g}"
    assert half["in_band"] == "no"  # below the scaled band 0.042 .. 0.127
    assert table["no_size"]["how"] == "not comparable: domino size not stated"
    assert table["no_size"]["diff_pct"] == "n/a"
    assert table["too_wide"]["how"].endswith("outside the computed gaps")  # not extrapolated
    # the standard thickness without a height: compared as a standard domino, and said so
    assert table["no_height"]["how"] == "height not stated, taken as 48 mm (thickness standard)"
    assert (table["no_height"]["median_m_s"], table["no_height"]["in_band"]) == ("0.24", "yes")
    assert comparison_markdown(list(table.values())).count("\n") == len(table) + 1
    speeds = speeds_markdown(study).splitlines()
    assert speeds[0].startswith("| gap d [mm] | pitch [mm] | d/l | band 5-95 % | median | dem3d |")
    assert speeds[3] == "| 12 | 19.5 | 0.250 | 0.06 - 0.18 | 0.12 | 0.12 | 0.132 | 0.096 | 0.24 |"
    assert speeds[4].split(" | ")[6] == "n/a"  # the 2D wave that died at 24 mm


def test_a_half_size_measurement_inside_the_scaled_band_is_in_it(tmp_path):
    _synthetic_study(tmp_path)
    row = _measurement(key="half", spacing_m="0.006", height_m="0.024", thickness_m="0.00375")
    path = _write_csv(tmp_path / "m.csv", [row | {"speed_m_s": "0.05"}])
    (r,) = compare_measurements(read_study(tmp_path), measurements=path)
    lo, hi = (0.06 / math.sqrt(2), 0.18 / math.sqrt(2))  # 0.042 .. 0.127
    assert r["band_m_s"] == f"{lo:.3g} - {hi:.3g}" and r["in_band"] == "yes"


def test_validate_the_rod_dashpot_gives_the_restitution():
    """A linear spring-dashpot m x'' + c x' + k x = 0 entered at speed 1 (solve_ivp) leaves
    at speed e when c = 2 zeta sqrt(m k), zeta from restitution_damping_ratio(e)."""
    ratio = _script().restitution_damping_ratio
    m, k = 0.003, 2.0e6
    for e in (0.1, 0.5, 0.9):
        c = 2.0 * ratio(e) * math.sqrt(m * k)

        def rhs(t, y, c=c):
            return [y[1], -(c * y[1] + k * y[0]) / m]

        def released(t, y):
            return y[0]

        released.terminal, released.direction = True, -1
        sol = solve_ivp(rhs, (0, 1.0), [0.0, 1.0], events=released, rtol=1e-10, atol=1e-14)
        assert -sol.y_events[0][0][1] == pytest.approx(e, rel=1e-6)
    assert ratio(None) == 0.0 and ratio(1.0) == 0.0


def test_the_rod_chain_carries_the_box_chains_values():
    from dominowave.chain.presets import standard_domino

    module = _script()
    p = standard_domino(gap=0.012, floor="hardwood", n_dominoes=7)
    rods = module.rod_chain(p)
    assert (rods.n, rods.l, rods.s) == (7, p.height, p.thickness)
    assert rods.d == pytest.approx(0.012)
    assert rods.k == p.pair_stiffness and rods.mu == p.friction_dominoes
    assert rods.mass.m == pytest.approx(p.mass)
    assert rods.mass.inertia == pytest.approx(p.mass * (p.height**2 + p.thickness**2) / 3)
    assert rods.floor_restitution == p.restitution_pairs[1]


@pytest.mark.slow
def test_the_quick_study_writes_every_table_and_the_figure(tmp_path):
    from dominowave.chain.compare import theory_speed
    from dominowave.chain.presets import standard_domino

    args = ["--quick", "--out", str(tmp_path), "--runs", str(tmp_path / "runs")]
    done = subprocess.run(
        [sys.executable, str(SCRIPT), *args],
        capture_output=True,
        text=True,
        check=True,
    )
    assert "| key |" in done.stdout
    band = list(csv.DictReader((tmp_path / "speed_vs_pitch_band.csv").open()))
    assert [float(r["gap_m"]) for r in band] == [0.012, 0.024]
    for r in band:
        assert float(r["q05_m_s"]) <= float(r["q50_m_s"]) <= float(r["q95_m_s"])
        assert int(r["runs"]) == 8  # one base sample, D = 6: 8 chains
    models = list(csv.DictReader((tmp_path / "speed_vs_pitch_models.csv").open()))
    names = {r["model"] for r in models}
    assert names == {"dem2d", "rods", "rods_ideal", "transient", "eq34_rigid", "eq34_tc"}
    for r in models:
        if r["model"] == "eq34_tc":
            p = standard_domino(gap=float(r["gap_m"]), floor="hardwood", stiffness_ratio=1e3)
            assert float(r["speed_m_s"]) == pytest.approx(theory_speed(p), rel=1e-5)
    assert (tmp_path / "speed_vs_pitch.png").exists()
    assert (tmp_path / "speed_vs_pitch_measurements.csv").exists()


def test_the_shipped_speed_tables_are_current():
    """docs/real_dominoes.md holds what the report makes of the shipped CSVs and of the
    shipped measurements (re-run ``speed_vs_pitch.py --report`` after adding rows)."""
    study = read_study(SCRIPT.parent)
    doc = (SCRIPT.parents[1] / "real_dominoes.md").read_text(encoding="utf-8")
    assert speeds_markdown(study) in doc, "regenerate the speeds table (--report)"
    table = comparison_markdown(compare_measurements(study))
    assert table in doc, "regenerate the comparison table (--report)"


def test_replace_between_markers():
    replace = _script().replace_between
    text = "a\n<!-- t:begin -->\nold\n<!-- t:end -->\nb"
    assert replace(text, "t", "new") == "a\n<!-- t:begin -->\nnew\n<!-- t:end -->\nb"
    with pytest.raises(ValueError, match="<!-- u:begin -->"):
        replace(text, "u", "new")
