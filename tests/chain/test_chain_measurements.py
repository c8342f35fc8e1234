"""The shipped table of published wave-speed measurements and the loader's checks."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from dominowave.chain.measurements import (
    BASES,
    COLUMNS,
    SPEED_KINDS,
    MeasurementsError,
    load_measurements,
)

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
