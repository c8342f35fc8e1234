"""Measuring a toppling wave from arrival times, independent of the simulator.

Everything here works on two arrays a simulation (DEM, rods) or an experiment gives:

* ``arrival_times`` -- shape ``(N,)`` [s]: the first-contact time of each domino,
  i.e. the moment domino ``n`` is first touched by the wave; ``NaN`` where the
  wave never reached it. Domino 0 is the pushed one; its entry is its push time
  (or ``NaN``) and is used only if finite.
* ``positions`` -- shape ``(N,)`` [m]: a coordinate of each domino along the chain
  (pivot or front face; only differences matter), strictly increasing.

The wave is measured as a researcher would:

1. ``local_speeds``: ``v_n = (x_{n+1} - x_n) / (t_{n+1} - t_n)`` between neighbours.
2. ``settled_start``: where the local speed has settled, *detected from the data*:
   the longest tail of the profile with no significant drift (see its docstring).
3. ``steady_speed``: least-squares fit ``t_n = t_0 + x_n / v`` over the settled
   dominoes, with an uncertainty (the larger of the fit's standard error and the
   standard error of the interval mean; see ``SteadySpeed``).
3b. ``speed_from``: the same fit from a chosen domino ``K`` to the last domino reached,
   as high-speed-camera studies report a front speed (no settling detection).
4. ``ensemble_stats``: mean, standard deviation and standard error over an
   ensemble (the chain is chaotic: single runs are not reproducible numbers).
5. ``secondary_wave``: the wave of *second* contacts between neighbours (dominoes
   that bounced back and fell again) -- its speed, its lag behind the primary wave,
   and whether and where it overtakes the primary wave (paper section 3, Fig 6E).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from dominowave.checks import check_in_range

__all__ = [
    "EnsembleStats",
    "SecondaryWave",
    "SteadySpeed",
    "check_fit_from",
    "ensemble_arrival_stats",
    "ensemble_stats",
    "first_and_second_onsets",
    "fit_speed",
    "local_speeds",
    "reached_count",
    "secondary_wave",
    "settled_start",
    "speed_from",
    "steady_speed",
    "unsettled_reason",
]

# Noise scale of i.i.d. samples from their second differences: var(x[i+1] - 2x[i] + x[i-1])
# = 6 sigma^2; 0.6745 converts a median absolute deviation to a Gaussian sigma.
_MAD_TO_SIGMA = 1.0 / 0.6745
_SECOND_DIFF_VAR = 6.0


def _as_times_positions(arrival_times, positions) -> tuple[np.ndarray, np.ndarray]:
    t = np.asarray(arrival_times, dtype=float)
    x = np.asarray(positions, dtype=float)
    if t.ndim != 1 or x.shape != t.shape:
        raise ValueError(
            f"arrival_times and positions must be 1-D arrays of equal length, got shapes "
            f"{t.shape} and {x.shape}"
        )
    if not np.all(np.isfinite(x)):
        raise ValueError("positions must be finite")
    if x.size > 1 and not np.all(np.diff(x) > 0):
        raise ValueError("positions must be strictly increasing along the chain")
    return t, x


def reached_count(arrival_times) -> int:
    """Number of dominoes the wave reached *in order* from domino 1 on.

    Counts dominoes ``0..K-1`` such that every arrival time from domino 1 to ``K-1``
    is finite and not earlier than the previous one. Domino 0 (pushed) always
    counts. A wave that stops, or a domino reached out of order (hit from two
    ahead before its neighbour reached it), ends the count.
    """
    t = np.asarray(arrival_times, dtype=float)
    if t.size == 0:
        return 0
    k = 1
    while k < t.size and np.isfinite(t[k]) and (k == 1 or t[k] >= t[k - 1]):
        k += 1
    return k


def local_speeds(arrival_times, positions) -> np.ndarray:
    """Local wave speed between neighbours [m/s], shape ``(N-1,)``.

    ``v_n = (x_{n+1} - x_n) / (t_{n+1} - t_n)``. ``NaN`` where either arrival time
    is missing or the later domino was not reached strictly after the earlier one
    (the speed is then undefined, not infinite).
    """
    t, x = _as_times_positions(arrival_times, positions)
    dt = np.diff(t)
    dx = np.diff(x)
    v = np.full(dt.shape, np.nan)
    ok = np.isfinite(dt) & (dt > 0)
    v[ok] = dx[ok] / dt[ok]
    return v


def _noise_sigma(v: np.ndarray) -> float:
    """Robust scatter of a slowly varying sequence from its second differences."""
    if v.size < 3:
        return 0.0
    d2 = v[2:] - 2.0 * v[1:-1] + v[:-2]
    mad = float(np.median(np.abs(d2 - np.median(d2))))
    return _MAD_TO_SIGMA * mad / math.sqrt(_SECOND_DIFF_VAR)


def _linear_drift(v: np.ndarray) -> tuple[float, float]:
    """Fitted change of ``v`` from its first to its last point, and its standard error."""
    n = v.size
    j = np.arange(n, dtype=float)
    j -= j.mean()
    sxx = float(j @ j)
    slope = float(j @ (v - v.mean())) / sxx
    resid = v - v.mean() - slope * j
    dof = max(n - 2, 1)
    slope_err = math.sqrt(float(resid @ resid) / dof / sxx)
    return slope * (n - 1), slope_err * (n - 1)


def settled_start(local_speed, rtol: float = 0.01, min_points: int = 5) -> int | None:
    """Index of the first local speed of the settled part of a speed profile.

    Parameters
    ----------
    local_speed : array, shape (M,)
        Local speeds [m/s] (``local_speeds``); only the leading run of finite
        values is used (the wave must have arrived in order).
    rtol : float
        Relative tolerance on what counts as "settled" when the scatter is small
        (e.g. a noise-free transient approaching its limit geometrically).
    min_points : int
        Minimum number of local speeds in the settled part (>= 3).

    Returns
    -------
    int or None
        The smallest ``k`` such that the tail ``v[k:]`` (at least ``min_points``
        long) shows no drift: (a) the change of a straight-line fit over the tail is
        at most ``max(2 sigma_drift, rtol |mean|)`` and (b) the first tail value
        lies within ``max(3 sigma_noise, rtol |mean|)`` of the tail mean (so a
        short excursion at the start of a long tail cannot hide in the fit).
        ``sigma_noise`` is estimated robustly from second differences of the tail.
        ``None`` if no tail qualifies: the wave has not settled within the chain.
    """
    check_in_range("rtol", rtol, 0.0, 1.0)
    check_in_range("min_points", min_points, 3, math.inf, lo_inclusive=True)
    v = np.asarray(local_speed, dtype=float)
    finite = np.isfinite(v)
    m = int(np.argmin(finite)) if not finite.all() else v.size
    v = v[:m]
    for k in range(0, m - min_points + 1):
        tail = v[k:]
        mean = float(tail.mean())
        drift, drift_err = _linear_drift(tail)
        sigma = _noise_sigma(tail)
        if abs(drift) > max(2.0 * drift_err, rtol * abs(mean)):
            continue
        if abs(tail[0] - mean) > max(3.0 * sigma, rtol * abs(mean)):
            continue
        return k
    return None


@dataclass(frozen=True)
class SteadySpeed:
    """Steady wave speed fitted over the settled part of the chain.

    Attributes
    ----------
    speed : float
        Fitted speed ``v`` of ``t_n = t_0 + x_n / v`` [m/s]; NaN if not settled.
    speed_err : float
        Reported uncertainty [m/s]: ``max(fit_err, interval_err)``.
    fit_err : float
        Standard error from the least-squares residuals (right for independent
        timing jitter on each ``t_n``).
    interval_err : float
        Standard error of the mean slowness over the fitted intervals (right when
        the interval durations scatter independently, so ``t_n`` is a random walk,
        which the least-squares error would underestimate).
    first, last : int
        Dominoes ``first..last`` (inclusive) used in the fit; -1 if not settled.
    settled : bool
        Whether a settled part was found (``settled_start``).
    reached : int
        Number of dominoes reached in order (``reached_count``).
    intercept : float
        ``t_0`` of the fit [s].
    residual_rms : float
        RMS residual of the arrival times about the fit [s].
    """

    speed: float
    speed_err: float
    fit_err: float
    interval_err: float
    first: int
    last: int
    settled: bool
    reached: int
    intercept: float
    residual_rms: float

    @property
    def n_points(self) -> int:
        """Number of arrival times in the fit."""
        return self.last - self.first + 1 if self.settled else 0


def _fit_slowness(t: np.ndarray, x: np.ndarray) -> tuple[float, float, float, float, float]:
    """LS fit ``t = t0 + p x``; returns p, its fit error, interval error, t0, rms."""
    n = t.size
    xc = x - x.mean()
    sxx = float(xc @ xc)
    p = float(xc @ (t - t.mean())) / sxx
    t0 = float(t.mean() - p * x.mean())
    resid = t - t0 - p * x
    dof = max(n - 2, 1)
    p_fit_err = math.sqrt(float(resid @ resid) / dof / sxx)
    slowness = np.diff(t) / np.diff(x)
    p_int_err = float(slowness.std(ddof=1)) / math.sqrt(slowness.size) if n > 2 else 0.0
    rms = math.sqrt(float(resid @ resid) / n)
    return p, p_fit_err, p_int_err, t0, rms


def _fit_window(t, x, first: int, last: int, reached: int) -> SteadySpeed:
    """Least-squares speed over dominoes ``first..last`` of arrival times ``t`` [s]."""
    p, p_fit_err, p_int_err, t0, rms = _fit_slowness(t[first : last + 1], x[first : last + 1])
    if not p > 0:
        raise ValueError(f"fitted slowness {p:.6g} s/m is not positive: arrival times unordered")
    fit_err, interval_err = p_fit_err / p**2, p_int_err / p**2
    return SteadySpeed(
        speed=1.0 / p,
        speed_err=max(fit_err, interval_err),
        fit_err=fit_err,
        interval_err=interval_err,
        first=first,
        last=last,
        settled=True,
        reached=reached,
        intercept=t0,
        residual_rms=rms,
    )


def steady_speed(arrival_times, positions, rtol: float = 0.01, min_points: int = 5) -> SteadySpeed:
    """Steady wave speed [m/s] with uncertainty from the settled part of the chain.

    The settled part is detected with ``settled_start`` on the local speeds of the
    dominoes reached in order. The speed comes from a least-squares fit of the
    arrival times against position, ``t_n = t_0 + x_n / v`` (position is exact,
    time carries the scatter), over dominoes ``first..last``. Its uncertainty
    propagates the slowness error: ``err_v = err_p / p^2``.

    Parameters
    ----------
    arrival_times, positions : arrays, shape (N,)
        See the module docstring ([s] and [m]).
    rtol, min_points
        Passed to ``settled_start``.
    """
    t, x = _as_times_positions(arrival_times, positions)
    reached = reached_count(t)
    start = 1 if not np.isfinite(t[0]) else 0
    v = local_speeds(t[start:reached], x[start:reached]) if reached - start > 1 else np.empty(0)
    k = settled_start(v, rtol=rtol, min_points=min_points) if v.size else None
    if k is None:
        nan = math.nan
        return SteadySpeed(nan, nan, nan, nan, -1, -1, False, reached, nan, nan)
    return _fit_window(t, x, start + k, reached - 1, reached)


@dataclass(frozen=True)
class EnsembleStats:
    """Statistics of one quantity over an ensemble of runs.

    ``mean``, ``std`` (sample, ddof=1), ``stderr = std / sqrt(n)`` over the ``n``
    finite values; ``n_failed`` counts members whose value is NaN (e.g. the wave
    did not settle or stopped). With ``n < 2`` the spread is NaN.
    """

    mean: float
    std: float
    stderr: float
    n: int
    n_failed: int

    def __str__(self) -> str:
        return f"{self.mean:.6g} ± {self.stderr:.2g} (std {self.std:.2g}, n={self.n})"


def ensemble_stats(values) -> EnsembleStats:
    """Mean, standard deviation and standard error of ``values`` (shape ``(M,)``), NaN-aware."""
    a = np.asarray(values, dtype=float).ravel()
    ok = a[np.isfinite(a)]
    n = int(ok.size)
    mean = float(ok.mean()) if n else math.nan
    std = float(ok.std(ddof=1)) if n > 1 else math.nan
    stderr = std / math.sqrt(n) if n > 1 else math.nan
    return EnsembleStats(mean, std, stderr, n, int(a.size - n))


def ensemble_arrival_stats(arrival_times) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per-domino mean, std and standard error of arrival times over an ensemble.

    ``arrival_times`` has shape ``(M, N)`` (members x dominoes) [s]; returns three
    arrays of shape ``(N,)``; entries with fewer than two finite members are NaN.
    """
    a = np.asarray(arrival_times, dtype=float)
    if a.ndim != 2:
        raise ValueError(f"arrival_times must have shape (members, N), got {a.shape}")
    ok = np.isfinite(a)
    n = ok.sum(axis=0)
    filled = np.where(ok, a, 0.0)
    mean = np.full(a.shape[1], np.nan)
    std = np.full(a.shape[1], np.nan)
    has = n > 0
    mean[has] = filled[:, has].sum(axis=0) / n[has]
    two = n > 1
    dev = np.where(ok, a - mean, 0.0)
    std[two] = np.sqrt((dev[:, two] ** 2).sum(axis=0) / (n[two] - 1))
    stderr = np.full(a.shape[1], np.nan)
    stderr[two] = std[two] / np.sqrt(n[two])
    return mean, std, stderr


