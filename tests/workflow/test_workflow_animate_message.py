"""`animate` on a sweep folder without --point asks for the point."""

from __future__ import annotations

from typer.testing import CliRunner

from dominowave.cli import app


def test_animate_sweep_folder_asks_for_point(tmp_path):
    sweep = tmp_path / "sweep"
    for key in ("b2c3", "a1b2", "c3d4", "d4e5", "e5f6"):
        (sweep / "points" / key).mkdir(parents=True)
    result = CliRunner().invoke(app, ["animate", str(sweep), "--out", str(tmp_path / "m.gif")])
    assert isinstance(result.exception, ValueError)
    message = str(result.exception)
    assert "is a sweep folder: name the point to draw with --point KEY" in message
    assert "a1b2, b2c3, c3d4, d4e5 ... (5 points)" in message
    assert "trajectory" not in message  # not the message for a run without frames
