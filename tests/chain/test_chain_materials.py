"""The shipped material data of the standard domino and the loader's checks of a bad file."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from dominowave.chain.materials import (
    KINDS,
    MaterialsError,
    floor_friction,
    load_materials,
)

SHIPPED = Path(__file__).parents[2] / "src/dominowave/chain/data/materials.toml"
PYPROJECT = Path(__file__).parents[2] / "pyproject.toml"


@pytest.fixture(scope="module")
def mat():
    return load_materials()


def test_every_entry_is_cited_and_its_range_holds_the_nominal_value(mat):
    names = []
    for name, e in mat.entries():
        names.append(name)
        assert e.lo <= e.value <= e.hi, name
        assert e.unit, name
        assert e.kind in KINDS, name
        assert len(e.source) >= 20, name
        if e.kind != "assumption":  # a cited value names a document: a URL or a publisher
            assert "http" in e.source or "Handbook" in e.source, name
        else:
            assert e.source.startswith("Assumption"), name
    assert len(names) == len(set(names)) >= 14


def test_the_floors_the_issue_asks_for_are_there(mat):
    assert {"hardwood", "felt", "laminate", "glass"} <= set(mat.floor_names)
    assert floor_friction("felt") == mat.floor_friction("felt")


def test_unknown_floor_names_the_floor_and_the_known_ones(mat):
    with pytest.raises(ValueError, match=r"floor = 'carpet' is not a known floor.*felt.*glass"):
        mat.floor_friction("carpet")


def test_the_standard_domino_is_48_by_24_by_7_5_mm(mat):
    d = mat.domino
    assert (d.height.value, d.width.value, d.thickness.value) == (0.048, 0.024, 0.0075)
    assert d.height.unit == d.width.unit == d.thickness.unit == "m"


def test_the_nominal_mass_and_density_are_consistent_within_the_ranges(mat):
    """The quoted 8 g is below a full box at the quoted density (rounded edges or a rounded
    mass); the mass range reaches the full box, so both readings stay inside the data."""
    d = mat.domino
    box = d.height.value * d.width.value * d.thickness.value
    full_box_mass = mat.plastic.density.value * box
    assert d.mass.value < full_box_mass
    assert full_box_mass == pytest.approx(d.mass.hi, rel=1e-3)


def test_the_data_file_is_package_data_so_a_wheel_ships_it():
    """A non-editable install only ships data files that pyproject's package-data names."""
    config = tomllib.loads(PYPROJECT.read_text(encoding="utf-8"))
    globs = config["tool"]["setuptools"]["package-data"]["dominowave.chain"]
    data_dir = SHIPPED.parent
    for path in data_dir.iterdir():
        if path.is_file():
            assert any(path.relative_to(data_dir.parent).match(g) for g in globs), path.name


# --- a bad file gives one clear error --------------------------------------------------------


def _write(tmp_path, text: str) -> Path:
    path = tmp_path / "materials.toml"
    path.write_text(text, encoding="utf-8")
    return path


