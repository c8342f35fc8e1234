"""The standard-domino preset from the material data, and `dominowave predict` on it."""

from __future__ import annotations

import csv
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from dominowave.chain.fidelity import DEFAULT_TOLERANCE
from dominowave.chain.materials import load_materials
from dominowave.chain.presets import SAMPLED, standard_domino, standard_entries
from dominowave.sweep.predict import (
    SAMPLES_CSV,
    PredictSample,
    _analyse,
    predict,
    predict_points,
    run_predict_sample,
)

# --------------------------------------------------------------------------- preset


def test_standard_domino_takes_every_value_from_the_materials_file():
    mat = load_materials()
    p = standard_domino(gap=0.00938, floor="felt", n_dominoes=7)
    assert (p.height, p.width, p.thickness) == (0.048, 0.024, 0.0075)
    assert p.d_over_l == pytest.approx(0.00938 / 0.048, rel=1e-15)
    assert p.spacing == pytest.approx(0.00938, rel=1e-14)
    assert p.model == "3d" and p.n_dominoes == 7 and p.shape == "box"
    assert p.mass == pytest.approx(mat.domino.mass.value, rel=1e-12)  # rho l w s
    assert p.young == mat.plastic.youngs_modulus.value and p.young_rule == "paper"
    assert p.friction_dominoes == mat.friction_domino_domino.value
    assert p.friction_floor == mat.floor_friction("felt").value
    assert p.restitution_pairs == (
        mat.restitution_domino_domino.value,
        mat.restitution_domino_floor.value,
    )
    glass = standard_domino(gap=0.00938, floor="glass")
    assert glass.friction_floor == mat.floor_friction("glass").value


def test_standard_domino_values_and_overrides():
    values = {"mass": 0.009, "restitution_floor": 0.8}
    p = standard_domino(gap=0.01, floor="hardwood", values=values)
    assert p.mass == pytest.approx(0.009, rel=1e-12) and p.restitution_pairs == (0.5, 0.8)
    q = standard_domino(gap=0.01, floor="hardwood", model="2d", stiffness_ratio=1e4)
    assert q.model == "2d" and q.young is None and q.stiffness_ratio == 1e4


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (dict(gap=0.0, floor="felt"), r"gap = 0 is outside .*\(0, 0\.048\)"),
        (dict(gap=0.05, floor="felt"), r"gap = 0\.05 is outside"),
        (dict(gap=0.01, floor="carpet"), r"floor = 'carpet' is not a known floor"),
        (dict(gap=0.01, floor="felt", values={"mass": 0.02}), r"mass = 0\.02 is outside"),
        (dict(gap=0.01, floor="felt", values={"poisson": 0.3}), r"'poisson' is not one of"),
        (dict(gap=0.01, floor="felt", model="4d"), r"model = '4d' is not one of"),
    ],
)
def test_standard_domino_bad_input(kwargs, message):
    with pytest.raises(ValueError, match=message):
        standard_domino(**kwargs)


# --------------------------------------------------------------------------- predict

CHEAP = dict(n_dominoes=6, fit_from=2, model="2d", stiffness_ratio=3e3)


def test_predict_points_sample_every_range_of_the_data():
    points, problem, x, fixed = predict_points(0.012, "laminate", 2, **CHEAP)
    entries = standard_entries("laminate")
    assert set(problem["names"]) | set(fixed) == set(SAMPLED)
    assert len(points) == x.shape[0] == 2 * (problem["num_vars"] + 2)
    for j, name in enumerate(problem["names"]):
        lo, hi = entries[name].range
        assert np.all((x[:, j] >= lo) & (x[:, j] <= hi))
        assert [getattr(p, name) for p in points] == list(x[:, j])
    again, *_ = predict_points(0.012, "laminate", 2, **CHEAP)
    assert again == points  # the Sobol' sequence is scrambled by the seed: reproducible


