"""The box DEM under the assumptions of the rigid "leaning train" theory, for a comparison.

The leaning-train theory takes rigid dominoes, perfectly inelastic collisions between
them, bases that do not slip on the floor and Coulomb friction ``mu`` between dominoes.
This script runs the standard 48 x 24 x 7.5 mm box domino (``chain.presets.standard_domino``,
the contact stiffness of the plastic's Young's modulus, ``fidelity="exact"``, every other
value nominal from materials.toml) as close to that as the model goes: a chain of ``--n``
dominoes pushed with ``omega = sqrt(g/l)``, once per (model, gap, domino-domino friction),
with

* restitution 0.01 between dominoes and with the floor: ``ChainParams`` refuses 0 (its
  restitutions lie in (0, 1]; a linear spring-dashpot has no restitution 0), and 0.01 is
  the low value taken (dashpot damping ratio 0.83 of critical; 1 would be reached only at
  restitution 0). 0.001 (ratio 0.91) moves the speed by under 0.1 % (2d, 9.38 mm, friction
  0 and 0.525);
* floor friction 1.0 (the upper end of felt in materials.toml);
* domino-domino friction ``mu`` in :data:`FRICTIONS`, gaps in :data:`GAPS`, models 2d and 3d.

The values are passed as ``standard_domino(..., **overrides)``, which bypasses the ranges
of the material data (their restitutions start at 0.1). The front speed is fitted from
domino ``--fit-from`` on, pitch-based (``chain.wave.speed_from``), as in friction_scan.py.

Beside the speed each row records what may explain a difference with the theory:

* ``slip_*``: the horizontal displacement along the chain of each domino's pivot -- the
  centre of its front bottom rounded edge, ``(s/2 - r, 0, r)`` from the bottom centre in
  the box frame, x along the chain (``DominoBox.pivot_point``) -- from its initial
  position to the end of the run (``ChainRun.events.slip_final``, the last trajectory
  frame; positive = forward). ``slip_max_m`` is the signed value of largest magnitude
  over all dominoes (``slip_max_domino`` which one), ``slip_median_m`` the median. Rolling
  without slip on the rounded edge (radius ``r = s/20``) moves that centre by
  ``r theta`` (``theta`` the final forward tilt), so the ``*_rolled_m`` columns give the
  displacement minus ``r theta``: the slip of the contact with the floor;
* ``wave_settled`` / ``wave_settled_from``: whether the package's steady-speed detection
  (``chain.wave.steady_speed``, ``ChainRun.wave``) found a settled part of the wave and
  from which domino; ``fit_settled`` is the flag of the ``speed_from`` fit (True whenever
  the wave reached two dominoes from ``--fit-from`` on);
* ``hits_on_next_mean``: collisions of each domino on the next one (contacts closer than
  a collision time merged), averaged over the fitted dominoes except the last -- 1 for the
  theory's single inelastic collision, more for chatter and bouncing;
  ``max_backward_rad``: the largest backward lean of any domino;
* ``reached_all``, ``stop_reason``: whether the wave ran through the chain, why it ended.

Usage::

    nice python docs/real_dominoes/leaning_vs_dem.py --out docs/real_dominoes/leaning_vs_dem.csv
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np
from rows_csv import write_rows  # this folder's CSV writer

from dominowave.chain.build import chain_positions
from dominowave.chain.events import forward_tilt, rotate_vectors
from dominowave.chain.presets import standard_domino
from dominowave.chain.scenario import DominoChain, Push
from dominowave.chain.wave import speed_from

FRICTIONS = (0.0, 0.3, 0.525)
"""Domino-domino friction coefficients (0.525: the nominal of materials.toml)."""
GAPS = (0.00938, 0.01509, 0.025)
"""Clear gaps d [m]."""
RESTITUTION = 0.01
"""Restitution of domino-domino and domino-floor contacts (ChainParams refuses 0)."""
FLOOR_FRICTION = 1.0
"""Friction with the floor: the upper end of felt."""


def one_run(model: str, gap: float, friction: float, n: int, fit_from: int) -> dict:
    """The CSV row of one chain: speed, fit, CPU time and the diagnostics."""
    p = standard_domino(
        gap=gap,
        floor="felt",
        n_dominoes=n,
        model=model,
        friction_dominoes=friction,
        friction_floor=FLOOR_FRICTION,
        restitution_dominoes=RESTITUTION,
        restitution_floor=RESTITUTION,
        held=False,  # (every box free and awake, as the shipped comparison was measured)
    )
    start = time.process_time()
    run = DominoChain(p, fidelity="exact", sleep=False).run(
        Push(omega=math.sqrt(p.g / p.height)), keep_record=True
    )
    cpu = time.process_time() - start
    fit = speed_from(run.arrival, chain_positions(p), fit_from)
    ev = run.events
    slip = ev.slip_final
    rec = run.record
    pivot_x = (rec.com + rotate_vectors(rec.quat, rec.base_offset))[..., 0]
    contact = pivot_x - pivot_x[0] - p.rounding_radius * forward_tilt(rec)  # (frames, N)
    rolled = contact[-1]
    k = int(np.argmax(np.abs(slip)))
    k_rolled = int(np.argmax(np.abs(rolled)))
    if run.reached_all:
        at_end = contact[min(np.searchsorted(rec.times, run.arrival[-1]), rec.times.size - 1)]
        k_end = 1 + int(np.argmax(np.abs(at_end[1:])))
        slip_end, k_end_text = f"{at_end[k_end]:.3e}", k_end
    else:
        slip_end, k_end_text = "nan", -1
    hits = ev.n_hits_on_next[fit_from : run.front]
    return {
        "model": model,
        "gap_m": gap,
        "friction_dominoes": friction,
        "restitution": RESTITUTION,
        "friction_floor": FLOOR_FRICTION,
        "stiffness_over_kstar": f"{p.stiffness_over_kstar:.4g}",
        "speed_m_s": f"{fit.speed:.4f}",
        "speed_stderr_m_s": f"{fit.speed_err:.4f}",
        "cpu_s": f"{cpu:.1f}",
        "fit_settled": fit.settled,
        "wave_settled": run.wave.settled,
        "wave_settled_from": run.wave.first,
        "reached_all": run.reached_all,
        "stop_reason": run.stop_reason,
        "slip_max_m": f"{slip[k]:.3e}",
        "slip_max_domino": k,
        "slip_median_m": f"{np.median(slip):.3e}",
        "slip_max_rolled_m": f"{rolled[k_rolled]:.3e}",
        "slip_max_rolled_domino": k_rolled,
        "slip_median_rolled_m": f"{np.median(rolled):.3e}",
        "slip_at_front_end_m": slip_end,
        "slip_at_front_end_domino": k_end_text,
        "hits_on_next_mean": f"{np.mean(hits):.1f}" if hits.size else "nan",
        "max_backward_rad": f"{np.max(ev.max_backward):.3g}",
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, required=True, help="CSV file to write")
    parser.add_argument("--n", type=int, default=30, help="dominoes per chain")
    parser.add_argument("--fit-from", type=int, default=10, help="first fitted domino")
    parser.add_argument("--models", default="2d,3d", help="comma-separated: 2d, 3d")
    args = parser.parse_args()
    rows = []
    for model in args.models.split(","):
        for gap in GAPS:
            for friction in FRICTIONS:
                rows.append(one_run(model, gap, friction, args.n, args.fit_from))
                print(rows[-1], flush=True)
    write_rows(args.out, rows)


if __name__ == "__main__":
    main()
