"""A chain study's ``sleep``: checked as a switch and given to ``DominoChain`` as the
command line's ``--sleep/--no-sleep`` is. Nothing is simulated."""

from __future__ import annotations

import pytest

from dominowave.io.config import parse_study
from dominowave.io.models import ChainScenario
from dominowave.sweep import run_chain


class Stop(Exception):
    pass


@pytest.fixture
def recorded(monkeypatch):
    """The keyword options the chain run of a study gives ``DominoChain``."""
    seen = {}

    class Recording:
        def __init__(self, params, **options):
            seen.update(options)
            raise Stop

    monkeypatch.setattr(run_chain, "DominoChain", Recording)
    return seen


@pytest.mark.parametrize("sleep", [True, False])
def test_sleep_reaches_the_chain_of_the_run(sleep, recorded):
    study = parse_study({"scenario": {"kind": "chain", "shape": "box", "sleep": sleep}})
    assert study.scenario.sleep is sleep
    assert study.scenario.run_options()["sleep"] is sleep
    with pytest.raises(Stop):
        run_chain.ChainScenarioStepper(study.scenario)
    assert recorded["sleep"] is sleep
    assert recorded["steps_per_collision"] is None and recorded["fidelity"] is None


def test_sleep_is_on_unless_set_and_is_part_of_the_config():
    assert ChainScenario().sleep is True
    assert ChainScenario(sleep=False).model_dump()["sleep"] is False
    from dominowave.sweep.hashing import point_key

    assert point_key(ChainScenario(sleep=False)) != point_key(ChainScenario())


@pytest.mark.parametrize("text", ['"no"', "0", "1.0"])
def test_sleep_that_is_not_a_switch_is_one_line_naming_it(text, tmp_path, cli):
    study = tmp_path / "study.toml"
    study.write_text(f'[scenario]\nkind = "chain"\nsleep = {text}\n')
    code, _, err = cli("config", study)
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "scenario.sleep" in lines[0], err


def test_the_example_study_lists_sleep(cli):
    code, out, _ = cli("config", "--example", "chain")
    assert code == 0
    assert "\nsleep = true\n" in out
