"""Cross-code check: the box-domino chain in MuJoCo (exact boxes), its front speed.

What: a straight chain of N rigid box dominoes (height l = 0.048 m, width w = 0.024 m,
thickness s = 0.0075 m, mass 0.008 kg) standing upright on a floor plane, clear gap d
between neighbours (pitch d + s, x along the chain), simulated in MuJoCo; the front speed
is fitted to the times each domino is first struck, for comparison with dominowave's DEM
chain of boxes.

How:
* The model is an MJCF string built here. Each domino is a free body with one ``box``
  geom; the floor is a ``plane``. MuJoCo collides them with its dedicated analytic
  primitives (box-box: ``mjc_BoxBox``, box-plane: ``mjc_PlaneBox``), so the boxes have
  sharp edges and corners (no rounding). ``cone="elliptic"``, ``integrator="implicitfast"``,
  Newton solver with MuJoCo's default iterations and tolerance, time step ``dt``.
* Friction: every contact has ``condim="3"`` and sliding friction ``mu``. The dominoes'
  geoms carry ``friction_dominoes``; the floor carries ``friction_floor`` with
  ``priority="1"``, so a domino-floor contact takes the floor's coefficient and a
  domino-domino contact the dominoes' (equal priorities: the maximum of two equal
  values). With ``friction_dominoes = 0`` the dominoes get ``condim="1"`` (frictionless
  contact between dominoes; the floor contact keeps condim 3 through its priority)
  rather than a condim-3 cone of zero width, which MuJoCo clamps to mu = 1e-5.
* Contacts: ``solref="0.002 1"`` (time constant 2 ms, critical damping ratio 1: a
  collision does not bounce, it is nearly perfectly inelastic),
  ``solimp="0.9 0.95 0.001 0.5 2"``, ``impratio=1``, contact margin 0. MuJoCo's default
  time constant, 20 ms, is too soft for a domino impact: the boxes then overlap by 4-7.6
  mm (up to a whole thickness) and the chain runs 2-4 % slow with friction between the
  dominoes and 26 % slow without. At 2 ms the deepest overlap is 0.45 mm and the speed
  is converged in the time constant (0.8747 m/s at 5 ms, 0.8754 at 2 ms, 1 ms moves the
  frictionless speed by 0.1 %). The time constant is a physical parameter (not tied to
  ``dt``; MuJoCo needs ``tc >= 2 dt``); ``--solref-tc`` changes it for every run and the
  stiffness series (``--tcs`` at ``--tc-dt``, printed only) shows what it does.
* Start: all dominoes are first let settle for ``SETTLE_S`` on the floor (they sink into
  the soft floor contact by a fraction of a millimetre), then time is reset to 0 and
  domino 0 gets the angular velocity ``omega = sqrt(g / l)`` about +y (toppling it
  towards +x), about its front bottom edge (that edge at rest, the centre moving as
  ``omega x (centre - edge)``).
* Arrival time of domino n (n >= 1): its first-contact time, as in
  ``dominowave.chain.wave`` (a tilt threshold is not used). It is detected as the first
  step after which MuJoCo has a contact between dominoes n-1 and n (a contact exists
  once the boxes overlap, margin 0), and located inside that step: the geometric gap
  between the top front edge of domino n-1 and the back face of domino n (computed from
  the poses every step for the pair at the front of the wave) is interpolated linearly
  to zero between the end of the previous step and the end of this one. Without this the
  times are whole steps: the intervals between arrivals are nearly periodic, so the
  fitted speed would snap to pitch / (k dt), a grid ~4 % coarse at dt = 1e-3 s.
* Front speed: ``dominowave.chain.wave.speed_from`` on those times with
  ``x_n = n (d + s)``, from domino ``--fit-from`` (10) to the last domino reached in
  order: the least-squares slope of x_n against t_n.
* A run stops when the last domino is struck, when no new domino was struck for
  ``--stall`` simulated seconds (the wave stopped), or at ``--t-max``.
  ``wall_s`` is the wall-clock time of the stepping loop after settling, including the
  per-step scan of the contact list and the front pair's gap (numpy, ~10 us a step).

It runs, by default: the grid friction_dominoes in (0, 0.3, 0.525) x gaps (9.38, 15.09,
25.0) mm at friction_floor = 1.0, N = 30, dt = 2e-4 s; a dt-convergence series at one point
(default gap 9.38 mm, friction_dominoes 0.3, friction_floor 1.0; dt = 1e-3, 5e-4, 2e-4,
1e-4 s); and the standard chain (N = 40, gap 9.38 mm, friction 0.3 between dominoes and
on the floor, dt = 2e-4 s, wall time the median of ``--repeat`` runs). All rows go to the
CSV ``--out`` (gap_m, friction_dominoes, friction_floor, dt_s, n, speed_m_s, wall_s);
diagnostics (dominoes reached, re-contacts, slip of the pivot edge on the floor, deepest
overlap between dominoes) are printed.

Needs MuJoCo: ``pip install -e '.[bench]'``. Not imported by the tests.

Run:  python benchmarks/mujoco_chain.py [--out benchmarks/mujoco_chain.csv] [--n 30]
      [--dt 2e-4] [--dts 1e-3,5e-4,2e-4,1e-4] [--gaps-mm 9.38,15.09,25.0]
      [--mu-dd 0,0.3,0.525] [--mu-floor 1.0] [--repeat 3] [--solref-tc 0.002]
      [--tcs 0.02,0.005,0.002,0.001] [--tc-dt 1e-4] [--skip-grid] [--skip-conv] [--skip-standard]
      [--skip-stiffness]
"""

