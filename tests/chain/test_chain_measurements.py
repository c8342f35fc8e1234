"""The shipped table of published wave-speed measurements and the loader's checks."""

from __future__ import annotations

import csv
import math
import subprocess
import sys
from pathlib import Path

import pytest
from scipy.integrate import quad

from dominowave.chain.measurements import (
    BASES,
    COLUMNS,
    SPEED_KINDS,
    MeasurementsError,
    eq34_rigid_speed,
    load_measurements,
)
from dominowave.theory import omega_limit
from dominowave.units import G_STANDARD

SHIPPED = Path(__file__).parents[2] / "src/dominowave/chain/data/measurements.csv"


def test_every_measurement_is_cited_and_says_where_it_is_printed():
    rows = load_measurements()
    assert rows
    assert len({m.key for m in rows}) == len(rows)
    for m in rows:
        assert "http" in m.source or "doi" in m.source.lower(), m.key
        assert m.method and m.where_printed, m.key
        assert m.spacing_basis in BASES and m.speed_kind in SPEED_KINDS, m.key
        assert 0.05 < m.speed < 10.0, m.key  # dominoes topple at walking pace, not faster


def test_a_speed_the_source_does_not_print_comes_with_its_arithmetic():
    """Where a source prints only raw observations (frames, times), the row says that the
    speed is not printed and its note says how the speed was computed from them."""
    derived = [m for m in load_measurements() if "speed itself is not printed" in m.where_printed]
    assert derived  # the high-speed-camera rows of section 3
    for m in derived:
        assert "fitted here" in m.note or "computed here" in m.note, m.key


def test_gap_and_pitch_convert_with_the_thickness(tmp_path):
    row = _good_row(spacing_m="0.020", spacing_basis="pitch", thickness_m="0.0075")
    (m,) = load_measurements(_write(tmp_path, [row]))
    assert m.pitch == 0.020
    assert m.gap == pytest.approx(0.0125)
    row = _good_row(spacing_m="0.020", spacing_basis="gap", thickness_m="")
    (m,) = load_measurements(_write(tmp_path, [row]))
    assert (m.gap, m.pitch, m.thickness) == (0.020, None, None)


# --- bad file content -------------------------------------------------------------------------


def _good_row(**cells) -> dict[str, str]:
    row = dict.fromkeys(COLUMNS, "")
    row.update(
        key="a2020",
        source="A. Author, J. Dominoes 1, 1 (2020), https://example.org/a2020",
        method="high-speed camera",
        height_m="0.048",
        thickness_m="0.0075",
        material="ABS",
        floor="felt",
        spacing_m="0.01",
        spacing_basis="gap",
        speed_m_s="1.2",
        speed_kind="asymptotic",
        n_dominoes="30",
        where_printed="Table 1",
    )
    row.update(cells)
    return row


