"""Documented parameters: one declaration checks the class and shapes the study schema."""

from __future__ import annotations

import dataclasses
import math
import re
import typing
from typing import Annotated, Literal

import pytest
from hypothesis import given
from hypothesis import strategies as st
from pydantic import TypeAdapter, ValidationError

from dominowave.chain import ChainParams
from dominowave.cli.declared import parameter_options
from dominowave.io.models import ChainScenario
from dominowave.params import (
    ParameterSpec,
    check_parameters,
    choice,
    parameter,
    parameter_specs,
    text,
)


@dataclasses.dataclass(frozen=True)
class Pendulum:
    length: float = parameter(1.0, "m", "length", gt=0, allow_inf=True)
    damping: float = parameter(0.0, "", "damping ratio", ge=0, lt=1)
    mode: str = parameter("small", "", "amplitude model", choices=("small", "large"))

    def __post_init__(self):
        check_parameters(self)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"length": 0.0}, "length = 0 is outside the valid range (0, inf]"),
        ({"damping": 1.0}, "damping = 1 is outside the valid range [0, 1)"),
        ({"damping": math.nan}, "damping = nan is outside the valid range [0, 1)"),
        ({"mode": "huge"}, "mode = 'huge' is not one of 'small', 'large'"),
    ],
)
def test_a_value_outside_its_declared_range_is_named_with_the_range(kwargs, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        Pendulum(**kwargs)


def test_bounds_and_infinity_as_declared():
    Pendulum(length=math.inf)  # allow_inf: a rigid limit is a valid value
    with pytest.raises(ValueError, match=r"\[0, 1\)"):
        Pendulum(damping=math.inf)
    with pytest.raises(TypeError, match="at most one lower"):
        parameter(1.0, "m", "x", gt=0, ge=0)


def test_the_chain_schema_is_the_chain_parameters():
    """Every ChainParams field is a study field of the same name, default, unit and doc."""
    specs = parameter_specs(ChainParams)
    assert set(specs) == {f.name for f in dataclasses.fields(ChainParams)}
    fields = ChainScenario.model_fields
    run_fields = {  # how the run is driven
        *("kind", "push_omega", "steps_per_collision", "fit_from", "fidelity", "sleep"),
        *("preset", "gap", "floor"),
    }
    assert set(fields) == {*specs, *run_fields}
    for name, (field, spec) in specs.items():
        info = fields[name]
        assert info.default == field.default, name
        assert info.description == spec.doc, name
        assert info.json_schema_extra == {"unit": spec.unit}, name


def test_the_default_study_is_the_default_chain():
    assert ChainScenario().params() == ChainParams()


FLOAT_FIELDS = [
    name
    for name, (_, spec) in parameter_specs(ChainParams).items()
    if ChainScenario.model_fields[name].annotation in (float, float | None)
]


@pytest.mark.parametrize("name", FLOAT_FIELDS)
@given(value=st.floats(-10.0, 10.0) | st.sampled_from([0.0, 1.0, math.inf, -math.inf, math.nan]))
def test_class_and_schema_accept_the_same_values(name, value):
    """A value the class refuses for its range, the study file refuses too (and back)."""
    spec: ParameterSpec = parameter_specs(ChainParams)[name][1]
    try:
        spec.check(name, value)
        class_ok = True
    except ValueError:
        class_ok = False
    info = ChainScenario.model_fields[name]
    field = TypeAdapter(Annotated[info.annotation, info], config=ChainScenario.model_config)
    try:
        field.validate_python(value)
        schema_ok = True
    except ValidationError:
        schema_ok = False
    assert class_ok == schema_ok, (name, value)


def test_a_choice_takes_its_values_and_default_from_its_literal_type():
    """``choice`` declares a categorical field from its Literal type: the values in their
    order, the first the default unless another is given, no unit; anything but a
    Literal is refused."""
    Mode = Literal["small", "large"]
    spec_field = choice(Mode, "amplitude model", group="model")
    spec = spec_field.metadata["parameter"]
    assert (spec_field.default, spec.choices, spec.unit, spec.group) == (
        "small",
        ("small", "large"),
        "",
        "model",
    )
    assert choice(Mode, "amplitude model", default=None).default is None
    with pytest.raises(TypeError, match="Literal"):
        choice(Mode | None, "amplitude model")


def test_a_text_is_not_set_by_default_and_left_to_its_reader():
    """``text`` declares a free text (a name, a path): not set by default and without a
    range, so that any text passes the class's check, while a number beside it is still
    checked; its reader checks what it means."""

    @dataclasses.dataclass(frozen=True)
    class Labelled:
        label: str | None = text("a name", group="output")
        tolerance: float | Literal["exact"] | None = text("a number or 'exact'")
        length: float = parameter(1.0, "m", "length", gt=0)

        def __post_init__(self):
            check_parameters(self)

    spec = text("a name", group="output").metadata["parameter"]
    assert (spec.text, spec.unit, spec.group) == (True, "", "output")
    assert Labelled().label is None
    assert Labelled(label="felt, or [0, 1)").label == "felt, or [0, 1)"
    with pytest.raises(ValueError, match=re.escape("length = -1 is outside")):
        Labelled(label="x", length=-1.0)
    assert not ParameterSpec("m", "length").text  # (a number is checked as before)
    options = {p.name: p for p in parameter_options(Labelled)}
    option = options["label"]
    assert typing.get_args(option.annotation)[0] == str | None
    # a number or a word is text on the command line, read by its reader
    assert typing.get_args(options["tolerance"].annotation)[0] == str | None
    assert option.annotation.__metadata__[0].help == "a name [not set by default]"
    with pytest.raises(ValueError, match="is not a number"):
        ParameterSpec("m", "length").check("length", "felt")
