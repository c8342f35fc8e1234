"""Documented physical parameters: declared once, checked when set, read by the schema.

A scenario's parameter class (e.g. :class:`dominowave.chain.ChainParams`) declares each
field with :func:`parameter`: its default, SI unit, one-line description and valid
range (or, with :func:`choice`, the values of a categorical field, from its ``Literal``
type; with :func:`text`, a free text that its reader checks). That one declaration is

* checked when an instance is made (:func:`check_parameters`, the same one-line errors
  as :mod:`dominowave.checks`: name, value, valid range), and
* read by :mod:`dominowave.io` to derive the study-file schema, so that the names,
  defaults, units and ranges of a study can never drift from the scenario's own, and
* read by :mod:`dominowave.cli` to derive a command's options (``dominowave chain``),
  grouped in its help by each parameter's declared concern (``group``).

Cross-field rules (e.g. a thickness below half the height) stay in the class.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal, get_args, get_origin

from dominowave.checks import check_in_range

__all__ = [
    "ParameterSpec",
    "check_parameters",
    "choice",
    "parameter",
    "parameter_specs",
    "text",
]


@dataclass(frozen=True)
class ParameterSpec:
    """What is known of one parameter besides its type.

    ``gt``/``ge`` and ``lt``/``le`` are the exclusive/inclusive bounds (at most one of
    each pair); ``allow_inf`` lets an unbounded side reach infinity (e.g. a rigid
    stiffness); ``choices`` lists the values of a categorical field; ``group`` names the
    concern the parameter belongs to (e.g. the domino's shape, the contact law), by which
    the command line groups its options; ``text`` marks a free text (a name, a path)
    that whoever reads it checks (:func:`text`).
    """

    unit: str
    doc: str
    gt: float | None = None
    ge: float | None = None
    lt: float | None = None
    le: float | None = None
    allow_inf: bool = False
    choices: tuple | None = None
    group: str = ""
    text: bool = False

    def check(self, name: str, value) -> None:
        """Raise ``ValueError`` naming ``name``, ``value`` and the valid range or choices."""
        if value is None or self.text:
            return
        if self.choices is not None:
            if value not in self.choices:
                listed = ", ".join(repr(c) for c in self.choices)
                raise ValueError(f"{name} = {value!r} is not one of {listed}")
            return
        if isinstance(value, bool):
            return
        lo = self.ge if self.ge is not None else self.gt
        hi = self.le if self.le is not None else self.lt
        check_in_range(
            name,
            value,
            -math.inf if lo is None else lo,
            math.inf if hi is None else hi,
            lo_inclusive=self.ge is not None or (lo is None and self.allow_inf),
            hi_inclusive=self.le is not None or (hi is None and self.allow_inf),
        )

    @property
    def pydantic_constraints(self) -> dict[str, Any]:
        """The bounds as keyword arguments of ``pydantic.Field``."""
        out = {
            k: getattr(self, k) for k in ("gt", "ge", "lt", "le") if getattr(self, k) is not None
        }
        if self.allow_inf:
            out["allow_inf_nan"] = True
        return out


def parameter(
    default: Any,
    unit: str,
    doc: str,
    *,
    gt: float | None = None,
    ge: float | None = None,
    lt: float | None = None,
    le: float | None = None,
    allow_inf: bool = False,
    choices: Sequence | None = None,
    group: str = "",
) -> Any:
    """A dataclass field carrying its :class:`ParameterSpec` (unit, description, range,
    concern)."""
    if (gt is not None and ge is not None) or (lt is not None and le is not None):
        raise TypeError("give at most one lower (gt/ge) and one upper (lt/le) bound")
    spec = ParameterSpec(
        unit, doc, gt, ge, lt, le, allow_inf, None if choices is None else tuple(choices), group
    )
    return dataclasses.field(default=default, metadata={"parameter": spec})


_FIRST = object()
"""The default of :func:`choice`: the first of the choices."""


def choice(kind, doc: str, *, default: Any = _FIRST, group: str = "") -> Any:
    """A :func:`parameter` that takes one of the values of ``kind`` (a ``typing.Literal``,
    the field's type), without a unit; its default the first of them, or ``default``
    (None: not set)."""
    if get_origin(kind) is not Literal:
        raise TypeError(f"choice needs a typing.Literal of the values, not {kind!r}")
    values = get_args(kind)
    default = values[0] if default is _FIRST else default
    return parameter(default, "", doc, choices=values, group=group)


def text(doc: str, *, group: str = "") -> Any:
    """A :func:`parameter` whose value is free text (a name, a path, a number or a word),
    not set by default: it has no range here, and whoever reads it checks it and names it
    in its error (e.g. ``chain.fidelity.parse_fidelity``)."""
    spec = ParameterSpec("", doc, group=group, text=True)
    return dataclasses.field(default=None, metadata={"parameter": spec})


def parameter_specs(cls) -> dict[str, tuple[dataclasses.Field, ParameterSpec]]:
    """``name -> (field, spec)`` of every documented parameter of dataclass ``cls``."""
    return {
        f.name: (f, f.metadata["parameter"])
        for f in dataclasses.fields(cls)
        if "parameter" in f.metadata
    }


def check_parameters(obj) -> None:
    """Check every documented parameter of the dataclass instance ``obj``, in field order."""
    for name, (_, spec) in parameter_specs(type(obj)).items():
        spec.check(name, getattr(obj, name))