def first_and_second_onsets(
    onsets_per_pair: Sequence[Sequence[float]],
) -> tuple[np.ndarray, np.ndarray]:
    """First and second contact onset of each neighbour pair.

    ``onsets_per_pair[n]`` lists the onset times [s] of every contact between
    dominoes ``n`` and ``n+1`` (any order). Returns two arrays of shape ``(len,)``:
    the earliest and the second-earliest onset, NaN where missing.
    """
    first = np.full(len(onsets_per_pair), np.nan)
    second = np.full(len(onsets_per_pair), np.nan)
    for n, onsets in enumerate(onsets_per_pair):
        s = np.sort(np.asarray(onsets, dtype=float))
        if s.size > 0:
            first[n] = s[0]
        if s.size > 1:
            second[n] = s[1]
    return first, second


@dataclass(frozen=True)
class SecondaryWave:
    """The wave of second contacts between neighbours and its race with the primary.

    Attributes
    ----------
    lag : array, shape (P,)
        ``second_onset - first_onset`` per pair [s] (NaN: no second contact).
    pairs : array of int
        Pairs with a second contact, used for the fits.
    primary, secondary : SteadySpeed-like fits
        Straight-line fits (``t = t0 + x / v``) of first and second onsets over
        ``pairs`` (no settling detection: the secondary wave is usually short).
    lag_slope, lag_slope_err : float
        Change of the lag per pair [s] and its standard error; negative means the
        secondary wave is catching up.
    catching_up : bool
        ``lag_slope < -2 lag_slope_err``: the secondary wave is significantly faster.
    merged_pair : int or None
        First pair whose lag is at most ``merge_lag``: the secondary wave has
        reached the primary one there (observed overtaking).
    predicted_pair : float
        Pair index where the fitted lag line reaches ``merge_lag`` (may lie beyond
        the chain; NaN if not catching up).
    """

    lag: np.ndarray
    pairs: np.ndarray
    primary: SteadySpeed
    secondary: SteadySpeed
    lag_slope: float
    lag_slope_err: float
    catching_up: bool
    merged_pair: int | None
    predicted_pair: float

    @property
    def overtakes(self) -> bool:
        """Whether the secondary wave catches the primary one within the chain."""
        return self.merged_pair is not None