def _shipped_with(old: str, new: str) -> str:
    text = SHIPPED.read_text(encoding="utf-8")
    assert old in text, old
    return text.replace(old, new, 1)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            "[plastic.density]\nvalue = 1060.0",
            "[plastic.density]\nvalue = 1200.0",
            r"\[plastic.density\]: value = 1200 is outside its range \[lo, hi\] = \[1020, 1080\]",
        ),
        (
            '[plastic.density]\nvalue = 1060.0\nlo = 1020.0\nhi = 1080.0\nunit = "kg/m^3"',
            '[plastic.density]\nvalue = 1060.0\nlo = 1020.0\nhi = 1080.0\nunit = "g/cm^3"',
            r"\[plastic.density\]: unit = 'g/cm\^3', expected 'kg/m\^3'",
        ),
        (
            'kind = "assumption"\nsource = "Assumption: no published friction',
            'kind = "guess"\nsource = "Assumption: no published friction',
            r"\[friction.floor.felt\]: kind = 'guess' is not one of manufacturer",
        ),
        (
            "[restitution.domino_floor]\nvalue = 0.5\nlo = 0.1\nhi = 0.9",
            "[restitution.domino_floor]\nvalue = 0.5\nlo = 0.1\nhi = 1.2",
            r"\[restitution.domino_floor\]: range \[lo, hi\] = \[0.1, 1.2\] leaves the physical "
            r"interval \[0, 1\]",
        ),
        (
            "[plastic.youngs_modulus]\nvalue = 2.39e9\nlo = 2.0e9",
            "[plastic.youngs_modulus]\nvalue = 2.39e9\nlo = 0.0",
            r"\[plastic.youngs_modulus\]: range .* leaves the physical interval \(0, inf\]",
        ),
        (
            "[domino.mass]\nvalue = 0.008",
            '[domino.mass]\nvalue = "8 g"',
            r"\[domino.mass\]: value = '8 g' is not a number",
        ),
        (
            "[domino.mass]\nvalue = 0.008",
            "[domino.mass]\nvalue = nan",
            r"\[domino.mass\]: value = nan is not a finite number",
        ),
        (
            "[friction.floor.glass]",
            '[friction.floor.marble]\nvalue = 0.3\nlo = 0.2\nhi = 0.4\nunit = "1"\n'
            'kind = "handbook"\n\n[friction.floor.glass]',
            r"\[friction.floor.marble\]: missing source",
        ),
        (
            "[restitution.domino_domino]",
            "[restitution.domino_dominoes]",
            r"missing entry \[restitution.domino_domino\]",
        ),
        ("schema = 1", "schema = 2", r"schema = 2, expected 1"),
    ],
)
def test_bad_file_content_gives_a_clear_error(tmp_path, old, new, message):
    path = _write(tmp_path, _shipped_with(old, new))
    with pytest.raises(MaterialsError, match=message):
        load_materials(path)


def test_an_uncited_entry_is_refused(tmp_path):
    text = SHIPPED.read_text(encoding="utf-8")
    start = text.index("[restitution.domino_floor]")
    head, tail = text[:start], text[start:]
    tail = tail[: tail.index("source =")] + 'source = "see above"\n'
    with pytest.raises(MaterialsError, match=r"domino_floor\]: source = 'see above' is not a cit"):
        load_materials(_write(tmp_path, head + tail))


def test_unknown_keys_and_tables_are_refused(tmp_path):
    bad_key = _shipped_with(
        "[domino.mass]\nvalue = 0.008", "[domino.mass]\nvalu = 1\nvalue = 0.008"
    )
    with pytest.raises(MaterialsError, match=r"\[domino.mass\]: unknown key\(s\) valu"):
        load_materials(_write(tmp_path, bad_key))
    extra = SHIPPED.read_text(encoding="utf-8") + '\n[colour]\nname = "red"\n'
    with pytest.raises(MaterialsError, match=r"unknown table\(s\) colour"):
        load_materials(_write(tmp_path, extra))
    extra_entry = _shipped_with("[domino.height]", "[domino.colour]\n\n[domino.height]")
    with pytest.raises(MaterialsError, match=r"unknown entry\(ies\) \[domino.colour\]"):
        load_materials(_write(tmp_path, extra_entry))


def test_missing_file_and_broken_toml_name_the_file(tmp_path):
    with pytest.raises(MaterialsError, match=r"nowhere.toml: no such file"):
        load_materials(tmp_path / "nowhere.toml")
    with pytest.raises(MaterialsError, match=r"materials.toml: not valid TOML"):
        load_materials(_write(tmp_path, "[domino\n"))


def test_the_user_docs_table_shows_the_shipped_values(mat):
    doc = (Path(__file__).parents[2] / "docs/real_dominoes.md").read_text(encoding="utf-8")
    for name, e in mat.entries():
        row = f"| `{name}` | {e.value:g} | [{e.lo:g}, {e.hi:g}] | {e.unit} | {e.kind} |"
        assert row in doc, row
