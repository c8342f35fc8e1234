"""Runs whose wave did not settle, drawn rather than dropped.

Their speed is NaN, so a plain ``errorbar`` would leave a gap where a run was made. They
are drawn as open markers along the bottom edge of the axes at their abscissa (the
height means nothing: there is no speed to show), with a legend entry that says so.
"""

from __future__ import annotations

import numpy as np

__all__ = ["UNSETTLED_LABEL", "mark_unsettled"]

UNSETTLED_LABEL = "not settled: no speed (open, on the bottom edge)"
"""Legend text of the open markers."""


def mark_unsettled(ax, x, color, label: str | None = UNSETTLED_LABEL):
    """Open markers at abscissae ``x`` on the bottom edge of ``ax``; returns the line
    (None if ``x`` is empty). Axis limits and scales are left as the data set them."""
    from matplotlib.transforms import blended_transform_factory

    x = np.asarray(x, dtype=float)
    if x.size == 0:
        return None
    (line,) = ax.plot(
        x,
        np.full(x.size, 0.03),
        "o",
        mfc="none",
        mec=color,
        mew=1.5,
        ms=7,
        transform=blended_transform_factory(ax.transData, ax.transAxes),
        clip_on=False,
        label=label,
    )
    return line
