"""A chain's preset and numerics (``chain.settings``): declared once, checked when made,
read the same way by a study file and by ``dominowave chain``."""

from __future__ import annotations

import re
import typing

import pytest
from pydantic import ValidationError

from dominowave.chain.settings import ChainSettings, numerics
from dominowave.io.models import ChainScenario
from dominowave.params import parameter_specs


def test_the_settings_are_checked_when_made():
    assert ChainSettings() == ChainSettings(fidelity=None, sleep=True, preset=None)
    assert ChainSettings(fidelity="exact").fidelity == "exact"
    assert ChainSettings(fidelity=0.05).fidelity == 0.05
    with pytest.raises(ValueError, match=r"fidelity = 0\.5 is outside the valid range"):
        ChainSettings(fidelity=0.5)
    not_a_tolerance = re.escape("fidelity = '0.05' is not 'exact' or a tolerance")
    with pytest.raises(ValueError, match=not_a_tolerance):
        ChainSettings(fidelity="0.05")  # (text is read by parse_fidelity first)
    with pytest.raises(ValueError, match=re.escape("gap = -0.01 is outside the valid range")):
        ChainSettings(preset="standard", gap=-0.01, floor="felt")
    with pytest.raises(ValueError, match="preset = 'tiny' is not one of 'standard'"):
        ChainSettings(preset="tiny")


def test_the_numerics_are_the_keywords_of_a_chain():
    """``numerics`` gives the group ``numerics`` by name, from the settings and from a
    study's chain alike: what ``DominoChain`` takes besides the parameters."""
    assert numerics(ChainSettings(fidelity=0.05, sleep=False)) == {
        "fidelity": 0.05,
        "sleep": False,
    }
    study = ChainScenario(fidelity="exact", sleep=False, steps_per_collision=20)
    assert study.run_options() == {"steps_per_collision": 20, "fidelity": "exact", "sleep": False}


@pytest.mark.parametrize("name", list(parameter_specs(ChainSettings)))
def test_a_study_field_has_the_type_and_range_of_its_declaration(name):
    hints = typing.get_type_hints(ChainSettings)
    field, spec = parameter_specs(ChainSettings)[name]
    study = ChainScenario.model_fields[name]
    assert study.annotation == hints[name]
    assert (study.default, study.description) == (field.default, spec.doc)
    bounds = {
        k: getattr(m, k) for m in study.metadata for k in ("gt", "ge", "lt", "le") if hasattr(m, k)
    }
    assert bounds == spec.pydantic_constraints, name


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        ({"fidelity": "loose"}, "fidelity = 'loose' is not 'exact' or a tolerance in (0, 0.1]"),
        ({"fidelity": 0.5}, "fidelity = 0.5 is outside the valid range (0, 0.1]"),
        ({"gap": 0.01}, "gap and floor are the options of a preset: give preset too"),
    ],
)
def test_a_study_refuses_bad_settings_in_one_line(fields, message):
    with pytest.raises(ValidationError) as err:
        ChainScenario(**fields)
    assert message in str(err.value)
    assert err.value.error_count() == 1
