"""Fig 6's speed panels draw every ensemble: none settled -> an open marker at its d/l,
some settled -> the count beside the point."""

from __future__ import annotations

import math

import numpy as np
from matplotlib.colors import to_rgba
from matplotlib.figure import Figure

from dominowave.plots.fig6 import _speed_axes


def _row(config, d, settled, members=8, speed=1.0):
    return {
        "config": config,
        "d_over_l": d,
        "members": members,
        "n_settled": settled,
        "speed_mean": speed if settled else math.nan,
        "speed_stderr": 0.01 if settled > 1 else math.nan,
        "theory_window_speed": 1.1,
    }


def test_ensembles_without_a_settled_member_are_open_markers():
    summary = [
        _row("2d", 0.2, 8),
        _row("2d", 0.4, 0),  # no member settled: once a gap in Fig 6B
        _row("3d", 0.2, 5),
        _row("3d", 0.4, 0),
    ]
    ax = Figure().subplots()
    _speed_axes(ax, summary, ("2d", "3d"), 1.0, np.linspace(0.1, 0.5, 5), ())
    open_x = [
        x
        for line in ax.get_lines()
        if line.get_marker() == "o" and to_rgba(line.get_markerfacecolor())[3] == 0
        for x in line.get_xdata()
    ]
    assert len(open_x) == 2 and np.allclose(sorted(open_x), [0.4, 0.4], atol=0.01)
    notes = [t.get_text() for t in ax.texts]
    assert notes == ["5/8"]  # the 3D ensemble at 0.2 left 3 members out
    _, labels = ax.get_legend_handles_labels()
    assert sum(label.startswith("no member settled") for label in labels) == 1
