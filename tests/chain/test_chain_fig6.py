"""The Fig 6 study (tiny preset) on the sweep engine, its plots and the CLI commands."""

from __future__ import annotations

import csv
import re
import subprocess
import sys

import pytest

from dominowave.plots.fig6 import plot_fig6
from dominowave.sweep.fig6 import Fig6Preset, read_rows, run_fig6, summarise

TINY = Fig6Preset("tiny", d_over_l=(0.5,), members=2, n_dominoes=6, configs=("2d", "mu0.6"))


def test_sweep_writes_rows_resumes_and_summarises(tmp_path):
    seen = []
    run_fig6(TINY, tmp_path, workers=1, progress=seen.append)
    path = tmp_path / "runs.csv"
    rows = read_rows(path)
    assert len(rows) == len(seen) == 4
    # a re-run finds every row done and runs nothing (resumable, nothing lost)
    again = []
    run_fig6(TINY, tmp_path, workers=1, progress=again.append)
    assert again == [] and len(read_rows(path)) == 4
    summary = summarise(rows)
    assert {s["config"] for s in summary} == {"2d", "mu0.6"}
    assert all(s["members"] == 2 and s["theory_speed"] > 0 for s in summary)
    written = plot_fig6(summary, tmp_path / "fig")
    names = {p.name for p in written}
    assert {"fig6C.png", "fig6D.csv", "fig6E.png"} <= names
    with (tmp_path / "fig" / "fig6D.csv").open() as fh:
        assert len(list(csv.DictReader(fh))) == 2


def test_a_study_member_is_the_ensemble_member_of_the_same_seed():
    """Member i of the Fig 6 study pushes and runs exactly as member i of
    ``DominoChain.ensemble`` (push scaled by 1 + jitter N(0,1) from default_rng([seed, i]))."""
    from dominowave.chain import DominoChain
    from dominowave.chain.paper_fig6 import fig6_params, run_member

    ens = DominoChain(fig6_params("2d", 0.5, 6)).ensemble(None, members=2, seed=3, jitter=0.01)
    for i, run in enumerate(ens.runs):
        row = run_member("2d", 0.5, i, 6, seed=3, jitter=0.01)
        assert row["push_omega"] == run.omega_1
        assert row["n_steps"] == run.n_steps
        assert row["reached"] == run.wave.reached
    assert ens.runs[0].omega_1 != ens.runs[1].omega_1


def test_summary_does_not_depend_on_completion_order():
    """Workers append rows in the order they finish; the summary sums members in member
    order, so it is reproducible to the last bit ((0.1 + 0.2) + 0.3 != (0.3 + 0.2) + 0.1)."""
    fields = (
        "theory_speed theory_speed_point theory_speed_rigid multiple_collision_fraction "
        "mean_hits_in_passage mean_abs_slip forward_slip_fraction wall_time"
    ).split()
    rows = [
        {"config": "2d", "d_over_l": 0.4, "member": m, "speed": v, "theory_window_speed": v}
        | dict.fromkeys(fields, v)
        for m, v in enumerate((0.1, 0.2, 0.3))
    ]
    forward, backward = summarise(rows)[0], summarise(rows[::-1])[0]
    assert forward == backward
    assert forward["speed_mean"] == ((0.1 + 0.2) + 0.3) / 3


def _cli(*args, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "dominowave", *args],
        capture_output=True, text=True, cwd=cwd, timeout=600,
    )  # fmt: skip


def test_chain_command_table_csv_plot(tmp_path):
    res = _cli("chain", "--n", "6", "--d-over-l", "0.5", "--members", "2", "--out", str(tmp_path))
    assert res.returncode == 0, res.stderr
    assert "steady speed" in res.stdout and "limit speed eq 34" in res.stdout
    assert (tmp_path / "chain.png").stat().st_size > 0
    with (tmp_path / "chain_dominoes.csv").open() as fh:
        assert len(list(csv.DictReader(fh))) == 6


def test_chain_command_reports_an_unsettled_wave_without_nan():
    # At d/l = 0.4 the undamped 30-domino wave still accelerates at the end of the chain
    # (f_+ close to 1: a long transient). The command says so and compares the tail of
    # the chain with the theory's transient instead of printing a NaN speed.
    res = _cli("chain", "--n", "30", "--d-over-l", "0.4")
    assert res.returncode == 0, res.stderr
    assert "not settled" in res.stdout and "theory transient over the same dominoes" in res.stdout
    assert "nan ±" not in res.stdout
    # the main job's summary: the difference in %, what the ± is, what the slip is
    out = " ".join(res.stdout.split())
    assert re.search(r"theory transient over the same dominoes: [0-9.]+ m/s \([+-][0-9.]+ % ", out)
    assert "not the spread of the speed between runs" in out
    assert "domino 0 has no neighbour behind it" in out


def test_chain_command_names_units_and_which_speed_to_quote(cli):
    code, stdout, _ = cli("chain", "--n", "12", "--d-over-l", "0.6", "--members", "4")
    assert code == 0
    header = next(line for line in stdout.splitlines() if "t_arr" in line)
    for unit in ("t_arr [s]", "t_theory [s]", "v_local [m/s]", "slip [m]", "max tilt [rad]"):
        assert unit in header
    quote = stdout[stdout.index("quote the") :]
    assert quote.startswith("quote the ensemble speed with its standard error")
    # members whose wave did not settle are named beside the ensemble, never silently dropped
    ensemble = next(line for line in stdout.splitlines() if line.startswith("ensemble"))
    assert "n=4)" in ensemble or "members did not settle and are left out" in ensemble


def test_chain_command_rejects_bad_input_in_one_line():
    res = _cli("chain", "--d-over-l", "1.5")
    assert res.returncode == 2
    assert res.stderr.strip().startswith("dominowave: error: --d-over-l = 1.5")
    assert len(res.stderr.strip().splitlines()) == 1


@pytest.mark.slow
def test_paper_fig6_quick_preset(tmp_path):
    res = _cli("paper-fig6", "--quick", "--out", str(tmp_path))
    assert res.returncode == 0, res.stderr
    for panel in "BCDE":
        assert (tmp_path / f"fig6{panel}.png").stat().st_size > 0
    assert len(read_rows(tmp_path / "runs.csv")) == 2 * 2 * 8


@pytest.mark.slow
def test_paper_fig6_stops_on_sigterm_keeps_its_members_and_resumes(tmp_path):
    """``kill`` (SIGTERM) stops the preset's sweep with exit code 143, every finished member
    stored and in runs.csv; the same command again runs only the missing members."""
    import signal
    import time

    out = tmp_path / "fig6"
    proc = subprocess.Popen(
        [sys.executable, "-m", "dominowave", "paper-fig6", "--quick", "--out", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    points = out / "points"
    end = time.monotonic() + 600
    while time.monotonic() < end and proc.poll() is None:
        if points.is_dir() and any(not p.name.startswith(".") for p in points.iterdir()):
            break
        time.sleep(0.05)
    proc.send_signal(signal.SIGTERM)
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 143, stderr
    assert "Traceback" not in stderr and "sweep interrupted: 32 points" in stdout
    stored = [p for p in points.iterdir() if not p.name.startswith(".")]
    assert 1 <= len(stored) < 32
    assert len(read_rows(out / "runs.csv")) == len(stored)
    again = _cli("paper-fig6", "--quick", "--out", str(out))
    assert again.returncode == 0, again.stderr
    assert f"{len(stored)} already stored, {32 - len(stored)} run now" in again.stdout
    assert len(read_rows(out / "runs.csv")) == 32
