"""The ``theory`` and ``figures`` commands, run as a user runs them."""

from __future__ import annotations

import csv
import io
import json
import subprocess
import sys

import numpy as np
import pytest

from dominowave import theory as th
from dominowave.cli import main
from dominowave.cli.theory import parse_values, theory_table
from dominowave.theory import leaning


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "dominowave", *args], capture_output=True, text=True, timeout=120
    )


def test_theory_json_matches_library():
    result = run(
        "theory",
        "--d-over-l",
        "0.4",
        "--stiffness-ratio",
        "1e4",
        "--s-over-l",
        "0.1",
        "--friction-floor",
        "0.3",
        "--format",
        "json",
    )
    assert result.returncode == 0, result.stderr
    (row,) = json.loads(result.stdout)
    beta = np.arcsin(0.4)
    # l = g = m = 1: k* = 1 and every quantity is dimensionless
    assert row["beta"] == pytest.approx(beta, rel=1e-14)
    assert row["omega"] == pytest.approx(th.omega_limit(beta, 1, 1), rel=1e-14)
    assert row["v"] == pytest.approx(th.wave_speed(beta, 1, 1, 1e4, 1), rel=1e-14)
    assert row["v_s"] == pytest.approx(row["v"] * 0.5 / 0.4, rel=1e-14)
    assert row["collision_time"] == pytest.approx(th.collision_time(1e4, 1, beta), rel=1e-14)
    assert row["fm_over_mg"] == pytest.approx(th.peak_contact_force(beta, 1, 1, 1e4, 1), rel=1e-14)
    assert row["pair_regime"] is True
    assert row["regime"] == "II forward rotation + slip"


def test_theory_table_accepts_scalars():
    """The public theory_table takes scalars as one-element lists."""
    (row,) = theory_table(0.4, 1e4, 0.1, 0.3)
    assert row == theory_table([0.4], [1e4], 0.1, 0.3)[0]
    assert row["v"] == pytest.approx(th.wave_speed(np.arcsin(0.4), 1, 1, 1e4, 1), rel=1e-14)
    assert len(theory_table(0.4, [1.0, 10.0], 0.1, 0.3)) == 2


def test_theory_csv_grid_and_rigid_limit():
    result = run(
        "theory", "--d-over-l", "0.1:0.8:3", "--stiffness-ratio", "inf,1e8", "--format", "csv"
    )
    assert result.returncode == 0, result.stderr
    rows = list(csv.DictReader(io.StringIO(result.stdout)))
    assert len(rows) == 6
    assert [float(r["d_over_l"]) for r in rows[::2]] == pytest.approx([0.1, 0.45, 0.8])
    rigid = rows[0]
    assert float(rigid["collision_time"]) == 0 and rigid["v_w"] == "inf"
    assert float(rigid["v"]) == pytest.approx(th.mclachlan_G(0.1), rel=1e-12)


def test_theory_table_default():
    result = run("theory")
    assert result.returncode == 0, result.stderr
    lines = result.stdout.strip().splitlines()
    assert lines[0].startswith("# dimensionless")
    assert "F_m/mg" in lines[1] and "pair(T>T_c/2)" in lines[1]
    assert len(lines) == 2 + 9  # 3 spacings x 3 stiffnesses


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["--d-over-l", "1.2"], "d_over_l = 1.2 is outside the valid range (0, 1)"),
        (["--d-over-l", "0,0.5"], "d_over_l = 0 is outside the valid range (0, 1)"),
        (["--stiffness-ratio", "-1"], "stiffness_ratio = -1 is outside the valid range (0, inf]"),
        (["--stiffness-ratio", "0"], "stiffness_ratio = 0 is outside the valid range (0, inf]"),
        (["--friction-floor", "-0.1"], "friction_floor = -0.1 is outside the valid range [0, inf)"),
        (["--s-over-l", "-0.1"], "s_over_l = -0.1 is outside the valid range [0, 1)"),
        (["--d-over-l", "abc"], "d_over_l = 'abc' is not a list"),
        (["--stiffness-ratio", "0:1:3"], "stiffness_ratio = 0 is outside the valid range (0, inf)"),
        (["--k-ratio", "1e4"], "no such option: --k-ratio (renamed: use --stiffness-ratio)"),
        (["--format", "xml"], "format = 'xml' is not one of table, csv, json"),
        (["--convention", "yade"], "convention = 'yade' is not one of paper, contact"),
    ],
)
def test_theory_bad_input_one_line_exit_2(args, fragment, monkeypatch, capsys):
    """In process through the console-script entry point (a subprocess per case would
    re-import every command module): one line on stderr, exit code 2."""
    monkeypatch.setattr(sys, "argv", ["dominowave", "theory", *args])
    with pytest.raises(SystemExit) as info:
        main()
    assert info.value.code == 2
    out, err = capsys.readouterr()
    assert out == ""
    (line,) = err.strip().splitlines()
    assert line.startswith(f"dominowave: error: {fragment}")
    assert "Traceback" not in err


