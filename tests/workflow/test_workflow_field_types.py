"""Every field of every study kind refuses a value of the wrong type in one line.

The line names the file, the line of the key and the key; never a traceback. Wrong
types are drawn by hypothesis: a quoted number, a list, a table, a boolean where a
number is due, a number where text is due.
"""

from __future__ import annotations

import tomllib
import typing

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dominowave.io.config import SCENARIO_MODELS, parse_study
from dominowave.io.toml_text import toml_value

FIELDS = [
    (kind, name, field)
    for kind, model in SCENARIO_MODELS.items()
    for name, field in model.model_fields.items()
    if name != "kind"
]
EXTRA = {  # the fields a preset needs beside it, so that the field under test is reached
    ("chain", "gap"): {"preset": "standard", "floor": "felt"},
    ("chain", "floor"): {"preset": "standard", "gap": 0.00938},
    ("chain", "preset"): {"gap": 0.00938, "floor": "felt"},
}


def _is_text(field) -> bool:
    args = typing.get_args(field.annotation) or (field.annotation,)
    return any(a is str or typing.get_origin(a) is typing.Literal for a in args)


def _is_bool(field) -> bool:
    return bool in (typing.get_args(field.annotation) or (field.annotation,))


def wrong_values(field):
    """Values whose TOML type is not the field's."""
    common = st.sampled_from([[0.01], {"a": 1}, [], [[1.0]]])
    if _is_bool(field):
        return st.one_of(common, st.floats(allow_nan=False), st.sampled_from(["yes", "true"]))
    if _is_text(field):
        return st.one_of(common, st.floats(allow_nan=False, allow_infinity=False), st.booleans())
    return st.one_of(
        common,
        st.floats(allow_nan=False, allow_infinity=False).map(str),
        st.booleans(),
        st.text("abcxyz_- ", min_size=1, max_size=5).filter(lambda s: not _numeric(s)),
    )


def _numeric(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


@pytest.mark.parametrize(("kind", "name", "field"), FIELDS, ids=[f"{k}.{n}" for k, n, _ in FIELDS])
@settings(max_examples=12, deadline=None)
@given(data=st.data())
def test_a_wrong_type_is_one_line_naming_file_line_and_key(kind, name, field, data):
    value = data.draw(wrong_values(field))
    scenario = {"kind": kind, **EXTRA.get((kind, name), {}), name: value}
    lines = ["[scenario]", *(f"{k} = {toml_value(v)}" for k, v in scenario.items())]
    text = "\n".join(lines) + "\n"
    line = lines.index(f"{name} = {toml_value(value)}") + 1
    with pytest.raises(ValueError) as info:
        parse_study(tomllib.loads(text), "study.toml", text)
    message = str(info.value)
    assert "\n" not in message.strip(), message
    assert message.startswith(f"study.toml:{line}: "), message
    assert name in message, message
