"""Parameter checks shared by every layer of the package.

Every public function validates its physical inputs with these helpers so that a
bad value fails early with a message naming the parameter, the value and the
valid range, e.g. ``ValueError: d_over_l = 1.2 is outside the valid range (0, 1)``.

The helpers accept scalars or NumPy arrays; for arrays the first offending
element is reported.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "check_finite",
    "check_format",
    "check_in_range",
    "check_memory",
    "check_nonnegative",
    "check_positive",
]


def _first_bad(value, bad_mask):
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        return float(arr)
    return float(arr.reshape(-1)[np.argmax(np.asarray(bad_mask).reshape(-1))])


def _fmt(x: float) -> str:
    return f"{x:.6g}"


def check_finite(name: str, value):
    """Raise ``ValueError`` unless every element of ``value`` is a finite number."""
    arr = np.asarray(value, dtype=float)
    bad = ~np.isfinite(arr)
    if np.any(bad):
        raise ValueError(f"{name} = {_fmt(_first_bad(value, bad))} is not a finite number")
    return value


def check_in_range(
    name: str,
    value,
    lo: float = -math.inf,
    hi: float = math.inf,
    *,
    lo_inclusive: bool = False,
    hi_inclusive: bool = False,
):
    """Raise ``ValueError`` unless ``lo < value < hi`` (bounds optionally inclusive).

    The message names the parameter, the offending value and the valid interval in
    standard notation, e.g. ``(0, 1)`` or ``[0, inf)``.
    """
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {value!r} is not a number") from None
    nan = np.isnan(arr)
    below = arr < lo if lo_inclusive else arr <= lo
    above = arr > hi if hi_inclusive else arr >= hi
    bad = nan | below | above
    if np.any(bad):
        left = "[" if lo_inclusive else "("
        right = "]" if hi_inclusive else ")"
        interval = f"{left}{_fmt(lo)}, {_fmt(hi)}{right}"
        raise ValueError(
            f"{name} = {_fmt(_first_bad(value, bad))} is outside the valid range {interval}"
        )
    return value


def check_positive(name: str, value):
    """Raise ``ValueError`` unless every element of ``value`` is > 0 (inf allowed)."""
    return check_in_range(name, value, 0.0, math.inf, hi_inclusive=True)


def check_nonnegative(name: str, value):
    """Raise ``ValueError`` unless every element of ``value`` is >= 0 and finite."""
    return check_in_range(name, value, 0.0, math.inf, lo_inclusive=True)


MEMORY_FRACTION = 0.8
"""Largest share of the machine's available memory one run may plan to use."""


def available_memory() -> int:
    """Memory this process can still allocate without swapping [bytes] (psutil)."""
    import psutil

    return int(psutil.virtual_memory().available)


def check_memory(nbytes: float, what: str, culprits: str) -> None:
    """Raise ``ValueError`` if a run would need more than the machine can hold.

    ``nbytes`` is the run's estimated peak memory [bytes], ``what`` says what it is
    for and ``culprits`` names the parameters that set it (with their values). Called
    before the big arrays are allocated, so that a run too large fails at once with
    one line instead of a ``MemoryError`` (or swapping) minutes into the run.
    """
    limit = MEMORY_FRACTION * available_memory()
    if nbytes > limit:
        raise ValueError(
            f"{culprits}: the run needs about {nbytes / 2**30:.3g} GiB for {what}, more than"
            f" this machine can hold ({limit / 2**30:.3g} GiB, {MEMORY_FRACTION:.0%} of the"
            " memory available now); choose smaller values"
        )


def check_format(key: str, version: int, newest: int) -> int:
    """``version``, the format ``key`` of a saved state, if this version of the package
    reads it (1 to ``newest``); else ``ValueError`` naming both."""
    if not 1 <= version <= newest:
        newer = " (a newer dominowave wrote it)" if version > newest else ""
        raise ValueError(
            f"{key} = {version}: this version of dominowave reads formats 1 to {newest}{newer}"
        )
    return version
