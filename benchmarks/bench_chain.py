"""Speed of the DEM domino chain against YADE 2023.02a, one thread each.

Cases (2D, s/l = 0.1 -> 10 spheres per domino, k/k* = 1e4, d/l = 0.4, two-sphere base
and no holding so that YADE runs the identical scene without Python callbacks):

* paper -- N = 30, run to the last domino's first contact;
* large -- N = 300, the same number of steps per domino.

For each: the number of steps S to the last collision (from a recorded dominowave run);
dominowave engines-only (event log, pair statistics and energy ledger off, no trajectory:
what YADE's engines do by default) for S steps; the same with the energy ledger; with
event recording (log + pair statistics + trajectory every 100 steps + ledger, a real run);
YADE engines-only (``yade -n -j1``, O.run(S) timed inside YADE, no PyRunner; median of
--repeat runs for the paper case, one for the large one) of the identical scene with each
of the collider settings in compare_yade.COLLIDERS (YADE's defaults, and targetInterv = 0:
the faster one differs between the cases), the ratio taken against the faster; the
profile split of bench_engine.py (contact detection, forces, integration) on the chain's
state.

Run:  python benchmarks/bench_chain.py [--repeat 3] [--large-n 300]
      python benchmarks/bench_chain.py --interleave 7 [--whole]  (alternating pairs, ratios)
      python benchmarks/bench_chain.py --trace 300      (our cost per step along a run)
YADE is skipped if not installed.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import shutil
import sys
import time
from pathlib import Path

import numpy as np

from dominowave.chain.build import ChainParams
from dominowave.chain.scenario import DominoChain

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "yade"))


def _load(name, path):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


bench_engine = _load("bench_engine", HERE / "bench_engine.py")
compare_yade = _load("compare_yade", HERE / "yade" / "compare_yade.py")


def case(n_dominoes: int) -> DominoChain:
    p = ChainParams(n_dominoes=n_dominoes, d_over_l=0.4, base="two", held=False)
    return DominoChain(p)


def steps_to_last_collision(chain: DominoChain) -> int:
    """Steps until the last domino's first contact, from a recorded run."""
    run = chain.run()
    if not run.reached_all:
        raise RuntimeError("the wave did not reach the last domino")
    return int(np.ceil(run.arrival[-1] / chain.dt))


MODES = {
    # name: (event log + pair statistics + trajectory, energy ledger)
    "engines": (False, False),  # what YADE's engines do by default (no trackEnergy)
    "ledger": (False, True),
    "recording": (True, True),  # a real chain run
}


def time_ours(chain: DominoChain, steps: int, mode: str, repeat: int) -> float:
    record, ledger = MODES[mode]
    push = chain.resolve(None)
    times = []
    for _ in range(repeat):
        sim, _ = chain.build(push, record=record, track_energy=ledger)
        start = time.perf_counter()
        sim.run(n_steps=steps, trajectory_every=100 if record else 0)
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def time_yade(chain: DominoChain, steps: int, collider: str) -> float:
    """YADE engines-only wall time [s] of the identical scene (chain_yade.py) with the
    collider settings ``compare_yade.COLLIDERS[collider]``."""
    scene = compare_yade.scene_dict(chain, chain.resolve(None), "engines", steps)
    scene["collider"] = compare_yade.COLLIDERS[collider]
    return float(compare_yade.run_yade(scene)["wall_time"])


def interleaved(chain: DominoChain, steps: int, pairs: int) -> dict:
    """``pairs`` rounds of engines-only runs, alternating ours and YADE with each collider
    setting: the per-round ratio (the faster YADE run over ours) does not suffer from the
    VM's speed drifting between blocks of runs."""
    time_ours(chain, 100, "engines", 1)  # compile / warm up
    ours, yade = [], {name: [] for name in compare_yade.COLLIDERS}
    for _ in range(pairs):
        ours.append(time_ours(chain, steps, "engines", 1))
        for name in compare_yade.COLLIDERS:
            yade[name].append(time_yade(chain, steps, name))
    fastest = np.min([yade[name] for name in yade], axis=0)
    ratios = fastest / np.array(ours)
    return {
        "n_dominoes": len(chain.positions),
        "steps": steps,
        "ours_s": ours,
        "yade_s": yade,
        "ratios": ratios.tolist(),
        "median_ratio": float(np.median(ratios)),
    }