from __future__ import annotations

import argparse
import csv
import math
import statistics
import sys
import time
from dataclasses import dataclass

import numpy as np

try:
    import mujoco
except ImportError:  # pragma: no cover - depends on the environment
    sys.exit("mujoco_chain.py needs MuJoCo: pip install -e '.[bench]'")

from dominowave.chain.wave import reached_count, speed_from

HEIGHT = 0.048  # l [m]
WIDTH = 0.024  # w [m]
THICKNESS = 0.0075  # s [m]
MASS = 0.008  # [kg]
G = 9.81  # [m/s^2]
SETTLE_S = 0.1  # settling time before the push [s]
FIELDS = ["gap_m", "friction_dominoes", "friction_floor", "dt_s", "n", "speed_m_s", "wall_s"]


def chain_mjcf(
    n: int, gap: float, mu_dd: float, mu_floor: float, dt: float, solref_tc: float = 0.002
) -> str:
    """MJCF of a chain of ``n`` upright box dominoes with clear gap ``gap`` [m].

    ``mu_dd`` and ``mu_floor`` are the sliding friction coefficients [-] between dominoes
    and between a domino and the floor (see the module docstring for how MuJoCo combines
    them); ``dt`` is the time step [s]; ``solref_tc`` the contacts' time constant [s]
    (damping ratio 1). Domino k is body ``d{k}`` with geom ``g{k}`` at
    ``x = k (gap + THICKNESS)``; geom ids are 0 (floor), 1..n (dominoes).
    """
    pitch = gap + THICKNESS
    hx, hy, hz = THICKNESS / 2, WIDTH / 2, HEIGHT / 2
    condim = 3 if mu_dd > 0 else 1
    bodies = "\n".join(
        f'    <body name="d{k}" pos="{k * pitch:.9g} 0 {hz:.9g}"><freejoint/>'
        f'<geom name="g{k}" class="domino"/></body>'
        for k in range(n)
    )
    return f"""<mujoco model="domino_chain">
  <option timestep="{dt:.9g}" gravity="0 0 {-G}" integrator="implicitfast"
          cone="elliptic" impratio="1"/>
  <default>
    <geom solref="{solref_tc:.9g} 1" solimp="0.9 0.95 0.001 0.5 2" margin="0"/>
    <default class="domino">
      <geom type="box" size="{hx:.9g} {hy:.9g} {hz:.9g}" mass="{MASS:.9g}"
            condim="{condim}" friction="{mu_dd:.9g} 0.005 0.0001"/>
    </default>
  </default>
  <worldbody>
    <geom name="floor" type="plane" size="0 0 1" priority="1" condim="3"
          friction="{mu_floor:.9g} 0.005 0.0001"/>
{bodies}
  </worldbody>
</mujoco>
"""


