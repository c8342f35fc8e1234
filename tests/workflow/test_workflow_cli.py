"""The workflow commands end to end: the example study through sweep, collect, plot, animate."""

from __future__ import annotations

from pathlib import Path

import pytest

EXAMPLE = Path(__file__).parents[2] / "examples" / "fig4_theory_sweep.toml"


def test_example_study_sweep_collect_plot_animate(dask_client, tmp_path, cli):
    import xarray as xr

    out = tmp_path / "fig4"
    addr = dask_client.scheduler.address
    code, stdout, err = cli("sweep", EXAMPLE, "--out", out, "--scheduler", addr, "--quiet")
    assert code == 0, err
    assert "57 points, 0 already stored, 57 run now (0 failed)" in stdout
    assert err == ""  # no progress bar when not on a terminal
    code, stdout, _ = cli("sweep", EXAMPLE, "--out", out, "--scheduler", addr)
    assert "57 already stored, 0 run now" in stdout
    code, stdout, _ = cli("collect", out)
    assert code == 0 and "d_over_l: 19, stiffness_ratio: 3" in stdout
    with xr.open_dataset(out / "collected.nc") as ds:
        assert ds.speed.shape == (19, 3)
    code, stdout, _ = cli("plot", out)
    figures = sorted(p.name for p in (out / "figures").iterdir())
    assert figures == ["arrival_times.png", "local_speed.png", "speed_vs_spacing.png"]
    assert all((out / "figures" / f).stat().st_size > 10_000 for f in figures)
    key = next((out / "points").iterdir()).name
    movie = tmp_path / "chain.gif"
    code, _, err = cli("animate", out, "--out", movie)  # a sweep folder, no --point
    assert code == 2 and "--point KEY" in err and "trajectory" not in err
    code, stdout, err = cli(
        "animate",
        out,
        "--point",
        key,
        "--out",
        movie,
        "--fps",
        "5",
        "--slowdown",
        "1",
    )
    assert code == 0, err
    assert movie.stat().st_size > 0


def test_run_writes_results_and_vtk(tmp_path, cli):
    study = tmp_path / "s.toml"
    code, text, _ = cli("config", "--example", "theory")
    study.write_text(text.replace("n_frames = 200", "n_frames = 30"))
    code, stdout, err = cli("config", study)
    assert code == 0 and "ok, scenario theory, 1 point(s)" in stdout
    out = tmp_path / "run"
    code, stdout, err = cli("run", study, "--out", out, "--vtk", "every=10")
    assert code == 0, err
    assert sorted(p.name for p in out.iterdir()) == [
        "config.toml",
        "events.csv",
        "provenance.json",
        "summary.json",
        "trajectory.nc",
        "vtk",
    ]
    assert len(list((out / "vtk").glob("dominoes_*.vtu"))) == 3
    code, stdout, _ = cli("run", study, "--out", out)
    assert code == 0 and stdout.startswith("up to date")
    code, stdout, _ = cli("plot", out)
    assert code == 0 and (out / "figures" / "local_speed.png").is_file()


@pytest.mark.parametrize("kind", ["theory", "rods", "chain", "sweep"])
def test_config_example_prints_a_valid_study(kind, tmp_path, cli):
    from dominowave.io.config import SCENARIO_MODELS

    code, text, _ = cli("config", "--example", kind)
    (tmp_path / "s.toml").write_text(text)
    code, stdout, _ = cli("config", tmp_path / "s.toml")
    assert code == 0
    assert ("6 point(s)" in stdout) == (kind == "sweep")
    if kind != "sweep":  # the example is the model's defaults, every field written out
        from dominowave.io.config import load_study

        assert load_study(tmp_path / "s.toml").scenario == SCENARIO_MODELS[kind]()
