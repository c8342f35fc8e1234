"""The comparison of the identity tests (stored_runs.py): to the bit in the environment that
wrote the arrays, to round-off in another, integers always exactly."""

from __future__ import annotations

import numpy as np
import pytest
from stored_runs import ENVIRONMENT_KEY, ROUNDOFF, assert_as_stored, float_environment


def _stored(tmp_path, environment):
    path = tmp_path / "runs.npz"
    arrays = {
        "s/pos": np.array([1.0, -2.0, 0.5]),
        "s/ev_time": np.array([0.25]),
        "s/ev_i": np.array([3]),
    }
    np.savez(path, **{ENVIRONMENT_KEY: np.array(environment)}, **arrays)
    return path, arrays


def test_same_environment_compares_bits(tmp_path):
    path, arrays = _stored(tmp_path, float_environment())
    assert_as_stored(path, "s", arrays)
    arrays["s/pos"] = np.nextafter(arrays["s/pos"], 3.0)  # (one unit in the last place)
    with pytest.raises(AssertionError, match="s/pos"):
        assert_as_stored(path, "s", arrays)


def test_other_environment_compares_to_roundoff_and_says_so(tmp_path):
    path, arrays = _stored(tmp_path, "cpu another")
    scale = 2.0  # (the largest magnitude of s/pos)
    close = dict(arrays, **{"s/pos": arrays["s/pos"] + 0.5 * ROUNDOFF * scale})
    with pytest.warns(UserWarning, match="cpu another"):
        assert_as_stored(path, "s", close)
    far = dict(arrays, **{"s/pos": arrays["s/pos"] + 2.0 * ROUNDOFF * scale})
    with pytest.warns(UserWarning), pytest.raises(AssertionError, match="s/pos"):
        assert_as_stored(path, "s", far)
    other_event = dict(arrays, **{"s/ev_i": np.array([4])})
    with pytest.warns(UserWarning), pytest.raises(AssertionError, match="s/ev_i"):
        assert_as_stored(path, "s", other_event)