def test_the_study_file_of_a_prediction_leaves_unset_values_out(tmp_path):
    """A sample without a stiffness override (``stiffness_ratio`` not set) is written to
    the sweep's study.toml without it (TOML has no null) and reads back equal."""
    import tomllib

    from dominowave.sweep.presets import preset_study
    from dominowave.sweep.runner import study_toml

    points, *_ = predict_points(0.012, "felt", 1, n_dominoes=6, fit_from=2)
    assert points[0].stiffness_ratio is None
    stored = tomllib.loads(study_toml(preset_study(points, tmp_path)))["sweep"]["points"]
    assert "stiffness_ratio" not in stored[0]
    assert PredictSample(**stored[0]) == points[0]


def test_validate_sobol_indices_of_a_known_function():
    """The analysis step on a function with known Sobol' indices: for
    y = u_0 + 2 u_1 (u uniform on [0, 1], u_2.. inert) S_0 = 1/5, S_1 = 4/5, and the inert
    inputs have S = 0; the change over each range is 1, 2 and 0 exactly (linear); the
    quantile band is that of the sampled y."""
    _, problem, x, fixed = predict_points(0.012, "laminate", 512, **CHEAP)
    u = (x - np.array(problem["bounds"])[:, 0]) / np.ptp(np.array(problem["bounds"]), axis=1)
    y = u[:, 0] + 2.0 * u[:, 1]
    pred = _analyse(0.012, "laminate", problem, x, y, fixed, None)
    np.testing.assert_allclose(pred.sobol_first[:2], [0.2, 0.8], atol=0.05)
    np.testing.assert_allclose(pred.sobol_total[:2], [0.2, 0.8], atol=0.05)
    np.testing.assert_allclose(pred.sobol_total[2:], 0.0, atol=0.02)
    assert pred.band[1] == pytest.approx(np.median(y)) and pred.n_died == 0
    # the effect over the whole range: 1 and 2 (unit ranges), 0 for the inert inputs
    np.testing.assert_allclose(pred.effect, [1.0, 2.0] + [0.0] * (u.shape[1] - 2), atol=1e-12)
    few = slice(0, 2 * (problem["num_vars"] + 2))  # N = 2 base samples: effects, no indices
    rough = _analyse(0.012, "laminate", problem, x[few], y[few], fixed, None)
    np.testing.assert_allclose(rough.effect[:2], [1.0, 2.0], rtol=1e-12)
    assert np.all(np.isnan(rough.sobol_first)) and np.all(np.isnan(rough.sobol_total))
    y[3] = math.nan  # a dead wave: the band stays, the indices are undefined
    dead = _analyse(0.012, "laminate", problem, x, y, fixed, None)
    assert dead.n_died == 1 and np.all(np.isnan(dead.sobol_first))


def test_a_sample_runs_the_preset_chain_and_measures_from_fit_from():
    """A sample's speed is that of the preset chain run in full (its run stops at the
    last domino's touch: the arrivals are the same to the bit)."""
    from dominowave.chain.scenario import DominoChain
    from dominowave.chain.wave import speed_from

    cfg = PredictSample(gap=0.012, floor="felt", friction_floor=0.7, **CHEAP)
    summary = run_predict_sample(cfg).summary
    run = DominoChain(cfg.params()).run()
    assert summary["speed"] == speed_from(run.arrival, run.positions, 2).speed
    assert summary["dominoes_toppled"] == 6


def test_a_run_without_a_tail_stops_at_the_touch_of_the_last_domino():
    """``tail_time=0``: the run ends in the step the wave touches the last domino, with the
    arrivals of the full run to the bit; a negative tail is refused, naming it."""
    from dominowave.chain.scenario import DominoChain

    p = PredictSample(gap=0.012, floor="felt", friction_floor=0.7, **CHEAP).params()
    full = DominoChain(p).run()
    short = DominoChain(p, tail_time=0.0).run()
    assert short.stop_reason == "touched" and short.n_steps < full.n_steps
    np.testing.assert_array_equal(short.arrival, full.arrival)
    with pytest.raises(ValueError, match="tail_time"):
        DominoChain(p, tail_time=-1.0)


