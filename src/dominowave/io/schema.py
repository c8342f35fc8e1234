"""The building blocks of scenario models: a strict pydantic base and documented physical
fields, derived from a scenario's parameter class.

Each scenario kind declares its model with these (:mod:`dominowave.io.models`); the
registry of kinds is :mod:`dominowave.io.kinds`, against which :mod:`dominowave.io.config`
reads study files. (Kept apart from both so that neither imports the other back.)
"""

from __future__ import annotations

import typing
from typing import Any, ClassVar

from pydantic import BaseModel, ConfigDict, Field

from dominowave.params import parameter_specs

__all__ = ["ScenarioModel", "StrictModel", "fields_from_parameters", "quantity"]


class StrictModel(BaseModel):
    """Base of every config model: unknown keys and implicit conversions are errors.

    ``strict`` refuses ``"0.05"`` for a float and ``true`` for a number; ints are
    accepted for floats. NaN and infinities are refused unless a field allows them.
    """

    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False, frozen=True)


class ScenarioModel(StrictModel):
    """Base of scenario models; ``kind`` is the key in :data:`dominowave.io.kinds.KINDS`.

    ``RENAMED`` maps the keys a kind no longer has to the key that replaced them: a study
    file that still writes one is refused with an error naming the new key.
    """

    kind: str
    RENAMED: ClassVar[dict[str, str]] = {}


def quantity(default: Any, unit: str, doc: str, **constraints) -> Any:
    """A documented physical field: ``default``, ``unit`` (SI), description, bounds.

    ``constraints`` are pydantic's ``gt``, ``ge``, ``lt``, ``le`` and
    ``allow_inf_nan``. The unit is kept in the schema so that error messages and
    ``dominowave config --example`` can print it.
    """
    return Field(default, description=doc, json_schema_extra={"unit": unit}, **constraints)


def fields_from_parameters(params_cls) -> dict[str, tuple[Any, Any]]:
    """Pydantic field definitions ``name -> (type, Field)`` of a parameter dataclass.

    ``params_cls`` declares its fields with :func:`dominowave.params.parameter`; each
    becomes a :func:`quantity` of the same name, type, default, unit, description and
    bounds, so a study file is checked against the scenario's own declaration.
    """
    hints = typing.get_type_hints(params_cls)
    out = {}
    for name, (field, spec) in parameter_specs(params_cls).items():
        out[name] = (
            hints[name],
            quantity(field.default, spec.unit, spec.doc, **spec.pydantic_constraints),
        )
    return out
