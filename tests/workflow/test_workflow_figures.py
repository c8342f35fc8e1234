"""`dominowave plot`'s speed figure hides nothing: every point inside the axes, runs
that did not settle drawn as open markers."""

from __future__ import annotations

import math
import tomllib

import numpy as np
from matplotlib.colors import to_rgba

from dominowave.io.config import example_toml, parse_study
from dominowave.io.results import read_summary
from dominowave.plots.folder import _speed_figure
from dominowave.sweep.runner import run_one


def _records(tmp_path, spacings):
    base = tomllib.loads(example_toml("theory"))
    base["scenario"]["n_frames"] = 30
    out = []
    for i, d in enumerate(spacings):
        data = {"scenario": {**base["scenario"], "d_over_l": d}}
        folder = tmp_path / f"p{i}"
        assert run_one(parse_study(data), folder) == "ok"
        config = tomllib.loads((folder / "config.toml").read_text())["scenario"]
        summary = read_summary(folder)
        out.append({"key": f"p{i}", "swept": {"d_over_l": d}, "config": config,
                    "summary": summary, "folder": folder})  # fmt: skip
    return out


def test_speed_figure_keeps_fast_points_and_marks_unsettled_ones(tmp_path):
    """A point at small d/l (v/sqrt(gl) far above the old cap of 8) lies inside the
    axes, and a point whose speed is NaN is an open marker at its d/l, not a gap."""
    records = _records(tmp_path, [0.02, 0.25, 0.5])
    records[1]["summary"]["speed"] = math.nan  # as a run that did not settle
    fig = _speed_figure(records)
    ax = fig.axes[0]
    scale = math.sqrt(9.81 * records[0]["config"]["height"])
    fast = records[0]["summary"]["speed"] / scale
    assert fast > 8.0
    lo, hi = ax.get_ylim()
    assert lo < fast < hi
    for line in ax.get_lines():  # every curve inside the axes too
        y = np.asarray(line.get_ydata(), dtype=float)
        if line.get_transform() is ax.transData and np.isfinite(y).any():
            assert np.nanmax(y) <= hi and np.nanmin(y[y > 0]) >= lo
    open_markers = [
        line for line in ax.get_lines()
        if line.get_marker() == "o" and to_rgba(line.get_markerfacecolor())[3] == 0
    ]  # fmt: skip
    assert len(open_markers) == 1
    x_open = open_markers[0].get_xdata()
    assert np.allclose(x_open, [records[1]["summary"]["d_over_l"]])
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any(t.startswith("not settled") for t in labels)
