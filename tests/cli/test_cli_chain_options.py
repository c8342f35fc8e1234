"""``dominowave chain``: its options come from the parameter declarations.

Each declared field of :class:`~dominowave.chain.ChainParams` and of the command's own
:class:`~dominowave.cli.chain.RunOptions` (numerics, preset, push, ensemble, output) is
an option, shown in ``--help`` at 80 columns with its description, unit and default, in
the panel of its concern; a value given reaches ``ChainParams`` or the run; bad input is
one line naming the parameter. Nothing is simulated: ``DominoChain`` is replaced by one
that records what it is given and stops the command.
"""

from __future__ import annotations

import dataclasses
import re

import pytest
import typer
from typer.testing import CliRunner

from dominowave.chain import ChainParams
from dominowave.chain.fidelity import DEFAULT_TOLERANCE
from dominowave.chain.presets import standard_domino
from dominowave.cli import app
from dominowave.cli import chain as chain_cli
from dominowave.params import parameter_specs

SPECS = parameter_specs(ChainParams)
RUN_SPECS = parameter_specs(chain_cli.RunOptions)
EVERY_SPEC = SPECS | RUN_SPECS
COMMAND = typer.main.get_command(app).commands["chain"]
RENAMED = {
    "n_dominoes": "--n",
    "lateral_asymmetry": "--asymmetry",
    "asymmetry_seed": "--placement-seed",
}
"""The options whose name is not the field's (as the command line has always named them)."""


def flag(name: str) -> str:
    return RENAMED.get(name, "--" + name.replace("_", "-"))


def expected_help(name: str) -> str:
    """The field's description with its unit and default, as ``--help`` must show it."""
    field, spec = EVERY_SPEC[name]
    parts = [spec.unit] if spec.unit else []
    default = field.default
    if isinstance(default, bool):
        parts.append(f"default {flag(name)}" if default else f"default --no-{flag(name)[2:]}")
    elif isinstance(default, float):
        parts.append(f"default {default:g}")
    elif default is not None:
        parts.append(f"default {default}")
    elif "not set" not in spec.doc:
        parts.append("not set by default")
    return spec.doc + (f" [{'; '.join(parts)}]" if parts else "")


def flat(text: str) -> str:
    """The help without the panels' frames and line breaks (rich wraps at 80 columns)."""
    return " ".join(re.sub("[│╭╮╰╯─]", " ", text).split())


@pytest.fixture(scope="module")
def help_80():
    result = CliRunner().invoke(app, ["chain", "--help"], env={"COLUMNS": "80"}, terminal_width=80)
    assert result.exit_code == 0, result.output
    return result.output


def panels(text: str) -> dict[str, str]:
    """Panel title -> its text."""
    parts = re.split(r"╭─ (.+?) ─+╮", text)
    return {title: body for title, body in zip(parts[1::2], parts[2::2], strict=True)}


def test_every_declared_field_is_an_option_of_its_name():
    options = {p.name: p for p in COMMAND.params}
    assert len(SPECS) >= 30 and len(RUN_SPECS) >= 14
    assert set(options) == set(EVERY_SPEC)  # (no option written by hand)
    for name in EVERY_SPEC:
        assert name in options, f"the declared field {name} is not an option of chain"
        assert options[name].opts[0] == flag(name), name
        assert options[name].default is None, name  # not given: ChainParams' default


@pytest.mark.parametrize("name", list(EVERY_SPEC))
def test_help_at_80_columns_shows_description_unit_and_default(name, help_80):
    field, spec = EVERY_SPEC[name]
    shown = flat(help_80)
    assert expected_help(name) in shown, f"{flag(name)}: {expected_help(name)!r} not shown"
    if spec.unit:
        assert f"[{spec.unit}" in shown
    if field.default is not None:
        assert "default " in expected_help(name)


def test_help_fits_80_columns_with_one_panel_per_concern(help_80):
    assert max(len(line) for line in help_80.splitlines()) <= 80
    shown = panels(help_80)
    for name, (_, spec) in EVERY_SPEC.items():
        title = chain_cli.PANELS.get(spec.group, spec.group.capitalize())
        assert re.search(rf"(?<![\w-]){re.escape(flag(name))}(?![\w-])", shown[title]), (
            f"{flag(name)} is not in the panel {title!r}"
        )
    for title in ("Push", "Ensemble", "Preset", "Numerics", "Output"):  # RunOptions'
        assert title in shown
    assert "--sleep" in shown["Numerics"] and "--no-sleep" in shown["Numerics"]


def test_brackets_of_the_units_and_defaults_are_shown(help_80):
    shown = flat(help_80)
    default = f"the softest contact within it (not set: {DEFAULT_TOLERANCE:g};"
    for text in ("push as impulse (not set: --push) [N s]", "between neighbours [m;", default):
        assert text in shown


class Stop(Exception):
    """Raised by the recording DominoChain: the command got as far as building the chain."""


