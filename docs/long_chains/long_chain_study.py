"""Long chains and wide spacings of the paper's clump chain (docs/long_chains.md).

Two studies of the 2D (and 3D) clump chain of Fig 6 (s/l = 0.1, phi_f = 0.3, phi_d = 0,
no damping, held until touched; the configurations of ``dominowave.chain.paper_fig6``),
each member pushed by ``omega = sqrt(g/l) (1 + 1e-3 N(0, 1))`` from
``numpy.random.default_rng([0, member])`` (the ``DominoChain.ensemble`` rule, so member m of
a 30-domino chain is member m of ``dominowave paper-fig6``). Speeds are v / sqrt(g l).

* ``long``: chains of N = 300 dominoes. Per member: the settled-region fit of
  ``steady_speed`` (the default of ``ensemble``), block speeds (least-squares fits over
  dominoes 10-29, 30-99, 100-199, 200-299: how the front speed evolves along the chain),
  the theory's transient over the same blocks (eqs 8, 12, 19, pushed like the member),
  eq 34 (clump mapping), and the share of neighbour pairs hit more than once before the
  wave reaches the next domino (Fig 6E).
* ``wide``: 30-domino chains at d/l = 0.6 .. 0.95 for several floor frictions, 2D and 3D.
  Per member: how many dominoes the wave toppled in order, the Fig 5A mechanism of every
  struck domino right after its first hit (chain.events), members with a backward fall
  (mechanism III and a backward lean of 60-150 deg), the height at which the striker's
  top meets the next domino, and the mechanism the theory's section 2.4 predicts
  (``theory.bounds.classify_regime`` with the peak force of eq 37, clump mass and k_n).

Rows are appended to ``runs.jsonl`` (next to this script) the moment a member ends; a
re-run skips the members already there (a killed study loses at most one member).
``--report`` writes the tables from ``runs.jsonl``; ``--diagnose`` re-runs the members
whose wide-spacing wave stopped and says where and how.

    S=docs/long_chains/long_chain_study.py
    nice -n 15 python $S long --configs 2d,mu2,damp_small,k1e3 --members 3   # N = 300
    nice -n 15 python $S wide --models 2d,3d --phi 0.3,0.6,1.0 --members 8    # N = 30
    nice -n 15 python $S long --configs box,box_3d --members 3              # box dominoes
    nice -n 15 python $S long --configs box_k1e3,box_k1e5 --members 3       # box stiffness
    python $S --report --figure docs/long_chains/speed_along_chain.png \\
        > docs/long_chains/long_chain_study.txt
    nice -n 15 python $S --diagnose --models 2d,3d > docs/long_chains/stopped_waves.txt

(every command of the committed results: docs/long_chains.md).

Chain shapes: the studies take every chain from ``CHAINS`` below, a name -> ChainParams
changes table; ``box`` and ``box_3d`` are chains of the rounded-cuboid dominoes
(docs/shape.md) with the clump chain's other parameters. One process, no pool (the
machine is shared).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

from dominowave.chain.paper_fig6 import CONFIGS

RUNS = Path(__file__).with_name("runs.jsonl")
BLOCKS = ((10, 29), (30, 99), (100, 199), (200, 299))  # dominoes first..last of a block fit
BACKWARD_LEAN = (math.radians(60), math.radians(150))

CHAINS: dict[str, dict] = {
    **{name: CONFIGS[name] for name in ("2d", "3d", "3d_asym", "k1e3", "k1e5", "damp_small")},
    "mu2": {"friction_floor": 2.0},
    "s19": {"spheres_per_column": 19},
    "2d_phid": {"friction_dominoes": 0.5},
    "3d_phid": {"model": "3d", "friction_dominoes": 0.5},
    "box": {"shape": "box", "held": False},
    "box_3d": {"shape": "box", "model": "3d", "held": False},
    "box_k1e3": {"shape": "box", "stiffness_ratio": 1e3, "held": False},
    "box_k1e5": {"shape": "box", "stiffness_ratio": 1e5, "held": False},
}
"""Chain name -> ``ChainParams`` changes from the Fig 6 base chain (paper_fig6.CONFIGS)."""


def chain_params(name: str, d_over_l: float, n: int, phi_f: float | None = None):
    """The ``ChainParams`` of chain ``name`` at gap ``d/l`` with ``n`` dominoes."""
    from dominowave.chain import ChainParams

    extra = {} if phi_f is None else {"friction_floor": phi_f}
    return ChainParams(n_dominoes=n, d_over_l=d_over_l, **CHAINS[name], **extra)


def _run(params, member: int, keep_record: bool):
    from dominowave.chain import DominoChain
    from dominowave.chain.scenario import member_push_factor

    chain = DominoChain(params, sleep=False)  # (as the data were measured: awake)
    push = chain.resolve(None).scaled(member_push_factor(0, member, 1e-3))
    return chain, chain.run(push, keep_record=keep_record)


def long_member(name: str, d_over_l: float, n: int, member: int) -> dict:
    """One member of the long-chain study (speeds in m/s, times in s)."""
    from dominowave.chain.compare import theory_first_contacts
    from dominowave.chain.wave import fit_speed

    chain, run = _run(chain_params(name, d_over_l, n), member, keep_record=False)
    theory = theory_first_contacts(chain.params, run.omega_1)
    blocks, blocks_theory = [], []
    for first, last in BLOCKS:
        ok = last < n and np.all(np.isfinite(run.arrival[first : last + 1]))
        blocks.append(fit_speed(run.arrival, chain.positions, first, last).speed if ok else None)
        ok_t = last < n
        blocks_theory.append(
            fit_speed(theory, chain.positions, first, last).speed if ok_t else None
        )
    hits = run.events.n_hits_in_passage[1 : n - 2]
    sec = run.secondary
    return {
        "speed": _num(run.wave.speed),
        "speed_err": _num(run.wave.speed_err),
        "settled": bool(run.wave.settled),
        "first": run.wave.first,
        "reached": run.wave.reached,
        "eq34": run.theory_speed,
        "window_theory": _num(run.theory_window_speed),
        "blocks": blocks,
        "blocks_theory": blocks_theory,
        "multiple_hits": float(np.mean(hits > 1)),
        "hits_in_passage": [int(h) for h in run.events.n_hits_in_passage],
        "slip": [float(x) for x in run.events.slip_final],
        "mechanism": [int(c) for c in run.events.mechanism],
        "secondary_catching_up": bool(sec.catching_up) if sec else None,
        "secondary_merged_pair": sec.merged_pair if sec else None,
        "secondary_predicted_pair": _num(sec.predicted_pair) if sec else None,
        "secondary_lag": [_num(x) for x in sec.lag] if sec else None,
        "arrival": [_num(t) for t in run.arrival],
        "wall_time": run.wall_time,
    }


def wide_member(name: str, d_over_l: float, phi_f: float, n: int, member: int) -> dict:
    """One member of the wide-spacing study."""
    from dominowave.chain.events import forward_tilt, rotate_vectors

    _, run = _run(chain_params(name, d_over_l, n, phi_f), member, keep_record=True)
    ev, rec = run.events, run.record
    reached = run.wave.reached
    # height of the striker's top when it first touches the next domino [m]
    top = rec.com + rotate_vectors(rec.quat, rec.top_offset)
    tilt = forward_tilt(rec)
    hit_z, hit_tilt = [], []
    for k in range(1, n):
        if not np.isfinite(ev.arrival[k]):
            break
        f = min(int(np.searchsorted(rec.times, ev.arrival[k])), rec.times.size - 1)
        hit_z.append(float(top[f, k - 1, 2]))
        hit_tilt.append(float(tilt[f, k - 1]))
    lean = ev.max_backward
    backward = (ev.mechanism == 3) & (lean > BACKWARD_LEAN[0]) & (lean < BACKWARD_LEAN[1])
    backward[0] = False
    last = reached - 1  # the last domino the wave reached in order
    return {
        "speed": _num(run.wave.speed),
        "settled": bool(run.wave.settled),
        "reached": reached,
        "toppled": int(np.sum(np.isfinite(ev.topple_time))),
        "mechanism": [int(c) for c in ev.mechanism[1:reached]],
        "backward_falls": int(backward.sum()),
        "first_backward": int(np.argmax(backward)) if backward.any() else -1,
        "hit_z": hit_z,
        "hit_tilt": hit_tilt,
        "slip": [float(s) for s in ev.slip_final[:reached]],
        "last_mechanism": int(ev.mechanism[last]),
        "last_max_forward": float(ev.max_forward[last]),
        "last_toppled": bool(np.isfinite(ev.topple_time[last])),
        "eq34": run.theory_speed,
        "wall_time": run.wall_time,
    }


def theory_regime(name: str, d_over_l: float, phi_f: float) -> str:
    """Fig 5A regime of section 2.4 for this chain: peak force eq 37 (the domino's mass,
    clump or box, and its pair spring)."""
    from dominowave import theory
    from dominowave.chain.compare import beta_from_spacing

    p = chain_params(name, d_over_l, 30, phi_f)
    m = p.mass
    beta = beta_from_spacing(d_over_l)
    fm = theory.peak_contact_force(beta, p.height, m, p.pair_stiffness, p.g, "contact")
    cls = theory.classify_regime(beta, fm / (m * p.g), phi_f, p.thickness / p.height)
    return f"{cls.name.item()} (F_m/mg = {fm / (m * p.g):.0f})"


def _num(x) -> float | None:
    x = float(x)
    return x if math.isfinite(x) else None


def done_keys() -> set[str]:
    if not RUNS.exists():
        return set()
    return {json.loads(line)["key"] for line in RUNS.read_text().splitlines() if line.strip()}


def _round(x):
    """Floats to 7 significant digits (1 us on a 10 s arrival time): a smaller file."""
    if isinstance(x, float):
        return float(f"{x:.7g}")
    if isinstance(x, list):
        return [_round(v) for v in x]
    return x


def append(row: dict) -> None:
    with RUNS.open("a") as f:
        f.write(json.dumps({k: _round(v) for k, v in row.items()}) + "\n")


def run_study(args) -> None:
    from dominowave.cli import version_line

    done = done_keys()
    version = version_line()
    for name in args.configs.split(",") if args.part == "long" else args.models.split(","):
        for d in (float(x) for x in args.d_over_l.split(",")):
            for phi in (float(x) for x in args.phi.split(",")):
                for m in range(args.members):
                    if args.part == "long":
                        key = f"long/{name}/{d:g}/{args.n}/{m}"
                    else:
                        key = f"wide/{name}/{d:g}/{phi:g}/{args.n}/{m}"
                    if key in done:
                        continue
                    start = time.perf_counter()
                    try:
                        if args.part == "long":
                            row = long_member(name, d, args.n, m)
                        else:
                            row = wide_member(name, d, phi, args.n, m)
                    except RuntimeError as err:  # an aborted engine run: say so, go on
                        print(key, "ABORTED:", err, flush=True)
                        continue
                    row.update(
                        key=key,
                        wall=time.perf_counter() - start,
                        version=version,
                        utc=time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
                    )
                    append(row)
                    print(key, f"{row['wall']:.0f} s", flush=True)


# --- report -------------------------------------------------------------------------------
def _rows(prefix: str) -> list[dict]:
    if not RUNS.exists():
        return []
    rows = [json.loads(line) for line in RUNS.read_text().splitlines() if line.strip()]
    return [r for r in rows if r["key"].startswith(prefix)]


def _stats(values) -> str:
    v = np.array([x for x in values if x is not None], dtype=float)
    if v.size == 0:
        return "-"
    if v.size == 1:
        return f"{v[0]:.2f}"
    return f"{v.mean():.2f} +- {v.std(ddof=1) / math.sqrt(v.size):.2f}"


def _lags(group: list[dict]) -> str:
    """Median lag of the second contacts behind the first ones, per block of pairs [ms]."""
    lag = np.array([[np.nan if x is None else x for x in r["secondary_lag"]] for r in group])
    cells = []
    for first, last in ((1, 29), (30, 99), (100, 199), (200, lag.shape[1] - 1)):
        block = lag[:, first : last + 1]
        cells.append(f"{1e3 * np.nanmedian(block):.1f}" if np.isfinite(block).any() else "-")
    return " / ".join(cells)


def report_long() -> str:
    rows = _rows("long/")
    scale = math.sqrt(9.80665 * 0.05)
    out = [
        "## Long chains (N dominoes): v / sqrt(g l), ensemble mean +- standard error",
        "",
        "blocks: least-squares speed over dominoes 10-29 / 30-99 / 100-199 / 200-299;"
        " DEM (theory's transient for the same pushes).",
        "",
        "| chain | d/l | N | members (settled) | settled fit | from domino (median) "
        "| block 10-29 | block 30-99 | block 100-199 | block 200-299 | eq 34 "
        "| engine s/member |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    collisions = [
        "",
        "Collisions along the chain: multiple-hit pairs (pairs n, n+1 hit more than once"
        " before the wave reaches n+2) over pairs 1-29 / 30-299; mechanism II share and mean"
        " |base slip| over dominoes 1-298; the secondary (re-contact) wave: members whose lag"
        " behind the first contacts shrinks significantly, and the first pair where it has"
        " caught up (lag <= T_c; chain.wave.secondary_wave), and the median lag over"
        " members and pairs of each block.",
        "",
        "| chain | d/l | N | multiple hits 1-29 | multiple hits 30-299 | mechanism II "
        "| mean abs slip [cm] | secondary catching up | caught up at pair "
        "| re-contact lag [ms], pairs 1-29 / 30-99 / 100-199 / 200-298 |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    groups = sorted({tuple(r["key"].split("/")[1:4]) for r in rows})
    for name, d, n in groups:
        g = [r for r in rows if tuple(r["key"].split("/")[1:4]) == (name, d, n)]
        sp = [r["speed"] / scale if r["speed"] else None for r in g]
        settled = sum(r["settled"] for r in g)
        first = np.median([r["first"] for r in g if r["settled"]]) if settled else math.nan
        cells = []
        for b in range(len(BLOCKS)):
            dem = _stats([r["blocks"][b] / scale if r["blocks"][b] else None for r in g])
            th = [r["blocks_theory"][b] for r in g if r["blocks_theory"][b]]
            cells.append(f"{dem} ({np.mean(th) / scale:.2f})" if th else "-")
        out.append(
            f"| {name} | {d} | {n} | {len(g)} ({settled}) | {_stats(sp)} | {first:.0f} | "
            + " | ".join(cells)
            + f" | {g[0]['eq34'] / scale:.2f} | {np.mean([r['wall_time'] for r in g]):.0f} |"
        )
        if "hits_in_passage" not in g[0]:
            continue
        hits = np.array([r["hits_in_passage"] for r in g])
        mech = np.array([r["mechanism"][1:-1] for r in g])
        slip = np.array([r["slip"][1:-1] for r in g])
        merged = [r["secondary_merged_pair"] for r in g if r["secondary_merged_pair"] is not None]
        collisions.append(
            f"| {name} | {d} | {n} | {100 * np.mean(hits[:, 1:30] > 1):.0f} % | "
            f"{100 * np.mean(hits[:, 30:-2] > 1):.0f} % | {100 * np.mean(mech == 2):.0f} % | "
            f"{100 * np.mean(np.abs(slip)):.1f} | "
            f"{sum(bool(r['secondary_catching_up']) for r in g)}/{len(g)} | "
            f"{', '.join(str(m) for m in merged) or 'none'} | {_lags(g)} |"
        )
    return "\n".join(out + collisions)


def report_wide() -> str:
    rows = _rows("wide/")
    scale = math.sqrt(9.80665 * 0.05)
    out = [
        "## Wide spacing (N = 30): survival, Fig 5A mechanisms, hit height",
        "",
        "survived: the wave reached domino 29 in order; reached: median dominoes reached;"
        " mechanisms: shares of I / II / III / IV among struck dominoes right after their"
        " first hit; hit z / l: median height of the striker's top at the first touch;"
        " theory: the section 2.4 regime of the limit collision (eq 37).",
        "",
        "| model | d/l | phi_f | members | survived | reached (median, min) | speed of survivors "
        "| eq 34 | I / II / III / IV | backward falls | hit z / l | mean abs slip [cm] "
        "| theory (Fig 5A) |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    groups = sorted(
        {tuple(r["key"].split("/")[1:4]) for r in rows},
        key=lambda k: (k[0], float(k[1]), float(k[2])),
    )
    for name, d, phi in groups:
        g = [r for r in rows if tuple(r["key"].split("/")[1:4]) == (name, d, phi)]
        n = int(g[0]["key"].split("/")[4])
        reached = np.array([r["reached"] for r in g])
        survived = reached >= n
        mech = np.concatenate([r["mechanism"] for r in g]) if g else np.empty(0)
        shares = " / ".join(f"{100 * np.mean(mech == c):.0f}" for c in (1, 2, 3, 4))
        hz = np.concatenate([r["hit_z"] for r in g]) / 0.05
        sp = [
            r["speed"] / scale if (r["speed"] and ok) else None
            for r, ok in zip(g, survived, strict=True)
        ]
        out.append(
            f"| {name} | {d} | {phi} | {len(g)} | {survived.sum()} | {np.median(reached):.0f}, "
            f"{reached.min()} | {_stats(sp)} | {g[0]['eq34'] / scale:.2f} | {shares} % | "
            f"{sum(r['backward_falls'] > 0 for r in g)} | {np.median(hz):.2f} | "
            f"{100 * np.mean(np.abs(np.concatenate([r['slip'] for r in g]))):.1f} | "
            f"{theory_regime(name, float(d), float(phi))} |"
        )
    return "\n".join(out)


def diagnose(models: list[str]) -> str:
    """Re-run every wide-spacing member whose wave stopped (same machine: the same
    trajectory) and say where and how it stopped: the last domino reached (n_s), whether
    it toppled, its largest forward tilt, its Fig 5A mechanism, whether the wave had
    turned into the backward-toppling mode before, and, in 3D, how far the last two
    dominoes turned out of the plane of the chain (yaw about the vertical while tilted
    by less than 60 deg, roll of the long axis out of the chain's plane) [deg]."""
    from dominowave.chain.events import rotate_vectors

    rows = [
        r
        for r in _rows("wide/")
        if r["reached"] < int(r["key"].split("/")[4]) and r["key"].split("/")[1] in models
    ]
    out = [
        "## Where the wide-spacing waves stopped (members whose wave did not reach the end)",
        "",
        "| member | n_s | n_s toppled | max tilt n_s [deg] | mechanism n_s (n_s - 1) "
        "| first backward fall | hit z / l on n_s | max yaw n_s-1, n_s [deg] "
        "| max roll n_s-1, n_s [deg] |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for r in rows:
        _, name, d, phi, n, m = r["key"].split("/")
        _, run = _run(chain_params(name, float(d), int(n), float(phi)), int(m), True)
        rec, ev = run.record, run.events
        last = run.wave.reached - 1
        if run.wave.reached != r["reached"]:
            raise RuntimeError(f"{r['key']}: the re-run is not the stored run")
        normal = rotate_vectors(rec.quat, np.tile([1.0, 0.0, 0.0], (int(n), 1)))
        axis = rotate_vectors(rec.quat, rec.axis)
        # the face normal's horizontal direction against the chain's axis, while the
        # domino is tilted by less than 60 deg (lying down, its normal has no direction)
        yaw = np.degrees(np.arctan2(np.abs(normal[..., 1]), np.abs(normal[..., 0])))
        yaw = np.where(axis[..., 2] > 0.5, yaw, 0.0).max(axis=0)
        roll = np.degrees(np.abs(np.arcsin(np.clip(axis[..., 1], -1, 1)))).max(axis=0)
        pair = slice(max(last - 1, 0), last + 1)
        out.append(
            f"| {'/'.join((name, d, phi, m))} | {last} | {bool(np.isfinite(ev.topple_time[last]))}"
            f" | {np.degrees(ev.max_forward[last]):.0f} | {int(ev.mechanism[last])} "
            f"({int(ev.mechanism[last - 1])}) | {r['first_backward']} | "
            f"{r['hit_z'][-1] / 0.05:.2f} | "
            f"{', '.join(f'{x:.0f}' for x in yaw[pair])} | "
            f"{', '.join(f'{x:.0f}' for x in roll[pair])} |"
        )
    return "\n".join(out)


def figure(path: Path) -> None:
    """The front speed along the 300-domino chains (plots.long_chains) to ``path``."""
    from dominowave.chain.build import chain_positions
    from dominowave.chain.compare import theory_first_contacts
    from dominowave.chain.scenario import member_push_factor
    from dominowave.plots.long_chains import SpeedPanel, plot_speed_along_chain

    rows = _rows("long/")
    panels = []
    groups = {tuple(r["key"].split("/")[1:4]) for r in rows}
    spacings = {name: sum(g[0] == name for g in groups) for name, _, _ in groups}
    # chains run at every spacing first (one row each), the others after them
    for name, d, n in sorted(groups, key=lambda g: (-spacings[g[0]], g)):
        g = [r for r in rows if tuple(r["key"].split("/")[1:4]) == (name, d, n)]
        p = chain_params(name, float(d), int(n))
        omega = math.sqrt(p.g / p.height) * member_push_factor(0, 0, 1e-3)
        members = np.array([[np.nan if t is None else t for t in r["arrival"]] for r in g])
        panels.append(
            SpeedPanel(
                title=f"{name}, d/l = {d}, {len(g)} members",
                positions=chain_positions(p),
                members=members,
                theory=theory_first_contacts(p, omega),
                limit=g[0]["eq34"],
                scale=math.sqrt(p.g * p.height),
            )
        )
    plot_speed_along_chain(panels, path, window=10, ncols=2)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("part", nargs="?", choices=("long", "wide"))
    parser.add_argument("--report", action="store_true", help="print the tables of runs.jsonl")
    parser.add_argument("--figure", type=Path, help="--report also draws the long chains here")
    parser.add_argument(
        "--diagnose", action="store_true", help="re-run the stopped wide-spacing waves: where"
    )
    parser.add_argument("--configs", default="2d", help="long: chains of CHAINS")
    parser.add_argument("--models", default="2d,3d", help="wide, --diagnose: chains of CHAINS")
    parser.add_argument("--d-over-l", default=None)
    parser.add_argument("--phi", default=None, help="wide: floor frictions phi_f")
    parser.add_argument("--n", type=int, default=None, help="dominoes per chain")
    parser.add_argument("--members", type=int, default=3)
    args = parser.parse_args(argv)
    if args.report or args.diagnose:
        from dominowave.cli import version_line

        what = "report" if args.report else "stopped waves"
        print(f"# {version_line()}, {what} of runs.jsonl, {time.strftime('%d %b %Y %H:%M UTC')}")
        print()
    if args.report:
        print(report_long())
        print()
        print(report_wide())
        if args.figure:
            figure(args.figure)
    if args.diagnose:
        print(diagnose(args.models.split(",")))
    if args.report or args.diagnose:
        return
    if args.part is None:
        sys.exit("give a part (long or wide) or --report")
    if args.part == "long":
        args.d_over_l = args.d_over_l or "0.2,0.5"
        args.n = args.n or 300
        args.phi = "0.3"
    else:
        args.d_over_l = args.d_over_l or "0.6,0.7,0.8,0.9,0.95"
        args.n = args.n or 30
        args.phi = args.phi or "0.3,0.6,1.0"
    run_study(args)


if __name__ == "__main__":
    main()
