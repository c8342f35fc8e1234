"""Study files: TOML validated by pydantic models, with one-line errors.

A study file has three tables::

    [scenario]            # what to simulate; ``kind`` selects the model
    kind = "theory"
    height = 0.05         # SI units everywhere (m, kg, s, N/m)
    d_over_l = 0.4
    ...
    [sweep]               # optional: a cartesian grid OR a listed set of points
    grid = { d_over_l = [0.2, 0.4], stiffness_ratio = [1.0, 1e4] }
    [output]              # optional
    dir = "results/my_study"

Every scenario kind has its pydantic model in the registry of kinds
(:data:`dominowave.io.kinds.KINDS`, read here through :data:`SCENARIO_MODELS`; the
package's own models are in :mod:`dominowave.io.models`). Everything is validated before anything
runs -- every sweep point too -- and the first problem is reported as one line
naming the file, the line, the key, the value and the valid range::

    study.toml:5: scenario.d_over_l = -0.4 is outside the valid range (0, 1)
"""

from __future__ import annotations

import itertools
import math
import re
import typing
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import annotated_types
from pydantic import BaseModel, Field, ValidationError, model_validator

from dominowave.checks import check_memory
from dominowave.io.kinds import SCENARIO_MODELS, register_scenario_model
from dominowave.io.schema import ScenarioModel, StrictModel, quantity
from dominowave.io.toml_text import dumps, line_of_key, loads_file

__all__ = [
    "SCENARIO_MODELS",
    "OutputSpec",
    "ScenarioModel",
    "Study",
    "SweepSpec",
    "example_toml",
    "load_study",
    "quantity",
    "register_scenario_model",
    "scenario_from_dict",
    "set_dotted",
]


class SweepSpec(StrictModel):
    """The points of a sweep: a cartesian ``grid`` or a listed set of ``points``.

    Keys are scenario fields (dotted for nested tables, e.g. ``"contact.stiffness"``);
    each point is the scenario with those fields replaced, validated before any runs.
    """

    grid: dict[str, list[Any]] | None = Field(
        None, description="field -> list of values; every combination is run"
    )
    points: list[dict[str, Any]] | None = Field(
        None, description="explicit list of points, each a table of field overrides"
    )

    @model_validator(mode="after")
    def _exactly_one(self):
        if (self.grid is None) == (self.points is None):
            raise ValueError("give exactly one of sweep.grid or sweep.points")
        if self.grid is not None:
            if not self.grid:
                raise ValueError("sweep.grid is empty: it needs at least one field")
            for key, values in self.grid.items():
                if not values:
                    raise ValueError(f"sweep.grid.{key} is an empty list: the sweep has no points")
        if self.points is not None and not self.points:
            raise ValueError("sweep.points is an empty list: the sweep has no points")
        return self

    def size(self) -> int:
        """The number of points, counted without building them."""
        if self.points is not None:
            return len(self.points)
        return math.prod(len(values) for values in self.grid.values())

    def overrides(self) -> list[dict[str, Any]]:
        """The list of per-point overrides, in a deterministic order."""
        if self.points is not None:
            return [dict(p) for p in self.points]
        keys = list(self.grid)
        return [
            dict(zip(keys, combo, strict=True)) for combo in itertools.product(*self.grid.values())
        ]


BYTES_PER_POINT = 25_000
"""Memory of one validated sweep point and its bookkeeping [bytes] (measured: 22 kB a
point of a prediction, tracemalloc's peak over 2048 points)."""


class OutputSpec(StrictModel):
    """Where and what to write."""

    dir: str = Field("results", description="output folder (relative to the current directory)")
    trajectory: bool = Field(
        True, description="keep the per-frame domino angles (needed by `dominowave animate`)"
    )


