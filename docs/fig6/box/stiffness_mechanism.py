"""Why a box chain slows down as its contacts stiffen: measured, pair by pair.

For the 2D box chain of Fig 6 (30 dominoes, d/l given, member 0 of the Fig 6 seeds: push
``sqrt(g/l) (1 + 1e-3 N(0,1))``), at each k/k*, this measures over the interior pairs
(dominoes 10-27, the tail of the wave):

* the tail speed (last 10 pitches) [m/s];
* the first collision of each pair (n, n+1): its duration against eq 31's T_c, the
  number of separate hits of n on n+1 before the wave reaches n+2, and the raw contact
  onsets of the pair over the whole run;
* the angular velocity the struck domino carries away from its first collision,
  ``Omega_{n+1}`` (at the end of the collision) over the striker's ``Omega_fn`` at the
  onset (the transfer ratio; eq 3's f_+ for the rigid, hinged, elastic pair), and the
  rebound ratio ``Omega_bn / Omega_fn``;
* the base of the struck domino: its horizontal speed at the end of the collision over
  its top's (0 = it pivots, > 0 it slides forward), the base slip over the whole run;
* the mechanical energy (kinetic + potential) of all dominoes just before and just
  after each first collision: the energy lost per collision, over the striker's
  kinetic energy at the onset.

The same with a floor friction of 10 (no base slip: a causal test of the floor's
part), and the rod model of the package (hinged rigid blocks with the box's mass, size
and pair stiffness, frictionless geometric contacts, no floor slip:
``dominowave.chain.theory_vs_rods.paper_chain(mass_model="block")``) at the same k/k*.

Run: ``python docs/fig6/box/stiffness_mechanism.py [--d-over-l 0.4] [--out CSV]``
"""

from __future__ import annotations

import argparse
import csv
import math
import time
from pathlib import Path

import numpy as np

from dominowave.chain import DominoChain
from dominowave.chain.compare import theory_collision_time
from dominowave.chain.paper_fig6 import fig6_params
from dominowave.chain.scenario import member_push_factor
from dominowave.chain.theory_vs_rods import paper_chain
from dominowave.rods import first_collisions, simulate

TAIL = 10
PAIRS = slice(10, 27)
"""Interior pairs (n, n+1) measured: away from the push and from the chain's end."""


def box_energy(p, rec, frame: int) -> float:
    """Kinetic + potential energy of all dominoes at ``frame`` [J] (2D: rotation about y)."""
    m = p.mass
    s, l = p.thickness, p.height
    i_cm = m * (s * s + l * l) / 12.0  # uniform cuboid about its centre, axis y
    v = rec.velocity[frame]
    w = rec.angular_velocity[frame][:, 1]
    z = rec.com[frame][:, 2]
    return float(np.sum(0.5 * m * (v**2).sum(axis=1) + 0.5 * i_cm * w**2 + m * p.g * z))


def measure_box(d_over_l: float, ratio: float, friction_floor: float | None = None) -> dict:
    """Measurements of member 0 of the 2D box chain at k/k* = ``ratio``."""
    p = fig6_params("2d", d_over_l, 30, "box").with_(stiffness_ratio=ratio)
    if friction_floor is not None:
        p = p.with_(friction_floor=friction_floor)
    t_c = theory_collision_time(p)
    chain = DominoChain(p, frame_interval=t_c / 10.0, sleep=False)  # (as measured: awake)
    push = chain.resolve(None).scaled(member_push_factor(0, 0, 1e-3))
    start = time.process_time()
    run = chain.run(push, keep_record=True)
    rec, ev = run.record, run.events
    times = rec.times
    n_idx = np.arange(p.n_dominoes)[PAIRS]
    onset = ev.arrival[n_idx + 1]
    end = ev.first_hit_end[n_idx]
    f_on = np.searchsorted(times, onset) - 1  # last frame before the onset
    f_off = np.searchsorted(times, end)  # first frame after the end
    w = rec.angular_velocity[:, :, 1]  # forward toppling (top towards +x) is +y
    omega_f = w[f_on, n_idx]
    omega_b = w[f_off, n_idx]
    omega_next = w[f_off, n_idx + 1]
    # the struck domino's base (front bottom edge) and top velocity at the end of the hit
    base = rec.velocity[f_off, n_idx + 1, 0] + w[f_off, n_idx + 1] * (-p.height / 2)
    top = rec.velocity[f_off, n_idx + 1, 0] + w[f_off, n_idx + 1] * (p.height / 2)
    i_cm = p.mass * (p.thickness**2 + p.height**2) / 12.0
    v_f = rec.velocity[f_on, n_idx]
    ke_striker = 0.5 * p.mass * (v_f**2).sum(axis=1) + 0.5 * i_cm * omega_f**2
    lost = np.array(
        [box_energy(p, rec, a) - box_energy(p, rec, b) for a, b in zip(f_on, f_off, strict=True)]
    )
    # the fall of the struck domino n+1 from the end of its first hit to its own hit
    # on n+2: the gain of angular velocity, how far its base slides, how long the
    # striker n stays in contact with it
    f_next = np.searchsorted(times, ev.arrival[n_idx + 2]) - 1
    gain = w[f_next, n_idx + 1] / omega_next
    tilt = 2.0 * np.arctan2(rec.quat[:, :, 2], rec.quat[:, :, 0])  # rotation about y
    base_x = rec.com[:, :, 0] - 0.5 * p.height * np.sin(tilt)
    flight_slip = base_x[f_next, n_idx + 1] - base_x[f_off, n_idx + 1]
    touching = np.array(
        [_contact_fraction(rec, n, end[k], ev.arrival[n + 2]) for k, n in enumerate(n_idx)]
    )
    tail = TAIL * p.pitch / (run.arrival[-1] - run.arrival[-1 - TAIL])
    return {
        "model": "box" if friction_floor is None else f"box, floor friction {friction_floor:g}",
        "k_over_kstar": ratio,
        "tail_speed": tail,
        "fitted_speed": run.wave.speed,
        "theory_T_c": t_c,
        "collision_time": float(np.median(end - onset)),
        "hits_in_passage": float(np.mean(ev.n_hits_in_passage[n_idx])),
        "contacts_per_pair": float(np.mean(ev.n_contacts_on_next[n_idx])),
        "transfer": float(np.median(omega_next / omega_f)),
        "rebound": float(np.median(omega_b / omega_f)),
        "omega_f": float(np.median(omega_f)),
        "base_over_top": float(np.median(base / top)),
        "mean_abs_slip": float(np.mean(np.abs(ev.slip_final[n_idx]))),
        "energy_lost_per_hit": float(np.median(lost / ke_striker)),
        "fall_gain": float(np.median(gain)),
        "fall_base_slip": float(np.median(flight_slip)),
        "fall_touching": float(np.median(touching)),
        "cpu_time": time.process_time() - start,
    }


