"""One vocabulary across scenario kinds: the theory and rods parameters (chain/params.py)."""

from __future__ import annotations

import math

import pytest

from dominowave.chain import ChainParams
from dominowave.chain.params import RodsParams, TheoryParams
from dominowave.io.config import parse_study
from dominowave.io.models import ChainScenario, RodsScenario, TheoryScenario
from dominowave.params import parameter_specs

SHARED = ("n_dominoes", "height", "thickness", "d_over_l", "g", "stiffness_ratio")


@pytest.mark.parametrize("model", [TheoryScenario, RodsScenario])
def test_every_kind_has_the_chains_default_domino(model):
    chain, cfg = ChainParams(), model()
    for name in ("n_dominoes", "height", "thickness", "d_over_l", "g", "mass"):
        assert getattr(cfg, name) == getattr(chain, name), name
    assert cfg.spacing == chain.spacing


@pytest.mark.parametrize(
    ("params", "model"), [(TheoryParams, TheoryScenario), (RodsParams, RodsScenario)]
)
def test_study_schema_is_derived_from_the_parameter_class(params, model):
    """Names, defaults, units and descriptions of the study fields are the parameter
    class's own; the study adds only how a run is driven."""
    specs = parameter_specs(params)
    for name, (field, spec) in specs.items():
        info = model.model_fields[name]
        assert info.default == field.default or (
            math.isinf(field.default) and math.isinf(info.default)
        )
        assert info.description == spec.doc
        assert info.json_schema_extra["unit"] == spec.unit
    run_fields = set(model.model_fields) - set(specs) - {"kind"}
    assert run_fields == {
        "push_omega",
        "n_frames" if model is TheoryScenario else "steps_per_contact",
    }


@pytest.mark.parametrize("model", [TheoryScenario, RodsScenario])
def test_shared_quantities_have_the_chains_names_and_units(model):
    chain = parameter_specs(ChainParams)
    for name in SHARED:
        assert name in model.model_fields, name
        unit = model.model_fields[name].json_schema_extra["unit"]
        assert unit == chain[name][1].unit, name
    assert "friction_floor" in ChainScenario.model_fields
    assert "friction_dominoes" in ChainScenario.model_fields


def test_parameter_class_checks_what_joins_fields():
    with pytest.raises(ValueError, match=r"thickness = 0\.05 m must be less than height"):
        TheoryParams(height=0.05, thickness=0.05)
    with pytest.raises(ValueError, match=r"d_over_l = 1 is outside the valid range \(0, 1\)"):
        RodsParams(d_over_l=1.0)
    with pytest.raises(ValueError, match="give exactly one of them"):
        TheoryParams(stiffness_ratio=10.0)  # the rigid default is still set
    assert TheoryParams(stiffness=None, stiffness_ratio=10.0).spacing == pytest.approx(0.02)
    with pytest.raises(ValueError, match=r"scenario\.friction_dominoes = 0\.2 needs normal"):
        parse_study({"scenario": {"kind": "rods", "normal": "head-on", "friction_dominoes": 0.2}})


@pytest.mark.parametrize(
    ("kind", "old", "new"),
    [
        ("theory", "spacing", "d_over_l"),
        ("theory", "gravity", "g"),
        ("theory", "friction", "friction_floor"),
        ("rods", "contact_friction", "friction_dominoes"),
        ("rods", "floor_restitution", "restitution_floor"),
    ],
)
def test_old_keys_are_refused_naming_the_new_one(kind, old, new):
    with pytest.raises(ValueError, match=rf"scenario\.{old} was renamed: write {new}\b"):
        parse_study({"scenario": {"kind": kind, old: 0.1}})
    with pytest.raises(ValueError, match=rf"sweep\.grid\.{old} was renamed: write {new}\b"):
        parse_study({"scenario": {"kind": kind}, "sweep": {"grid": {old: [0.1]}}})