@dataclass(frozen=True)
class Study:
    """A validated study: the base scenario, its sweep points, output options.

    ``points`` holds one validated scenario model per sweep point (just the base
    scenario for a single run); ``overrides`` the swept values of each point.
    """

    path: Path | None
    scenario: ScenarioModel
    points: tuple[ScenarioModel, ...]
    overrides: tuple[dict[str, Any], ...]
    sweep: SweepSpec | None
    output: OutputSpec

    def swept_keys(self) -> list[str]:
        keys: list[str] = []
        for o in self.overrides:
            keys.extend(k for k in o if k not in keys)
        return keys


class _StudyFile(StrictModel):
    scenario: dict[str, Any]
    sweep: dict[str, Any] | None = None
    output: dict[str, Any] | None = None


def set_dotted(data: dict, dotted: str, value: Any) -> dict:
    """Copy of nested dict ``data`` with ``data[a][b] = value`` for ``dotted = "a.b"``."""
    head, _, rest = dotted.partition(".")
    out = dict(data)
    if rest:
        sub = out.get(head, {})
        out[head] = set_dotted(sub if isinstance(sub, dict) else {}, rest, value)
    else:
        out[head] = value
    return out


# --------------------------------------------------------------------------- errors


def _field_info(model: type[BaseModel] | None, loc: tuple):
    """The pydantic FieldInfo at ``loc`` inside ``model`` (None if not a model field)."""
    info = None
    for part in loc:
        if model is None or not isinstance(part, str) or part not in model.model_fields:
            return None
        info = model.model_fields[part]
        ann = info.annotation
        model = ann if isinstance(ann, type) and issubclass(ann, BaseModel) else None
    return info


def _fmt(x: float) -> str:
    return f"{x:.6g}"


def _range_text(info) -> str:
    """``(0, inf) m`` from a field's bounds and unit; ``""`` for an unbounded field."""
    if info is None:
        return ""
    lo, hi, lo_in, hi_in = -math.inf, math.inf, False, False
    for m in info.metadata:
        if isinstance(m, annotated_types.Gt):
            lo = m.gt
        elif isinstance(m, annotated_types.Ge):
            lo, lo_in = m.ge, True
        elif isinstance(m, annotated_types.Lt):
            hi = m.lt
        elif isinstance(m, annotated_types.Le):
            hi, hi_in = m.le, True
    unit = (info.json_schema_extra or {}).get("unit", "") if info.json_schema_extra else ""
    if lo == -math.inf and hi == math.inf:
        return unit
    text = f"{'[' if lo_in else '('}{_fmt(lo)}, {_fmt(hi)}{']' if hi_in else ')'}"
    return f"{text} {unit}".rstrip()


def _type_name(info) -> str:
    if info is None:
        return "value"
    ann = info.annotation
    names = {float: "a number", int: "an integer", bool: "true or false", str: "a string"}
    return names.get(ann, getattr(ann, "__name__", str(ann)))


def _describe(err: dict, model: type[BaseModel] | None, prefix: str) -> tuple[str, str]:
    """(dotted key, message) for one pydantic error dict."""
    loc = tuple(err["loc"])
    key = ".".join(str(p) for p in (prefix, *loc) if p != "")
    info = _field_info(model, loc)
    value = err.get("input")
    kind = err["type"]
    if kind == "extra_forbidden":
        renamed = getattr(model, "RENAMED", {}).get(loc[-1]) if len(loc) == 1 else None
        if renamed:
            return key, f"{key} was renamed: write {renamed}"
        valid = sorted(model.model_fields) if model is not None else []
        parent = _field_info(model, loc[:-1]) if len(loc) > 1 else None
        if parent is not None and isinstance(parent.annotation, type):
            if issubclass(parent.annotation, BaseModel):
                valid = sorted(parent.annotation.model_fields)
        hint = f" (valid keys: {', '.join(valid)})" if valid and len(loc) == 1 else ""
        return key, f"unknown key {key}{hint}"
    if kind == "missing":
        return key, f"{key} is required"
    rng = _range_text(info)
    if kind in {"greater_than", "greater_than_equal", "less_than", "less_than_equal"}:
        return key, f"{key} = {value!r} is outside the valid range {rng}"
    if kind == "finite_number":
        return key, f"{key} = {value!r} is not a finite number (valid range {rng})"
    if kind.endswith("_type") or kind.endswith("_parsing"):
        unit = (
            (info.json_schema_extra or {}).get("unit") if info and info.json_schema_extra else None
        )
        if isinstance(value, str) and unit:
            why = f"is not {_type_name(info)}: write the value in SI units ({unit}) as a number"
        else:
            why = f"is not {_type_name(info)}" + (f" (valid range {rng})" if rng else "")
        return key, f"{key} = {value!r} {why}"
    if kind in {"literal_error", "enum"}:
        choices = typing.get_args(info.annotation) if info is not None else ()
        values = [c for a in choices for c in (typing.get_args(a) or (a,)) if a is not type(None)]
        valid = ", ".join(repr(c) for c in values) or err["msg"]
        return key, f"{key} = {value!r} is not one of {valid}"
    msg = err["msg"].removeprefix("Value error, ")
    if not loc:  # a model validator: its message starts with the field it is about
        field = re.match(r"(\w+) = ", msg)
        if field and prefix:
            return f"{prefix}.{field.group(1)}", f"{prefix}.{msg}"
        return key, msg
    return key, (f"{key} = {value!r}: {msg}" if not isinstance(value, dict) else msg)