@dataclass(frozen=True)
class ChainRun:
    """One MuJoCo chain run.

    ``arrival`` (N,) first-contact times [s] (domino 0: 0.0, the push; NaN: never
    struck); ``speed`` fitted front speed [m/s] (NaN if too few dominoes were reached);
    ``reached`` dominoes reached in order; ``wall_s`` wall time of the stepping loop [s];
    ``sim_s`` simulated time [s]; ``recontacts`` neighbour pairs whose contact ended and
    formed again; ``max_onsets`` most contact onsets of one pair; ``max_slip`` largest
    |x displacement| [m] of a domino's front bottom edge (its pivot) when it strikes the
    next one; ``max_overlap`` deepest overlap between two dominoes [m].
    """

    arrival: np.ndarray
    speed: float
    reached: int
    wall_s: float
    sim_s: float
    recontacts: int
    max_onsets: int
    max_slip: float
    max_overlap: float


def _pivot_x(data, k: int) -> float:
    """x [m] of the front bottom edge's midpoint of domino ``k`` (body k + 1)."""
    r = data.xmat[k + 1].reshape(3, 3)
    return float(data.xpos[k + 1, 0] + r[0] @ np.array([THICKNESS / 2, 0.0, -HEIGHT / 2]))


def _front_gap(data, k: int) -> float:
    """Gap [m] from the top front edge of domino ``k`` to the back face of domino ``k+1``.

    Positive while the edge is behind the face's plane; negative once it has crossed it
    (the boxes overlap there).
    """
    r0, r1 = data.xmat[k + 1].reshape(3, 3), data.xmat[k + 2].reshape(3, 3)
    normal = r1[:, 0]  # the next domino's +x axis (its back face looks along -normal)
    face = data.xpos[k + 2] - normal * (THICKNESS / 2)
    edge = data.xpos[k + 1] + r0 @ np.array([THICKNESS / 2, 0.0, HEIGHT / 2])
    half_edge = r0[:, 1] * (WIDTH / 2)
    return float(min(normal @ (face - edge - half_edge), normal @ (face - edge + half_edge)))


def run_chain(
    n: int,
    gap: float,
    mu_dd: float,
    mu_floor: float,
    dt: float,
    fit_from: int = 10,
    t_max: float = 5.0,
    stall: float = 0.5,
    solref_tc: float = 0.002,
) -> ChainRun:
    """Build, settle, push and run one chain until its last domino is struck.

    ``gap`` [m] clear gap, ``mu_dd``/``mu_floor`` friction coefficients [-], ``dt`` time
    step [s], ``fit_from`` first domino of the speed fit, ``t_max`` [s] simulated-time
    limit, ``stall`` [s] simulated time without a new arrival after which the wave counts
    as stopped, ``solref_tc`` [s] the contacts' time constant.
    """
    model = mujoco.MjModel.from_xml_string(chain_mjcf(n, gap, mu_dd, mu_floor, dt, solref_tc))
    data = mujoco.MjData(model)
    for _ in range(round(SETTLE_S / dt)):
        mujoco.mj_step(model, data)
    data.time = 0.0
    data.qvel[:] = 0.0
    # push: omega about +y through domino 0's front bottom edge (free joint: linear
    # velocity of the body origin in world axes, angular velocity in body axes; the
    # settled domino is upright to ~1e-9 rad, so body axes = world axes)
    omega = math.sqrt(G / HEIGHT)
    centre = data.xpos[1].copy()
    edge = np.array([_pivot_x(data, 0), centre[1], centre[2] - HEIGHT / 2])
    w = np.array([0.0, omega, 0.0])
    data.qvel[0:3] = np.cross(w, centre - edge)
    data.qvel[3:6] = w
    mujoco.mj_forward(model, data)

    pitch = gap + THICKNESS
    pivot0 = np.array([k * pitch + THICKNESS / 2 for k in range(n)])
    arrival = np.full(n, np.nan)
    arrival[0] = 0.0
    onsets = np.zeros(n - 1, dtype=int)
    touching = np.zeros(n - 1, dtype=bool)
    slip = np.zeros(n)
    max_overlap = 0.0
    last_arrival, remaining = 0.0, n - 1
    front = 0  # pair (front, front + 1): the next first contact of the wave
    gap_prev = _front_gap(data, front)
    t0 = time.perf_counter()
    while data.time < t_max:
        mujoco.mj_step(model, data)
        gap_now = _front_gap(data, front) if front < n - 1 else math.nan
        now = np.zeros(n - 1, dtype=bool)
        if data.ncon:
            geom = data.contact.geom
            a, b = geom.min(axis=1), geom.max(axis=1)
            nb = (a >= 1) & (b - a == 1)
            if nb.any():
                now[a[nb] - 1] = True
                max_overlap = max(max_overlap, -float(data.contact.dist[nb].min()))
        new = now & ~touching
        if new.any():
            onsets += new
            for k in np.flatnonzero(new & np.isnan(arrival[1:])):
                arrival[k + 1] = data.time
                if k == front and gap_prev > 0 > gap_now:  # locate the crossing in the step
                    arrival[k + 1] -= model.opt.timestep * gap_now / (gap_now - gap_prev)
                slip[k] = _pivot_x(data, k) - pivot0[k]
                last_arrival, remaining = data.time, remaining - 1
        touching = now
        if front < n - 1 and not np.isnan(arrival[front + 1]):
            front = int(np.flatnonzero(np.isnan(arrival))[0]) - 1 if remaining else n - 1
            gap_now = _front_gap(data, front) if front < n - 1 else math.nan
        gap_prev = gap_now
        if remaining == 0 or data.time - last_arrival > stall:
            break
    wall = time.perf_counter() - t0
    x = pitch * np.arange(n)
    fit = speed_from(arrival, x, fit_from)
    struck = ~np.isnan(arrival[1:])
    return ChainRun(
        arrival=arrival,
        speed=fit.speed,
        reached=reached_count(arrival),
        wall_s=wall,
        sim_s=float(data.time),
        recontacts=int((onsets > 1).sum()),
        max_onsets=int(onsets.max(initial=0)),
        max_slip=float(np.abs(slip[:-1][struck]).max(initial=0.0)),
        max_overlap=max_overlap,
    )


