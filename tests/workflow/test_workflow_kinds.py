"""The one registry of scenario kinds: the study loader, the sweep engine and the presets
all find a kind's model and run function in ``dominowave.io.kinds.KINDS``."""

from __future__ import annotations

import pytest

from dominowave.io.config import SCENARIO_MODELS, parse_study
from dominowave.io.kinds import KINDS
from dominowave.sweep.compare_rods import OmegaProfilePoint, RodsComparison
from dominowave.sweep.fig6 import Fig6Member
from dominowave.sweep.registry import get_runner, is_steppable, steppable_kinds


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_every_kind_names_its_own_model_and_a_run_function(kind):
    entry = KINDS[kind]
    assert entry.load_model().model_fields["kind"].default == kind
    assert callable(get_runner(kind))
    assert is_steppable(kind) == entry.steppable


def test_the_preset_points_are_kinds_of_the_registry_but_not_of_study_files():
    for model in (Fig6Member, RodsComparison, OmegaProfilePoint):
        kind = model.model_fields["kind"].default
        assert KINDS[kind].load_model() is model
        assert kind not in SCENARIO_MODELS
        with pytest.raises(ValueError, match=rf"scenario.kind = '{kind}' is not one of"):
            parse_study({"scenario": {"kind": kind}})


def test_study_kinds_and_steppable_kinds():
    assert {"theory", "rods", "chain"} <= set(SCENARIO_MODELS)
    assert {"rods", "chain"} <= set(steppable_kinds())
    assert not is_steppable("theory") and not is_steppable("no_such_kind")
    with pytest.raises(ValueError, match="'no_such_kind' has no run function"):
        get_runner("no_such_kind")