@pytest.fixture
def built(monkeypatch):
    """``run(*args) -> (params, options)`` that ``chain`` gives ``DominoChain``."""
    seen = {}

    class Recording:
        def __init__(self, params, **options):
            seen["params"], seen["options"] = params, options
            raise Stop

    monkeypatch.setattr(chain_cli, "DominoChain", Recording)

    def run(*args):
        result = CliRunner().invoke(app, ["chain", *map(str, args)])
        assert isinstance(result.exception, Stop), result.output
        return seen["params"], seen["options"]

    return run


# (arguments, the ChainParams fields they set): together every declared field
GIVEN = [
    (
        ["--n", 7, "--d-over-l", 0.5, "--height", 0.06, "--thickness", 0.006, "--width", 0.03],
        {"n_dominoes": 7, "d_over_l": 0.5, "height": 0.06, "thickness": 0.006, "width": 0.03},
    ),
    (
        ["--density", 900, "--spheres-per-column", 12, "--base", "two", "--model", "3d"],
        {"density": 900.0, "spheres_per_column": 12, "base": "two", "model": "3d"},
    ),
    (
        ["--stiffness-ratio", 1e3, "--kt-ratio", 0.5, "--shear-kinematics", "yade"],
        {"stiffness_ratio": 1e3, "kt_ratio": 0.5, "shear_kinematics": "yade"},
    ),
    (
        ["--friction-dominoes", 0.1, "--friction-floor", 0.4, "--damping", 0.1, "--no-held"],
        {"friction_dominoes": 0.1, "friction_floor": 0.4, "damping": 0.1, "held": False},
    ),
    (["--kn", 50.0, "--restitution", 0.9, "--g", 9.7], {"kn": 50.0, "restitution": 0.9, "g": 9.7}),
    (["--young", 1e9, "--young-rule", "yade"], {"young": 1e9, "young_rule": "yade"}),
    (
        ["--model", "3d", "--asymmetry", 0.01, "--placement-along", 1e-4],
        {"model": "3d", "lateral_asymmetry": 0.01, "placement_along": 1e-4},
    ),
    (
        ["--model", "3d", "--placement-across", 1e-4, "--push-error", 0.01, "--placement-seed", 3],
        {"model": "3d", "placement_across": 1e-4, "push_error": 0.01, "asymmetry_seed": 3},
    ),
    (
        ["--shape", "box", "--rounding", 1e-4, "--young", 1e9, "--normal-law", "hertz"],
        {"shape": "box", "rounding": 1e-4, "young": 1e9, "normal_law": "hertz"},
    ),
    (
        ["--shape", "box", "--young", 1e9, "--normal-law", "hertz", "--poisson", 0.25],
        {"shape": "box", "young": 1e9, "normal_law": "hertz", "poisson": 0.25},
    ),
    (
        ["--shape", "box", "--restitution-dominoes", 0.8, "--restitution-floor", 0.7],
        {"shape": "box", "restitution_dominoes": 0.8, "restitution_floor": 0.7},
    ),
]


def test_the_cases_give_every_declared_field():
    given = {name for _, fields in GIVEN for name in fields}
    missing = set(SPECS) - given
    assert not missing, f"give these new ChainParams fields a value in GIVEN: {missing}"


@pytest.mark.parametrize(("args", "fields"), GIVEN, ids=lambda v: None)
def test_a_value_given_reaches_chain_params(args, fields, built):
    params, _ = built(*args)
    for name, value in fields.items():
        assert getattr(params, name) == value, name
    untouched = {f.name for f in dataclasses.fields(ChainParams)} - set(fields)
    for name in untouched - {"stiffness_ratio"}:  # (a stiffness given unsets the others')
        assert getattr(params, name) == getattr(ChainParams(), name), name


def test_run_options_reach_the_run(built, monkeypatch):
    seen = {}

    class Recording:
        def __init__(self, params, **options):
            seen["params"], seen["options"] = params, options

        def ensemble(self, push, **options):
            seen["push"], seen["ensemble"] = push, options
            raise Stop

    monkeypatch.setattr(chain_cli, "DominoChain", Recording)
    args = ["--members", "3", "--seed", "4", "--jitter", "0.01", "--vary-placement"]
    args += ["--impulse", "2e-3", "--impulse-height", "0.04", "--fit-from", "2"]
    result = CliRunner().invoke(app, ["chain", "--no-sleep", *args])
    assert isinstance(result.exception, Stop), result.output
    assert seen["options"] == {"fidelity": None, "sleep": False}
    assert (seen["push"].impulse, seen["push"].height) == (2e-3, 0.04)
    assert seen["ensemble"] == {
        "members": 3,
        "seed": 4,
        "jitter": 0.01,
        "fit_from": 2,
        "vary_placement": True,
    }