def fit_speed(arrival_times, positions, first: int, last: int) -> SteadySpeed:
    """Least-squares speed over the given dominoes ``first..last`` (no settling detection).

    Use it to measure another record over the same window, e.g. the theory's transient
    arrival times over the dominoes where a simulation's wave had settled.
    """
    t_all, x_all = _as_times_positions(arrival_times, positions)
    if not 0 <= first < last < t_all.size:
        raise ValueError(f"first, last = {first}, {last} must satisfy 0 <= first < last < N")
    if not np.all(np.isfinite(t_all[first : last + 1])):
        raise ValueError(f"arrival times of dominoes {first}..{last} must be finite")
    return _fit_window(t_all, x_all, first, last, reached_count(t_all))


def check_fit_from(first, n_dominoes: int) -> int:
    """``first`` if it is a valid ``fit_from`` for ``n_dominoes``, else one ``ValueError``."""
    if isinstance(first, bool) or not isinstance(first, int | np.integer):
        raise ValueError(f"fit_from = {first!r} is not an integer domino index")
    if n_dominoes < 3:  # no fit from any domino: name the chain's length, not fit_from
        raise ValueError(
            f"n_dominoes = {n_dominoes} is outside the valid range [3, inf) for a fitted speed"
            " (domino 0 is pushed, a fit needs two arrival times)"
        )
    if not 1 <= first <= n_dominoes - 2:
        raise ValueError(
            f"fit_from = {first} is outside [1, {n_dominoes - 2}] (1 <= K <= N - 2 for a chain"
            f" of N = {n_dominoes} dominoes: domino 0 is pushed, a fit needs two arrival times)"
        )
    return int(first)