def _write(tmp_path, rows, header=COLUMNS) -> Path:
    path = tmp_path / "measurements.csv"
    with path.open("w", encoding="utf-8", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for row in rows:
            w.writerow([row.get(c, "") for c in header])
    return path


@pytest.mark.parametrize(
    ("cells", "message"),
    [
        ({"speed_m_s": ""}, r"line 2: speed_m_s is empty but required"),
        ({"speed_m_s": "fast"}, r"line 2: speed_m_s = 'fast' is not a number"),
        ({"speed_m_s": "-1"}, r"line 2: speed_m_s = -1 is outside \(0, inf\)"),
        ({"spacing_m": "inf"}, r"line 2: spacing_m = 'inf' is not a finite number"),
        ({"height_m": "0"}, r"line 2: height_m = 0 is outside \(0, inf\)"),
        ({"speed_unc_m_s": "-0.1"}, r"line 2: speed_unc_m_s = -0.1 is outside \[0, inf\)"),
        ({"spacing_basis": "centre"}, r"line 2: spacing_basis = 'centre' is not one of"),
        ({"speed_kind": "peak"}, r"line 2: speed_kind = 'peak' is not one of"),
        ({"n_dominoes": "2.5"}, r"line 2: n_dominoes = '2.5' is not an integer >= 2"),
        ({"source": "me"}, r"line 2: source = 'me' is not a citation"),
        ({"where_printed": ""}, r"line 2: where_printed is empty but required"),
        (
            {"spacing_basis": "pitch", "spacing_m": "0.007"},
            r"line 2: pitch 0.007 m minus thickness 0.0075 m leaves no gap",
        ),
    ],
)
def test_bad_cells_give_a_clear_error(tmp_path, cells, message):
    with pytest.raises(MeasurementsError, match=message):
        load_measurements(_write(tmp_path, [_good_row(**cells)]))


def test_duplicate_keys_wrong_headers_and_empty_files_are_refused(tmp_path):
    with pytest.raises(MeasurementsError, match=r"line 3: key = 'a2020' appears twice"):
        load_measurements(_write(tmp_path, [_good_row(), _good_row()]))
    header = (*(c for c in COLUMNS if c != "where_printed"), "page")
    with pytest.raises(MeasurementsError, match=r"missing where_printed; unknown page"):
        load_measurements(_write(tmp_path, [_good_row()], header=header))
    swapped = ("source", "key", *COLUMNS[2:])
    with pytest.raises(MeasurementsError, match=r"columns out of order"):
        load_measurements(_write(tmp_path, [_good_row()], header=swapped))
    with pytest.raises(MeasurementsError, match=r"no measurements"):
        load_measurements(_write(tmp_path, []))
    with pytest.raises(MeasurementsError, match=r"nowhere.csv: no such file"):
        load_measurements(tmp_path / "nowhere.csv")


def test_a_row_with_a_missing_cell_is_refused(tmp_path):
    path = tmp_path / "measurements.csv"
    path.write_text(",".join(COLUMNS) + "\n" + "a,b,c\n", encoding="utf-8")
    with pytest.raises(MeasurementsError, match=r"line 2: expected 17 cells"):
        load_measurements(path)


def test_the_shipped_file_has_the_documented_columns():
    assert SHIPPED.read_text(encoding="utf-8").splitlines()[0] == ",".join(COLUMNS)


# --- the paper's eq 34 beside each measurement ------------------------------------------------


def test_validate_eq34_rigid_speed_by_quadrature_of_the_free_fall(tmp_path):
    """``(d + s) / T`` with ``T`` integrated directly: a point mass on a massless rod of
    height ``l`` falls from upright at the EJ limit rate ``Omega`` (eq 9) to ``beta``,
    ``theta'^2 = Omega^2 + 2 g/l (1 - cos theta)`` (energy), ``T = int dtheta / theta'``."""
    l, s, g, d = 0.048, 0.0075, G_STANDARD, 0.012
    beta = math.asin(d / l)
    omega = float(omega_limit(beta, l, g))
    fall, _ = quad(lambda th: 1.0 / math.sqrt(omega**2 + 2 * g / l * (1 - math.cos(th))), 0, beta)
    for basis, spacing in (("gap", d), ("pitch", d + s)):
        row = _good_row(spacing_m=str(spacing), spacing_basis=basis, thickness_m=str(s))
        (m,) = load_measurements(_write(tmp_path, [row]))
        assert eq34_rigid_speed(m) == pytest.approx((d + s) / fall, rel=1e-9)


def test_eq34_rigid_speed_needs_height_thickness_and_a_gap_below_the_height(tmp_path):
    for cells in ({"height_m": ""}, {"thickness_m": ""}, {"spacing_m": "0.05"}):
        (m,) = load_measurements(_write(tmp_path, [_good_row(**cells)]))
        assert eq34_rigid_speed(m) is None


def test_the_theory_table_script_regenerates_the_table(tmp_path):
    script = Path(__file__).parents[2] / "docs/real_dominoes/theory_table.py"
    rows = [_good_row(), _good_row(key="b2021", height_m="")]
    out_csv = tmp_path / "table.csv"
    done = subprocess.run(
        [
            sys.executable,
            str(script),
            "--measurements",
            str(_write(tmp_path, rows)),
            "--csv",
            str(out_csv),
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    lines = done.stdout.splitlines()
    assert lines[0].startswith("| key |") and len(lines) == 4
    (m,) = load_measurements(_write(tmp_path, [_good_row()]))
    expected = eq34_rigid_speed(m)
    table = list(csv.DictReader(out_csv.open(encoding="utf-8")))
    assert float(table[0]["eq34_m_s"]) == pytest.approx(expected, rel=1e-2)
    assert table[0]["diff_pct"] == f"{100 * (expected - 1.2) / 1.2:+.0f}"
    assert table[1]["eq34_m_s"] == table[1]["diff_pct"] == "n/a"


def test_the_shipped_theory_table_is_current():
    """docs/real_dominoes/theory_vs_measurements.csv and the table in real_dominoes.md are
    what the script makes of the shipped data."""
    script = Path(__file__).parents[2] / "docs/real_dominoes/theory_table.py"
    shipped = script.parent / "theory_vs_measurements.csv"
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, check=True)
    n_rows = len(list(csv.DictReader(shipped.open(encoding="utf-8"))))
    assert n_rows == len(load_measurements()) == len(done.stdout.splitlines()) - 2
    doc = (script.parents[1] / "real_dominoes.md").read_text(encoding="utf-8")
    assert done.stdout.strip() in doc, "regenerate the table in docs/real_dominoes.md"