def describe(run: ChainRun, n: int) -> str:
    """One line of diagnostics of ``run`` (a chain of ``n`` dominoes)."""
    stop = "" if run.reached == n else f"  WAVE STOPPED after {run.reached} dominoes"
    return (
        f"reached {run.reached}/{n}, t_end {run.sim_s:.3f} s, re-contacting pairs "
        f"{run.recontacts} (max onsets {run.max_onsets}), max pivot slip "
        f"{run.max_slip * 1e3:.3f} mm, max overlap {run.max_overlap * 1e3:.3f} mm{stop}"
    )


def row(gap, mu_dd, mu_floor, dt, n, speed, wall) -> dict:
    """A CSV row (SI units)."""
    return {
        "gap_m": f"{gap:.6g}",
        "friction_dominoes": f"{mu_dd:.6g}",
        "friction_floor": f"{mu_floor:.6g}",
        "dt_s": f"{dt:.6g}",
        "n": n,
        "speed_m_s": f"{speed:.6g}",
        "wall_s": f"{wall:.4g}",
    }


def _floats(text: str) -> list[float]:
    return [float(v) for v in text.split(",") if v.strip()]


def main(argv: list[str] | None = None) -> None:
    """Run the grid, the dt-convergence series and the standard chain; write the CSV."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="benchmarks/mujoco_chain.csv", help="CSV to write")
    ap.add_argument("--n", type=int, default=30, help="dominoes in the grid chains")
    ap.add_argument("--dt", type=float, default=2e-4, help="time step of the grid [s]")
    ap.add_argument("--gaps-mm", type=_floats, default=[9.38, 15.09, 25.0], help="gaps [mm]")
    ap.add_argument("--mu-dd", type=_floats, default=[0.0, 0.3, 0.525], help="domino friction")
    ap.add_argument("--mu-floor", type=float, default=1.0, help="floor friction of the grid")
    ap.add_argument("--dts", type=_floats, default=[1e-3, 5e-4, 2e-4, 1e-4], help="dt list [s]")
    ap.add_argument("--conv-gap-mm", type=float, default=9.38, help="gap of the dt series")
    ap.add_argument("--conv-mu-dd", type=float, default=0.3, help="friction of the dt series")
    ap.add_argument("--fit-from", type=int, default=10, help="first domino of the speed fit")
    ap.add_argument("--repeat", type=int, default=3, help="runs of the standard chain")
    ap.add_argument("--t-max", type=float, default=5.0, help="simulated-time limit [s]")
    ap.add_argument("--stall", type=float, default=0.5, help="no-arrival time = stopped [s]")
    ap.add_argument("--solref-tc", type=float, default=0.002, help="contact time const [s]")
    ap.add_argument("--tcs", type=_floats, default=[0.02, 0.005, 0.002, 0.001], help="tc [s]")
    ap.add_argument("--tc-dt", type=float, default=1e-4, help="dt of the tc series [s]")
    ap.add_argument("--skip-grid", action="store_true")
    ap.add_argument("--skip-conv", action="store_true")
    ap.add_argument("--skip-standard", action="store_true")
    ap.add_argument("--skip-stiffness", action="store_true")
    args = ap.parse_args(argv)
    kw = {"fit_from": args.fit_from, "t_max": args.t_max, "stall": args.stall}
    kw["solref_tc"] = args.solref_tc
    print(f"MuJoCo {mujoco.__version__}, solref = {args.solref_tc:g} 1 (default solimp)")
    rows = []

    if not args.skip_grid:
        print(f"\ngrid: N={args.n}, dt={args.dt:g} s, friction_floor={args.mu_floor:g}")
        for gap_mm in args.gaps_mm:
            for mu in args.mu_dd:
                r = run_chain(args.n, gap_mm / 1e3, mu, args.mu_floor, args.dt, **kw)
                rows.append(
                    row(gap_mm / 1e3, mu, args.mu_floor, args.dt, args.n, r.speed, r.wall_s)
                )
                print(
                    f"  gap {gap_mm:6.2f} mm  mu_dd {mu:5.3f}: v = {r.speed:.4f} m/s, "
                    f"wall {r.wall_s:.2f} s; {describe(r, args.n)}"
                )

    if not args.skip_conv:
        gap = args.conv_gap_mm / 1e3
        print(
            f"\ndt convergence: N={args.n}, gap {args.conv_gap_mm:g} mm, mu_dd "
            f"{args.conv_mu_dd:g}, mu_floor {args.mu_floor:g}"
        )
        ref = None
        for dt in sorted(args.dts, reverse=True):
            r = run_chain(args.n, gap, args.conv_mu_dd, args.mu_floor, dt, **kw)
            rows.append(row(gap, args.conv_mu_dd, args.mu_floor, dt, args.n, r.speed, r.wall_s))
            ref = r.speed if ref is None else ref
            print(
                f"  dt {dt:8.1e} s: v = {r.speed:.5f} m/s ({100 * (r.speed / ref - 1):+.2f} % "
                f"vs the largest dt), wall {r.wall_s:.2f} s; {describe(r, args.n)}"
            )

    if not args.skip_stiffness:
        gap = args.conv_gap_mm / 1e3
        print(
            f"\ncontact stiffness (printed only): N={args.n}, gap {args.conv_gap_mm:g} mm, "
            f"mu_dd {args.conv_mu_dd:g}, mu_floor {args.mu_floor:g}, dt {args.tc_dt:g} s"
        )
        for tc in args.tcs:
            kw_tc = {**kw, "solref_tc": tc}
            r = run_chain(args.n, gap, args.conv_mu_dd, args.mu_floor, args.tc_dt, **kw_tc)
            print(
                f"  solref {tc:6.4f} 1: v = {r.speed:.5f} m/s, wall {r.wall_s:.2f} s; "
                f"{describe(r, args.n)}"
            )

    if not args.skip_standard:
        n, gap, mu = 40, 9.38e-3, 0.3
        runs = [run_chain(n, gap, mu, mu, args.dt, **kw) for _ in range(args.repeat)]
        wall = statistics.median(r.wall_s for r in runs)
        speeds = {f"{r.speed:.9g}" for r in runs}
        rows.append(row(gap, mu, mu, args.dt, n, runs[0].speed, wall))
        print(
            f"\nstandard chain: N={n}, gap 9.38 mm, mu_dd = mu_floor = 0.3, dt {args.dt:g} s: "
            f"v = {runs[0].speed:.4f} m/s (runs give {len(speeds)} distinct value(s)), "
            f"wall median of {len(runs)} = {wall:.3f} s "
            f"({', '.join(f'{r.wall_s:.3f}' for r in runs)}); {describe(runs[0], n)}"
        )

    with open(args.out, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=FIELDS)
        writer.writeheader()
        writer.writerows(rows)
    print(f"\nwrote {len(rows)} rows to {args.out}")


if __name__ == "__main__":
    main()