def speed_from(arrival_times, positions, first: int) -> SteadySpeed:
    """Front speed [m/s] fitted from domino ``first`` (``K``) to the last domino reached.

    What an experiment reports: a camera films the front from domino ``K`` on (past the
    push) and fits ``t_n = t_0 + x_n / v`` over every domino the wave reached in order;
    with ``x_n = n (d + s)`` (``chain_positions``) the speed is pitch-based. No settling
    is detected, so a wave still speeding up is averaged over. Returns the fit with
    ``settled=True``, or NaN speeds (``settled=False``, ``first = last = -1``) when the
    wave reached fewer than two dominoes from ``K`` on.

    ``first`` must satisfy ``1 <= K <= N - 2`` (domino 0 is the pushed one; at least two
    arrival times are fitted).
    """
    t, x = _as_times_positions(arrival_times, positions)
    check_fit_from(first, t.size)
    reached = reached_count(t)
    if reached - 1 <= first:
        nan = math.nan
        return SteadySpeed(nan, nan, nan, nan, -1, -1, False, reached, nan, nan)
    return _fit_window(t, x, int(first), reached - 1, reached)


def secondary_wave(
    first_onset, second_onset, positions, merge_lag: float = 0.0, min_pairs: int = 4
) -> SecondaryWave | None:
    """Detect the secondary (collective) wave of re-contacts and its overtaking.

    In a dissipative chain domino ``n`` bounces back after hitting ``n+1``, does not
    return to the vertical and falls again, hitting ``n+1`` a second time (paper
    section 3). The second onsets of successive pairs form the secondary wave. It
    overtakes the primary wave where its lag behind the first onsets vanishes;
    from then on the propagation is collective.

    Parameters
    ----------
    first_onset, second_onset : arrays, shape (P,)
        First and second contact onsets of pair ``n`` = dominoes ``(n, n+1)`` [s]
        (``first_and_second_onsets``); NaN where absent.
    positions : array, shape (P,)
        Coordinate of each pair (e.g. of its front domino) [m], increasing.
    merge_lag : float
        Lag [s] at or below which the two waves count as merged; a natural choice
        is a collision time (two contacts closer than one collision are one event).
    min_pairs : int
        Minimum number of pairs with a second contact needed to fit (>= 3).

    Returns
    -------
    SecondaryWave or None
        ``None`` if fewer than ``min_pairs`` contiguous pairs from the first pair
        with a second contact had one, or if the first or second onsets of those pairs
        do not advance along the chain (fitted slowness <= 0): no secondary wave.
    """
    check_in_range("merge_lag", merge_lag, 0.0, math.inf, lo_inclusive=True)
    check_in_range("min_pairs", min_pairs, 3, math.inf, lo_inclusive=True)
    t1, x = _as_times_positions(first_onset, positions)
    t2 = np.asarray(second_onset, dtype=float)
    if t2.shape != t1.shape:
        raise ValueError(f"second_onset shape {t2.shape} differs from first_onset {t1.shape}")
    lag = t2 - t1
    has = np.isfinite(lag)
    if not has.any():
        return None
    # contiguous run of pairs with a second contact, starting at the first such pair
    i0 = int(np.argmax(has))
    run = has[i0:]
    i1 = i0 + (int(np.argmin(run)) if not run.all() else run.size)
    if i1 - i0 < min_pairs:
        return None
    pairs = np.arange(i0, i1)
    for t in (t1, t2):
        if not _fit_slowness(t[pairs], x[pairs])[0] > 0:
            # the onsets do not run along the chain (e.g. dominoes falling backwards onto
            # their predecessors re-contact them in reverse order): no wave to fit
            return None
    primary = fit_speed(t1, x, i0, i1 - 1)
    secondary = fit_speed(t2, x, i0, i1 - 1)
    drift, drift_err = _linear_drift(lag[pairs])
    span = pairs.size - 1
    slope, slope_err = drift / span, drift_err / span
    catching_up = slope < -2.0 * slope_err
    below = np.flatnonzero(has & (lag <= merge_lag))
    merged = int(below[0]) if below.size else None
    if catching_up:
        lag_mean = float(lag[pairs].mean())
        predicted = float(pairs.mean()) + (merge_lag - lag_mean) / slope
    else:
        predicted = math.nan
    return SecondaryWave(
        lag=lag,
        pairs=pairs,
        primary=primary,
        secondary=secondary,
        lag_slope=slope,
        lag_slope_err=slope_err,
        catching_up=bool(catching_up),
        merged_pair=merged,
        predicted_pair=predicted,
    )


