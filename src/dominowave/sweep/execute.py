"""Run one point and package the outcome -- the code that runs on a dask worker.

A failing scenario does not raise: its error and traceback come back as data,
so the sweep records them and goes on. A result with NaN in its summary counts
as a failure (numerical blow-up is reported, never stored as a result).
"""

from __future__ import annotations

import math
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from dominowave.io.provenance import provenance
from dominowave.io.results import RunResult
from dominowave.sweep.hashing import point_key
from dominowave.sweep.registry import RunContext, get_runner

__all__ = ["PointOutcome", "execute_point"]


@dataclass
class PointOutcome:
    """Result of one point: ``status`` "ok" (``result`` set) or "failed" (``error`` set)."""

    key: str
    status: str
    provenance: dict
    result: RunResult | None = None
    error: str | None = None
    traceback: str | None = None


def _nan_fields(summary: dict[str, Any]) -> list[str]:
    return [k for k, v in summary.items() if isinstance(v, float) and math.isnan(v)]


def execute_point(
    config, runner: Callable | None = None, ctx: RunContext | None = None
) -> PointOutcome:
    """Run scenario ``config`` (a validated model) and return a :class:`PointOutcome`.

    ``runner`` defaults to the registered run function of ``config.kind``.
    """
    key = point_key(config)
    started, t0 = time.time(), time.perf_counter()
    try:
        run = runner if runner is not None else get_runner(config.kind)
        result = run(config, ctx or RunContext())
        bad = [k for k in _nan_fields(result.summary) if k not in result.may_be_nan]
        if bad:
            raise FloatingPointError(f"non-finite result: {', '.join(bad)} = NaN")
        outcome = PointOutcome(key, "ok", {}, result=result)
    except Exception as exc:  # the sweep goes on; the failure is recorded
        outcome = PointOutcome(
            key,
            "failed",
            {},
            error=f"{type(exc).__name__}: {exc}",
            traceback=traceback.format_exc(),
        )
    seed = getattr(config, "seed", None)
    outcome.provenance = provenance(
        key=key, seed=seed, wall_time=time.perf_counter() - t0, started=started
    )
    return outcome
