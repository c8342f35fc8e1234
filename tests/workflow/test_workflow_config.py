"""Study files: parsing, sweeps, examples, TOML round trips, config keys."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

import dominowave
from dominowave.io.config import example_toml, load_study, parse_study
from dominowave.io.models import TheoryScenario
from dominowave.io.toml_text import dumps, line_of_key
from dominowave.sweep.hashing import point_key

EXAMPLES = Path(__file__).parents[2] / "examples"


def study(text: str, tmp_path: Path):
    path = tmp_path / "study.toml"
    path.write_text(text)
    return load_study(path)


def test_sweep_example_is_valid_and_shows_the_defaults(tmp_path):
    loaded = study(example_toml("sweep"), tmp_path)
    assert loaded.scenario == TheoryScenario()
    assert len(loaded.points) == 6


def test_example_documents_every_field_with_its_unit():
    text = example_toml("theory")
    for field, info in TheoryScenario.model_fields.items():
        if field != "kind":
            assert info.description in text, field
    assert "# domino height l  [(0, inf) m]" in text


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_shipped_examples_validate(path):
    loaded = load_study(path)
    assert len(loaded.points) >= 1


def test_grid_is_the_cartesian_product_in_order(tmp_path):
    loaded = study(
        '[scenario]\nkind = "theory"\n[sweep.grid]\nd_over_l = [0.2, 0.4, 0.6]\n'
        "stiffness_ratio = [1.0, 100]\n",
        tmp_path,
    )
    assert len(loaded.points) == 6
    assert [(p.d_over_l, p.stiffness_ratio) for p in loaded.points[:3]] == [
        (0.2, 1.0),
        (0.2, 100.0),
        (0.4, 1.0),
    ]
    assert loaded.swept_keys() == ["d_over_l", "stiffness_ratio"]


def test_listed_points_override_only_their_fields(tmp_path):
    loaded = study(
        '[scenario]\nkind = "theory"\nmass = 0.01\n'
        "[sweep]\npoints = [{d_over_l = 0.2}, {d_over_l = 0.4, mass = 0.02}]\n",
        tmp_path,
    )
    assert [(p.d_over_l, p.mass) for p in loaded.points] == [(0.2, 0.01), (0.4, 0.02)]


def test_stiffness_ratio_resolves_against_k_star():
    cfg = TheoryScenario(stiffness_ratio=100.0, mass=0.01, height=0.05)
    assert cfg.contact_stiffness == pytest.approx(100.0 * 0.01 * 9.81 / 0.05, rel=1e-15)
    assert TheoryScenario().contact_stiffness == math.inf


def test_ints_are_accepted_for_floats_and_hash_like_floats():
    a = parse_study({"scenario": {"kind": "theory", "stiffness_ratio": 100}})
    b = parse_study({"scenario": {"kind": "theory", "stiffness_ratio": 100.0}})
    assert isinstance(a.scenario.stiffness_ratio, float)
    assert point_key(a.scenario) == point_key(b.scenario)


def test_key_changes_with_any_field_and_with_the_version(monkeypatch):
    base = TheoryScenario()
    keys = {point_key(base)}
    for field, value in [("d_over_l", 0.41), ("n_frames", 201), ("stiffness", 1e5)]:
        keys.add(point_key(base.model_copy(update={field: value})))
    assert len(keys) == 4
    assert point_key(TheoryScenario()) == point_key(base)  # deterministic
    monkeypatch.setattr(dominowave, "__version__", "999.0")
    assert point_key(base) not in keys


scalars = st.one_of(
    st.booleans(),
    st.integers(-(2**53), 2**53),
    st.floats(allow_nan=False),
    st.text(alphabet=st.characters(blacklist_categories=("Cs", "Cc")), max_size=12),
)
keys = st.from_regex(r"[a-z_][a-z0-9_]{0,8}", fullmatch=True)
tables = st.dictionaries(
    keys,
    st.one_of(scalars, st.lists(scalars, max_size=3), st.dictionaries(keys, scalars, max_size=3)),
    max_size=5,
)


@given(tables)
def test_toml_writer_round_trips(data):
    assert tomllib.loads(dumps(data)) == data


def test_line_of_key_finds_tables_keys_and_inline_tables():
    text = '[scenario]\nkind = "theory"\n\nspacing = 1\n[sweep]\ngrid = {spacing = [1]}\n'
    assert line_of_key(text, "scenario.spacing") == 4
    assert line_of_key(text, "scenario.height") == 1  # missing key: its table
    assert line_of_key(text, "sweep.grid.spacing") == 6
    assert line_of_key(text, "output.dir") is None