def _raise_validation(
    exc: ValidationError,
    model,
    prefix: str,
    path: Path | None,
    text: str,
    where: str = "",
    line_key: str | None = None,
):
    # a misspelt key also makes the intended key "missing": report the misspelling
    errors = sorted(exc.errors(), key=lambda e: e["type"] != "extra_forbidden")
    key, msg = _describe(errors[0], model, prefix)
    line = line_of_key(text, line_key or key) if text else None
    loc = f"{path}:{line}" if (path and line) else (str(path) if path else "<study>")
    more = f" (and {len(errors) - 1} more)" if len(errors) > 1 else ""
    raise ValueError(f"{loc}: {where}{msg}{more}") from None


# --------------------------------------------------------------------------- loading


def parse_study(data: dict, path: Path | None = None, text: str = "") -> Study:
    """Validate the parsed TOML ``data`` of a study; raise one-line ``ValueError``."""
    if not isinstance(data, dict):
        raise ValueError(f"{path or '<study>'}: a study must be a table")
    try:
        raw = _StudyFile.model_validate(data)
    except ValidationError as exc:
        _raise_validation(exc, _StudyFile, "", path, text)
    kind = raw.scenario.get("kind")
    where = f"{path or '<study>'}"
    if kind not in SCENARIO_MODELS:
        line = line_of_key(text, "scenario.kind") if text else None
        loc = f"{where}:{line}" if line else where
        known = ", ".join(sorted(SCENARIO_MODELS))
        shown = "missing" if kind is None else f"{kind!r}"
        raise ValueError(f"{loc}: scenario.kind = {shown} is not one of: {known}")
    model = SCENARIO_MODELS[kind]
    try:
        scenario = model.model_validate(raw.scenario)
    except ValidationError as exc:
        _raise_validation(exc, model, "scenario", path, text)
    output = OutputSpec()
    if raw.output is not None:
        try:
            output = OutputSpec.model_validate(raw.output)
        except ValidationError as exc:
            _raise_validation(exc, OutputSpec, "output", path, text)
    sweep = None
    overrides: list[dict[str, Any]] = [{}]
    points: list[ScenarioModel] = [scenario]
    if raw.sweep is not None:
        try:
            sweep = SweepSpec.model_validate(raw.sweep)
        except ValidationError as exc:
            _raise_validation(exc, SweepSpec, "sweep", path, text)
        check_memory(
            BYTES_PER_POINT * sweep.size(),
            f"the {sweep.size()} points of its sweep",
            f"{path or '<study>'}: sweep of {sweep.size()} points",
        )
        overrides = sweep.overrides()
        points = [
            _point(raw.scenario, model, o, i, sweep, path, text) for i, o in enumerate(overrides)
        ]
    return Study(path, scenario, tuple(points), tuple(overrides), sweep, output)


