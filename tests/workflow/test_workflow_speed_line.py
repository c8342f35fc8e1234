"""`dominowave run` ends with the wave speed, or "not settled" and the reason."""

from __future__ import annotations

from typer.testing import CliRunner

from dominowave.cli import app
from dominowave.io.config import example_toml
from dominowave.io.results import read_summary


def test_run_of_the_rods_example_says_why_its_speed_is_missing(tmp_path):
    """`config --example rods` has the face-normal contact without damping: its wave keeps
    accelerating; the run says so, and summary.json keeps the reason (speed_note)."""
    study = tmp_path / "rods.toml"
    study.write_text(example_toml("rods").replace("n_dominoes = 30", "n_dominoes = 12"))
    result = CliRunner().invoke(app, ["run", str(study), "--out", str(tmp_path / "r")])
    assert result.exit_code == 0, result.output
    line = result.output.strip().splitlines()[-1]
    assert line.startswith("speed: not settled (the wave is still")
    assert 'normal = "head-on"' in line
    assert read_summary(tmp_path / "r")["speed_note"] in line


def test_run_of_a_settling_study_prints_its_speed(tmp_path):
    study = tmp_path / "theory.toml"
    study.write_text(example_toml("theory"))
    result = CliRunner().invoke(app, ["run", str(study), "--out", str(tmp_path / "t")])
    assert result.exit_code == 0, result.output
    speed = read_summary(tmp_path / "t")["speed"]
    assert result.output.strip().splitlines()[-1].startswith(f"speed: {speed:.4g}")