def unsettled_reason(arrival_times, positions, min_points: int = 5) -> str:
    """Why ``steady_speed`` found no settled part, in one phrase ("" if it did).

    Read from the data as ``settled_start`` reads it: too few dominoes reached for a
    tail of ``min_points`` local speeds; or, over the last third of the local speeds
    (at least ``min_points``), a drift -- the wave still accelerates or slows, by the
    fitted change per domino in percent of the mean -- or a scatter larger than the
    settling tolerance. ``arrival_times`` [s] and ``positions`` [m] have shape (N,).
    """
    if steady_speed(arrival_times, positions, min_points=min_points).settled:
        return ""
    t, x = _as_times_positions(arrival_times, positions)
    n, reached = t.size, reached_count(t)
    start = 1 if not np.isfinite(t[0]) else 0
    v = local_speeds(t[start:reached], x[start:reached]) if reached - start > 1 else np.empty(0)
    finite = np.isfinite(v)
    v = v[: int(np.argmin(finite))] if not finite.all() else v
    if v.size < min_points:
        where = "stopped there" if reached < n else f"the chain has {n}"
        return (
            f"the wave reached only {reached} dominoes ({where}); a speed needs a settled "
            f"stretch of at least {min_points} local speeds"
        )
    tail = v[-max(min_points, v.size // 3) :]
    mean = float(tail.mean())
    drift, _ = _linear_drift(tail)
    per_domino = 100.0 * drift / (tail.size - 1) / abs(mean)
    if abs(drift) > 0.01 * abs(mean):
        trend = "accelerating" if drift > 0 else "slowing down"
        return (
            f"the wave is still {trend}: over the last {tail.size} dominoes its local speed "
            f"changes by {per_domino:+.2g} % per domino; a longer chain, or damping, "
            "may let it settle"
        )
    spread = 100.0 * float(tail.std()) / abs(mean)
    return (
        f"the local speed scatters by {spread:.2g} % (standard deviation) over the last "
        f"{tail.size} dominoes with no settled stretch"
    )