def _point(base: dict, model, override, index, sweep, path, text) -> ScenarioModel:
    """Validate sweep point ``index``: the scenario table of the file with ``override`` applied.

    Overrides go into the table as written (not into the resolved model), so a swept
    field is "given" exactly as if it were written in the file.
    """
    data = dict(base)
    for key, value in override.items():
        if key == "kind":
            raise ValueError(f"{path or '<study>'}: sweep cannot change scenario.kind")
        head = key.split(".")[0]
        if head not in model.model_fields:
            table = "grid" if sweep.grid is not None else f"points[{index}]"
            line = line_of_key(text, f"sweep.{table.split('[')[0]}.{key}") if text else None
            loc = f"{path}:{line}" if (path and line) else str(path or "<study>")
            if head in model.RENAMED:
                new = model.RENAMED[head]
                raise ValueError(f"{loc}: sweep.{table}.{key} was renamed: write {new}")
            valid = ", ".join(k for k in model.model_fields if k != "kind")
            raise ValueError(f"{loc}: sweep.{table}.{key} is not a scenario field (valid: {valid})")
        for other in _alternatives(model, key):  # a swept field replaces its alternatives
            data.pop(other, None)
        data = set_dotted(data, key, value)
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        label = ", ".join(f"{k}={v!r}" for k, v in override.items())
        table = f"grid.{next(iter(override))}" if sweep.grid is not None else "points"
        _raise_validation(
            exc,
            model,
            "scenario",
            path,
            text,
            where=f"sweep point {index} ({label}): ",
            line_key=f"sweep.{table}",
        )


def scenario_from_dict(data: dict, where: str = "<config>") -> ScenarioModel:
    """Validate a resolved scenario table (e.g. a result folder's config.toml)."""
    model = SCENARIO_MODELS.get(data.get("kind"))
    if model is None:
        raise ValueError(f"{where}: unknown scenario kind {data.get('kind')!r}")
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        _raise_validation(exc, model, "scenario", Path(where), "")


def _alternatives(model, key: str) -> list[str]:
    """Fields that ``key`` replaces (``model.ALTERNATIVES``: groups of exclusive fields)."""
    for group in getattr(model, "ALTERNATIVES", ()):
        if key in group:
            return [k for k in group if k != key]
    return []


def load_study(path: str | Path) -> Study:
    """Read and validate the study file ``path`` (see the module docstring)."""
    path = Path(path)
    data, text = loads_file(path)
    return parse_study(data, path, text)


# --------------------------------------------------------------------------- examples


def _comments(model: type[BaseModel], prefix: str) -> dict[str, str]:
    out = {}
    for name, info in model.model_fields.items():
        rng = _range_text(info)
        doc = info.description or ""
        out[f"{prefix}.{name}"] = f"{doc}" + (f"  [{rng}]" if rng else "")
    return out


def example_toml(name: str) -> str:
    """A complete, commented study file with every field at its default.

    ``name`` is a scenario kind (single run) or ``"sweep"`` (a theory sweep over
    the spacing ratio d/l and the stiffness).
    """
    kind = "theory" if name == "sweep" else name
    if kind not in SCENARIO_MODELS:
        choices = ", ".join([*sorted(SCENARIO_MODELS), "sweep"])
        raise ValueError(f"example = {name!r} is not one of: {choices}")
    model = SCENARIO_MODELS[kind]
    scenario = model().model_dump()
    data: dict[str, Any] = {"scenario": scenario}
    comments = _comments(model, "scenario")
    comments["scenario"] = (model.__doc__ or "").strip().splitlines()[0]
    if name == "sweep":
        data["sweep"] = {"grid": model.example_grid()}
        comments["sweep"] = "Cartesian product of the listed values (or: points = [{...}, {...}])."
    data["output"] = OutputSpec().model_dump()
    comments.update(_comments(OutputSpec, "output"))
    return dumps(data, comments)