def _contact_fraction(rec, n: int, t0: float, t1: float) -> float:
    """Fraction of ``[t0, t1]`` during which dominoes n and n+1 touch (contact log)."""
    on = rec.ev_kind == 1
    pair = (rec.ev_i == n) & (rec.ev_j == n + 1)
    starts, ends = rec.ev_time[pair & on], rec.ev_time[pair & ~on]
    ends = np.concatenate([ends, [rec.end_time] * (starts.size - ends.size)])
    overlap = np.clip(np.minimum(ends, t1) - np.maximum(starts, t0), 0.0, None)
    return float(overlap.sum() / (t1 - t0))


def measure_rods(d_over_l: float, ratio: float, omega: float) -> dict:
    """The rod model (hinged blocks, no slip) with the box's m, l, s and pair spring."""
    p = fig6_params("2d", d_over_l, 30, "box").with_(stiffness_ratio=ratio)
    chain = paper_chain(
        d_over_l, ratio, 30, mass_model="block", s_over_l=p.thickness / p.height,
        l=p.height, m=p.mass,
    )  # fmt: skip
    assert math.isclose(chain.k, p.pair_stiffness, rel_tol=1e-12)
    start = time.process_time()
    run = simulate(chain, omega)
    col = first_collisions(run)
    n = np.arange(30)[PAIRS]
    tail = TAIL * chain.pitch / (run.arrival[-1] - run.arrival[-1 - TAIL])
    return {
        "model": "rods (hinged blocks)",
        "k_over_kstar": ratio,
        "tail_speed": tail,
        "fitted_speed": math.nan,
        "theory_T_c": theory_collision_time(p),
        "collision_time": float(np.median(col.duration[n])),
        "hits_in_passage": math.nan,
        "contacts_per_pair": float(np.mean(col.n_contacts[n])),
        "transfer": float(np.median(col.transfer[n])),
        "rebound": float(np.median(col.rebound_ratio[n])),
        "omega_f": float(np.median(col.omega_f[n])),
        "base_over_top": 0.0,
        "mean_abs_slip": 0.0,
        "energy_lost_per_hit": math.nan,
        "fall_gain": float(np.median(col.omega_f[n + 1] / col.omega_next[n])),
        "fall_base_slip": 0.0,
        "fall_touching": math.nan,
        "cpu_time": time.process_time() - start,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--d-over-l", type=float, default=0.4)
    ap.add_argument("--ratios", default="1e3,1e4,1e5")
    ap.add_argument("--out", type=Path)
    args = ap.parse_args()
    ratios = [float(x) for x in args.ratios.split(",")]
    rows = []
    for ratio in ratios:
        rows.append(measure_box(args.d_over_l, ratio))
        print(rows[-1], flush=True)
    for ratio in ratios:
        rows.append(measure_box(args.d_over_l, ratio, friction_floor=10.0))
        print(rows[-1], flush=True)
    p = fig6_params("2d", args.d_over_l, 30, "box")
    omega = DominoChain(p).resolve(None).scaled(member_push_factor(0, 0, 1e-3)).omega
    for ratio in ratios:
        rows.append(measure_rods(args.d_over_l, ratio, omega))
        print(rows[-1], flush=True)
    if args.out:
        with args.out.open("w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=["d_over_l", *rows[0]])
            writer.writeheader()
            writer.writerows({"d_over_l": args.d_over_l} | r for r in rows)


if __name__ == "__main__":
    main()