def test_a_sample_runs_at_the_fidelity_and_reports_its_contact():
    """Without a stiffness override a sample runs at the default fidelity: the softest
    contact within 2 % of the plastic's speed, its spring and estimated error in the
    summary; ``fidelity = "exact"`` runs the plastic's spring with no error; a tolerance
    for a chain whose modulus a stiffness ratio replaced is refused before any run."""
    base = dict(gap=0.012, floor="hardwood", n_dominoes=5, fit_from=2, model="2d")
    soft = run_predict_sample(PredictSample(**base)).summary
    exact = run_predict_sample(PredictSample(**base, fidelity="exact")).summary
    material = standard_domino(gap=0.012, floor="hardwood").contact_stiffness
    assert exact["contact_kn"] == material and exact["stiffness_error"] == 0.0
    assert soft["contact_kn"] < material / 10
    assert 0.0 < soft["stiffness_error"] <= 1.5 * DEFAULT_TOLERANCE
    assert abs(soft["speed"] / exact["speed"] - 1.0) <= soft["stiffness_error"]
    with pytest.raises(ValueError, match=r"fidelity = 0\.02 softens a chain of given materials"):
        predict_points(0.012, "felt", 1, fidelity=0.02, **CHEAP)


def test_predict_runs_on_the_sweep_engine_writes_and_resumes(tmp_path):
    seen = []
    pred = predict(0.012, "felt", tmp_path, 1, workers=1, progress=seen.append, **CHEAP)
    d = len(pred.names)
    assert len(seen) == pred.speed.size == d + 2 and pred.n_died == pred.n_failed == 0
    assert pred.band[0] <= pred.band[1] <= pred.band[2] and pred.band[0] > 0
    with (tmp_path / "samples.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert [float(r["speed"]) for r in rows] == list(pred.speed)
    # a stiffness ratio replaces the plastic's modulus: nothing is softened
    assert all(float(r["stiffness_error"]) == 0.0 for r in rows)
    assert [float(r["contact_kn"]) for r in rows] == list(pred.contact_kn)
    import xarray as xr

    with xr.open_dataset(tmp_path / "samples.nc") as ds:
        np.testing.assert_array_equal(ds["speed"].values, pred.speed)
        np.testing.assert_array_equal(ds["stiffness_error"].values, pred.stiffness_error)
        assert ds.attrs["fidelity"] == f"{DEFAULT_TOLERANCE:g}"  # not set: the default
        assert ds["young"].attrs["units"] == "Pa"
    with (tmp_path / "prediction.csv").open() as fh:
        names = {r["quantity"] for r in csv.DictReader(fh)}
    assert {"speed_q05", "speed_q50", "speed_q95", "stiffness_error_max"} <= names
    assert {f"ST_{n}" for n in pred.names} | {f"effect_{n}" for n in pred.names} <= names
    assert np.all(np.isfinite(pred.effect)) and np.all(np.isnan(pred.sobol_first))
    again = []
    resumed = predict(0.012, "felt", tmp_path, 1, workers=1, progress=again.append, **CHEAP)
    assert again == [] and np.array_equal(resumed.speed, pred.speed)


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["--samples", "3"], "samples = 3 is not a power of 2"),
        (["--samples", "0"], "samples = 0 must be a power of 2"),
        (["--fit-from", "20"], "fit_from = 20 is outside [1, 10]"),
        (["--floor", "carpet"], "floor = 'carpet' is not a known floor"),
        (["--gap", "-0.01"], "gap = -0.01 is outside"),
        (["--preset", "tiny"], "--preset 'tiny' is not one of standard"),
        (["--workers", "0"], "--workers = 0"),
        (["--fidelity", "0.5"], "fidelity = 0.5 is outside the valid range (0, 0.1]"),
        (["--fidelity", "loose"], "--fidelity 'loose' is not 'exact' or a tolerance"),
    ],
)
def test_predict_command_bad_input_is_one_line(args, fragment, tmp_path):
    """One line even where the kernels would be compiled (an empty numba cache): the
    input is checked before the compile notice."""
    base = {"--gap": "0.01", "--floor": "felt", "--out": str(tmp_path / "p")}
    for flag, value in zip(args[::2], args[1::2], strict=True):
        base[flag] = value
    argv = [a for kv in base.items() for a in kv]
    env = os.environ | {"NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    proc = subprocess.run(
        [sys.executable, "-m", "dominowave", "predict", *argv],
        capture_output=True,
        text=True,
        env=env,
    )
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and fragment in lines[0], proc.stderr


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["--preset", "tiny", "--gap", "0.01", "--floor", "felt"], "preset = 'tiny' is not one"),
        (["--preset", "standard", "--floor", "felt"], "needs --gap [m] and --floor"),
        (
            ["--preset", "standard", "--gap", "0.01", "--floor", "felt", "--friction-floor", "1"],
            "--friction-floor: set by --preset standard from materials.toml",
        ),
        (["--preset", "standard", "--gap", "0.1", "--floor", "felt"], "gap = 0.1 is outside"),
        # a value equal to the chain's own default is refused too: the preset would
        # otherwise replace it without a word
        (
            [
                *("--preset", "standard", "--gap", "0.01", "--floor", "felt"),
                *("--friction-dominoes", "0", "--friction-floor", "0.3"),
            ],
            "--friction-floor, --friction-dominoes: set by --preset standard",
        ),
        (
            ["--preset", "standard", "--gap", "0.01", "--floor", "felt", "--density", "1000"],
            "--density: set by --preset standard",
        ),
        (
            ["--preset", "standard", "--gap", "0.01", "--floor", "felt", "--fidelity", "0"],
            "fidelity = 0 is outside the valid range (0, 0.1]",
        ),
        (["--fidelity", "0.01"], "fidelity = 0.01 softens a chain of given materials only"),
    ],
)
def test_chain_command_preset_bad_input_is_one_line(args, fragment):
    proc = subprocess.run(
        [sys.executable, "-m", "dominowave", "chain", "--n", "3", *args],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and fragment in lines[0], proc.stderr


def test_chain_command_runs_the_standard_preset_and_shows_the_films():
    args = ["--preset", "standard", "--gap", "0.00938", "--floor", "hardwood", "--n", "4"]
    proc = subprocess.run(
        [sys.executable, "-m", "dominowave", "chain", *args, "--model", "2d", "--fit-from", "1"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr
    out = " ".join(proc.stdout.split())  # rich wraps long lines
    assert "front speed from domino 1 on (pitch-based)" in out
    assert "d/l=0.1954," in out  # the preset's d/l rounded in the title
    assert "pair None" not in out
    assert "leaning train (rigid, inelastic; theory.leaning) at friction 0.525: 0.694 m/s" in out
    assert "measured (high-speed films, hardwood, gap 9.38 mm, 7 rows): 1.264 m/s" in out
    assert "inferred from the measurement (not a material value): leaning train 0.04;" in out


# --------------------------------------------------------------------------- study files


def test_a_study_file_names_the_preset(tmp_path):
    """``preset = "standard"`` with gap and floor in a TOML study: the chain of
    ``standard_domino``; its stored (resolved) config reads back as the same scenario;
    sweeping the gap gives the preset at each gap."""
    from dominowave.io.config import load_study, scenario_from_dict
    from dominowave.sweep.hashing import config_dict

    study = tmp_path / "s.toml"
    study.write_text(
        '[scenario]\nkind = "chain"\npreset = "standard"\ngap = 0.00938\nfloor = "felt"\n'
        "n_dominoes = 8\nfit_from = 3\n\n[sweep.grid]\ngap = [0.00938, 0.012]\n"
    )
    loaded = load_study(study)
    expected = standard_domino(gap=0.00938, floor="felt", n_dominoes=8)
    assert loaded.scenario.params() == expected
    assert [p.params() for p in loaded.points] == [
        standard_domino(gap=g, floor="felt", n_dominoes=8) for g in (0.00938, 0.012)
    ]
    again = scenario_from_dict(config_dict(loaded.scenario))
    assert again == loaded.scenario
    assert loaded.scenario.fidelity is None  # not set: the default tolerance
    exact = tmp_path / "exact.toml"
    exact.write_text(study.read_text().replace("fit_from = 3", 'fit_from = 3\nfidelity = "exact"'))
    assert load_study(exact).scenario.fidelity == "exact"


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ('preset = "standard"\nfloor = "felt"', r"needs gap \[m\] and floor"),
        ('preset = "standard"\ngap = 0.01\nfloor = "felt"\nheight = 0.05', "height = 0.05 is set"),
        ('preset = "standard"\ngap = 0.01\nfloor = "felt"\nstiffness_ratio = 1e4', "sets young"),
        ('preset = "standard"\ngap = 0.01\nfloor = "carpet"', "floor = 'carpet' is not a known"),
        ('gap = 0.01\nfloor = "felt"', "give preset too"),
        ('preset = "standard"\ngap = 0.01\nfloor = "felt"\nfidelity = 0.3', "fidelity = 0.3 is"),
    ],
)
def test_a_study_file_with_a_bad_preset_is_refused(table, message, tmp_path):
    from dominowave.io.config import load_study

    study = tmp_path / "s.toml"
    study.write_text(f'[scenario]\nkind = "chain"\n{table}\n')
    with pytest.raises(ValueError, match=message):
        load_study(study)


# --------------------------------------------------------------------------- interrupts


def _interrupted_run(n_points: int, n_done: int, tmp_path):
    from dominowave.sweep.presets import PresetRun
    from dominowave.sweep.runner import SweepReport

    def fake_run_preset(points, out, **_):
        report = SweepReport(tmp_path, total=len(points), skipped=0, ran=n_done, interrupted=130)
        done = [{"speed": 0.7}] * n_done + [None] * (len(points) - n_done)
        return PresetRun(report, done, [None] * len(points), failed=[])

    return fake_run_preset


def test_an_interrupted_prediction_writes_no_result_and_counts_no_dead_wave(tmp_path, monkeypatch):
    """Points the sweep did not run are missing, not 'waves died', and no prediction.csv,
    samples.csv or samples.nc is written from them (the CLI then exits 130)."""
    import dominowave.sweep.predict as predict_module

    monkeypatch.setattr(predict_module, "run_preset", _interrupted_run(0, 5, tmp_path))
    pred = predict(0.00938, "felt", tmp_path, 1, n_dominoes=6, fit_from=2)
    assert pred.n_missing == pred.speed.size - 5 and pred.n_died == 0 and pred.n_failed == 0
    assert not any((tmp_path / name).exists() for name in (SAMPLES_CSV, "samples.nc"))
    assert not (tmp_path / "prediction.csv").exists()


def test_the_predict_command_says_an_interrupted_run_wrote_nothing(tmp_path, monkeypatch):
    from typer.testing import CliRunner

    import dominowave.sweep.predict as predict_module
    from dominowave.cli import app

    monkeypatch.setattr(predict_module, "run_preset", _interrupted_run(0, 3, tmp_path))
    out = tmp_path / "p"
    args = ["predict", "--gap", "0.00938", "--floor", "felt", "--samples", "1", "--n", "6"]
    result = CliRunner().invoke(app, [*args, "--fit-from", "2", "--out", str(out)])
    assert result.exit_code == 130
    assert "points did not run: no prediction written" in " ".join(result.output.split())
    assert "predicted front speed" not in result.output
    assert not (out / "prediction.csv").exists()