def test_parse_values_ranges():
    """In process (no subprocess): geometric ranges need finite positive ends."""
    np.testing.assert_allclose(parse_values("1:100:3", "k_ratio", geometric=True), [1, 10, 100])
    np.testing.assert_allclose(parse_values("0:1:3", "d_over_l"), [0, 0.5, 1])
    with pytest.raises(ValueError, match=r"k_ratio = inf is outside the valid range \(0, inf\)"):
        parse_values("1:inf:3", "k_ratio", geometric=True)
    with pytest.raises(ValueError, match="k_ratio = '1:10:x' is not a list"):
        parse_values("1:10:x", "k_ratio", geometric=True)


def test_figures_written_with_their_data(tmp_path):
    result = run("figures", "--out", str(tmp_path / "figs"))
    assert result.returncode == 0, result.stderr
    for name in ("fig1d", "fig4a", "fig4b", "fig5b", "leaning"):
        png = tmp_path / "figs" / f"{name}.png"
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000
        assert (tmp_path / "figs" / f"{name}.csv").exists()
    data = np.genfromtxt(tmp_path / "figs" / "fig4a.csv", delimiter=",", names=True)
    np.testing.assert_allclose(data["v_k1e4"], th.wave_speed(data["beta"], 1, 1, 1e4, 1), rtol=1e-9)
    np.testing.assert_array_equal(
        data["pair_k1e8"].astype(bool), th.pair_regime_holds(data["beta"], 1, 1, 1e8, 1)
    )
    lean = np.genfromtxt(tmp_path / "figs" / "leaning.csv", delimiter=",", names=True)
    np.testing.assert_allclose(
        lean["leaning_mu03_m_s"],
        leaning.limit_speed(height=0.048, thickness=0.0075, gap=lean["gap_m"], friction=0.3),
        rtol=1e-12,
    )
    fig5 = np.genfromtxt(tmp_path / "figs" / "fig5b.csv", delimiter=",", names=True)
    np.testing.assert_allclose(
        fig5["fm_over_mg_k1e1"], th.peak_contact_force(fig5["beta"], 1, 1, 10, 1), rtol=1e-9
    )
    for tag in ("1", "1e1", "1e2"):  # no pure rotation where the base slides (eq 39)
        pure = fig5["regime_k" + tag] == 1
        assert not np.any(pure & (fig5["fm_over_mg_k" + tag] * np.cos(fig5["beta"]) > 0.3))
    assert not np.all(fig5["by_paper_k1"])  # the curves cross the set the paper leaves open
    fig1 = np.genfromtxt(tmp_path / "figs" / "fig1d.csv", delimiter=",", names=True)
    assert fig1["omega_beta07_push05"][-1] == pytest.approx(fig1["omega_limit_beta07"][0], rel=1e-6)


def test_figures_bad_directory(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    result = run("figures", "--out", str(blocker / "sub"))
    assert result.returncode == 2
    assert len(result.stderr.strip().splitlines()) == 1
    assert result.stderr.startswith("dominowave: error:")


def test_leaning_json_matches_library_with_units_in_the_table_header():
    result = run("leaning", "--gap", "0.00938,0.045", "--friction", "0.3", "--format", "json")
    assert result.returncode == 0, result.stderr
    steady, flat = json.loads(result.stdout)
    st = leaning.steady_state(0.048, 0.0075, 0.00938, 0.3)
    assert steady["speed"] == pytest.approx(st.speed, rel=1e-14)
    assert steady["friction_loss"] == pytest.approx(1e3 * 0.008 * st.friction_loss, rel=1e-14)
    assert steady["note"] == "steady train"
    assert flat["speed"] == "nan" and "lie flat" in flat["note"]
    table = run("leaning", "--gap", "0.00938", "--friction", "0,0.525").stdout.splitlines()
    assert table[0].startswith("# leaning train") and "m/s^2" in table[0]
    for unit in ("gap[m]", "v[m/s]", "omega+[rad/s]", "T[s]", "E_rel[mJ]"):
        assert unit in table[1]
    assert len(table) == 4


def test_leaning_help_shows_units_and_bad_gap_is_one_line():
    help_text = run("leaning", "--help").stdout
    for option_unit in ("d [m]", "l [m]", "s [m]", "[kg]", "[m/s^2]"):
        assert option_unit in help_text
    result = run("leaning", "--gap", "0.06")
    assert result.returncode == 2
    assert result.stderr.strip().startswith("dominowave: error: gap = 0.06 is outside")
    assert len(result.stderr.strip().splitlines()) == 1