def test_a_single_run_takes_the_push_in_sqrt_g_over_l_the_fidelity_and_the_folder(
    monkeypatch, tmp_path
):
    seen = {}

    class Recording:
        def __init__(self, params, **options):
            seen["params"], seen["options"] = params, options

        def run(self, push):
            seen["push"] = push
            raise Stop

    monkeypatch.setattr(chain_cli, "DominoChain", Recording)
    out = tmp_path / "new" / "out"
    args = ["--height", 0.04, "--g", 9.0, "--push", 2.0, "--fidelity", 0.05]
    result = CliRunner().invoke(app, ["chain", *map(str, args), "--out", str(out)])
    assert isinstance(result.exception, Stop), result.output
    assert seen["push"].omega == 2.0 * (9.0 / 0.04) ** 0.5 and seen["push"].impulse is None
    assert seen["options"] == {"fidelity": 0.05, "sleep": True}
    assert out.is_dir()  # (made, and checked writable, before the run)


def test_no_option_given_is_the_default_chain_awake_or_asleep(built):
    params, options = built()
    assert params == ChainParams()
    assert options["sleep"] is True
    _, options = built("--no-sleep")
    assert options["sleep"] is False
    _, options = built("--sleep", "--shape", "box")
    assert options["sleep"] is True


def test_a_preset_takes_the_other_fields_given(built):
    params, _ = built("--preset", "standard", "--gap", 0.01, "--floor", "felt", "--n", 5)
    assert params == standard_domino(gap=0.01, floor="felt", n_dominoes=5)
    assert params.model == "3d"
    params, _ = built(
        "--preset", "standard", "--gap", 0.01, "--floor", "felt", "--model", "2d", "--damping", 0.2
    )
    assert params == standard_domino(gap=0.01, floor="felt", model="2d", damping=0.2)


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["--height", "-0.05"], "--height = -0.05 is outside the valid range (0, inf)"),
        (["--g", "0"], "--g = 0 is outside the valid range (0, inf)"),
        (["--n", "1"], "--n = 1 is outside the valid range [2, 100000]"),
        (["--kt-ratio", "0"], "--kt-ratio = 0 is outside the valid range (0, inf]"),
        (["--placement-seed", "-2"], "--placement-seed = -2 is outside the valid range [0, inf)"),
        (["--model", "4d"], "--model = '4d' is not one of '2d', '3d'"),
        (["--base", "three"], "--base = 'three' is not one of 'one', 'two'"),
        (["--density", "heavy"], "Invalid value for '--density'"),
        (["--members", "0"], "--members = 0 is outside the valid range [1, inf)"),
        (["--seed", "-1"], "--seed = -1 is outside the valid range [0, inf)"),
        (["--impulse", "0"], "--impulse = 0 is outside the valid range (0, inf)"),
        (["--fit-from", "-1"], "--fit-from = -1 is outside [1, 28]"),
        (["--jitter", "-1"], "--jitter = -1 is outside the valid range [0, inf)"),
        (["--push", "0"], "--push = 0 is outside the valid range (0, inf)"),
        (["--preset", "tiny"], "--preset = 'tiny' is not one of 'standard'"),
        (["--gap", "0.01", "--floor", "felt"], "--gap and --floor need --preset standard"),
        (["--fidelity", "loose"], "--fidelity 'loose' is not 'exact' or a tolerance"),
        (
            ["--preset", "standard", "--gap", "0.01", "--floor", "felt", "--height", "0.05"],
            "--height: set by --preset standard from materials.toml, give not both",
        ),
        (
            ["--preset", "standard", "--gap", "0.01", "--floor", "felt", "--kn", "10", "--n", "4"],
            "--kn: set by --preset standard",
        ),
    ],
    ids=lambda v: "_".join(v) if isinstance(v, list) else None,
)
def test_bad_input_is_one_line_naming_the_parameter(args, fragment, cli):
    code, out, err = cli("chain", *args)
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("dominowave: error: "), err
    assert fragment in lines[0], lines[0]
    assert out == ""


def test_the_preset_and_numerics_are_those_of_a_study_file(help_80):
    """``--preset``, ``--gap``, ``--floor``, ``--fidelity`` and ``--sleep`` and the study
    file's fields of the same names come from one declaration (``ChainSettings``): the
    same description, default and unit in both."""
    from dominowave.chain.settings import ChainSettings
    from dominowave.io.models import ChainScenario

    settings = parameter_specs(ChainSettings)
    assert set(settings) == {"preset", "gap", "floor", "fidelity", "sleep"}
    for name, (field, spec) in settings.items():
        study = ChainScenario.model_fields[name]
        assert (study.description, study.default) == (spec.doc, field.default), name
        assert study.json_schema_extra == {"unit": spec.unit}, name
        assert RUN_SPECS[name][1] == spec, name
        assert expected_help(name) in flat(help_80), name


def test_an_error_names_the_options_of_the_fields_it_names():
    """Each ``field = value`` of a declared field reads ``--option = value``; a renamed
    field takes its option's name, other names and messages stay as they are."""
    from dominowave.cli.declared import option_error

    exc = ValueError("n_dominoes = 1 needs shape = 'box' (k_n = 3, pre_shape = 1)")
    named = option_error(exc, {"n_dominoes", "shape"}, {"n_dominoes": "n"})
    assert str(named) == "--n = 1 needs --shape = 'box' (k_n = 3, pre_shape = 1)"
    plain = ValueError("--gap and --floor need --preset standard")
    assert option_error(plain, {"gap", "floor"}) is plain