def cost_trace(chain: DominoChain, steps: int, chunk: int = 20_000) -> None:
    """Engines-only cost per step along one run, with the contact counts that drive it."""
    sim, _ = chain.build(chain.resolve(None), record=False, track_energy=False)
    sim.run(n_steps=10)  # compile / warm up
    done = 10
    while done < steps:
        builds = sim.rec.n_rebuilds[0]
        start = time.perf_counter()
        sim.run(n_steps=chunk)
        elapsed = time.perf_counter() - start
        done += chunk
        c = sim.contacts
        n = int(c.n[0])
        active = c.overlap[:n] > 0.0
        print(
            f"step {done}: {elapsed / chunk * 1e6:.1f} us/step, a list build every "
            f"{chunk / max(1, sim.rec.n_rebuilds[0] - builds):.0f} steps, {n} candidate "
            f"pairs, {active.sum()} active ({np.sum(active & (c.j[:n] < 0))} on the floor), "
            f"{sim.spheres.n_listed[0]} listed spheres",
            flush=True,
        )


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--large-n", type=int, default=300)
    ap.add_argument(
        "--interleave",
        type=int,
        default=0,
        metavar="K",
        help="only the interleaved comparison: K alternating pairs at N = 30 (full run) "
        "and max(1, K // 2) at --large-n (first 40 000 steps, or --whole)",
    )
    ap.add_argument(
        "--whole",
        action="store_true",
        help="with --interleave: the large case over the paper case's steps per domino "
        "(the whole run, minutes per YADE run) instead of its first 40 000 steps",
    )
    ap.add_argument(
        "--trace",
        type=int,
        default=0,
        metavar="N",
        help="only the engines-only cost per step along one run of N dominoes (steps of the "
        "paper case scaled per domino), with its contact counts",
    )
    args = ap.parse_args(argv)
    if args.trace:
        paper_steps = steps_to_last_collision(case(30))
        cost_trace(case(args.trace), paper_steps * args.trace // 30)
        return 0
    have_yade = shutil.which("yade") is not None
    if args.interleave:
        if not have_yade:
            raise SystemExit("--interleave needs YADE (yade not found)")
        paper = case(30)
        steps = steps_to_last_collision(paper)
        print(json.dumps(interleaved(paper, steps, args.interleave)), flush=True)
        large = case(args.large_n)
        large_steps = steps * args.large_n // 30 if args.whole else 40_000
        print(json.dumps(interleaved(large, large_steps, max(1, args.interleave // 2))), flush=True)
        return 0
    rows = []
    for name, n in (("paper", 30), ("large", args.large_n)):
        chain = case(n)
        if name == "paper":
            steps = steps_to_last_collision(chain)
            steps_per_domino = steps / n
        else:
            steps = int(steps_per_domino * n)
        for mode in MODES:
            time_ours(chain, 100, mode, 1)  # compile / warm up
        bare = time_ours(chain, steps, "engines", args.repeat)
        ledger = time_ours(chain, steps, "ledger", args.repeat)
        rec = time_ours(chain, steps, "recording", args.repeat)
        # YADE: median of --repeat runs for the paper case, one run for the large one
        # (minutes each); the run-to-run spread of both codes on this shared VM is ~20 %
        n_yade = args.repeat if name == "paper" else 1
        yade = {c: float("nan") for c in compare_yade.COLLIDERS}
        if have_yade:
            for c in compare_yade.COLLIDERS:
                yade[c] = float(np.median([time_yade(chain, steps, c) for _ in range(n_yade)]))
        fastest = min(yade.values())

        def make(_n, record, chain=chain):
            return chain.build(chain.resolve(None), record=record)[0]

        prof = bench_engine.measure(make, n * chain.shape.radii.size, min(steps, 20000), 1)
        row = {
            "case": name,
            "n_dominoes": n,
            "spheres": n * chain.shape.radii.size,
            "steps": steps,
            "dt": chain.dt,
            "ours_engines_s": bare,
            "ours_ledger_s": ledger,
            "ours_recording_s": rec,
            "recording_overhead": rec / bare,
            "yade_engines_s": yade,
            "yade_fastest_s": fastest,
            "speedup_vs_yade": fastest / bare,
            "us_detect": prof["us_detect"],
            "us_forces": prof["us_forces"],
            "us_integrate": prof["us_integrate"],
        }
        rows.append(row)
        print(json.dumps(row))
        sys.stdout.flush()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
