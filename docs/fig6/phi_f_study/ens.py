"""Large ensembles for phi_f comparison. Usage: python ens.py OUT.npz MEMBERS phi1,phi2 d1,d2
Chain length: 30 dominoes, or the environment variable NDOM (60-domino study).
Each member is built exactly as dominowave.chain.paper_fig6.run_member (push omega=sqrt(g/l)*(1+1e-3 N(0,1)),
rng default_rng([0, member])), so members 0-7 are the docs' Fig 6 members."""
import os, sys, time, pickle
import numpy as np
from dominowave.chain.build import ChainParams
from dominowave.chain.scenario import DominoChain
from dominowave.chain.wave import local_speeds

out, M = sys.argv[1], int(sys.argv[2])
phis = [float(x) for x in sys.argv[3].split(",")]
dls = [float(x) for x in sys.argv[4].split(",")]
res = {}
t0 = time.time()
for d in dls:
    for phi in phis:
        chain = DominoChain(ChainParams(n_dominoes=int(os.environ.get("NDOM", "30")), d_over_l=d, friction_floor=phi))
        base = chain.resolve(None)
        vs = (chain.params.g * chain.params.height) ** 0.5
        rows = []
        for m in range(M):
            f = 1.0 + 1e-3 * np.random.default_rng([0, m]).standard_normal()
            try:
                run = chain.run(base.scaled(f))
            except ValueError as exc:
                print(f"member {m} phi={phi} d/l={d}: {type(exc).__name__}: {exc}", flush=True)
                rows.append(dict(member=m, speed=np.nan, settled=False, error=str(exc),
                                 ev=None, arrival=None, positions=None, local=None))
                continue
            ev = run.events
            rows.append(dict(
                member=m, speed=run.wave.speed / vs, settled=run.wave.settled,
                first=run.wave.first, last=run.wave.last, reached=run.wave.reached,
                arrival=run.arrival.copy(), positions=run.positions.copy(),
                local=local_speeds(run.arrival, run.positions) / vs,
                ev={k: np.asarray(v).copy() for k, v in ev.table().items()},
                theory=run.theory_speed / vs, window=run.theory_window_speed / vs,
                stop=run.stop_reason, wall=run.wall_time))
        res[(phi, d)] = rows
        sp = np.array([r["speed"] for r in rows])
        print(f"phi={phi} d/l={d}: n_settled={np.isfinite(sp).sum()} mean={np.nanmean(sp):.3f} "
              f"median={np.nanmedian(sp):.3f} t={time.time()-t0:.0f}s", flush=True)
        with open(out, "wb") as fh:
            pickle.dump(res, fh)
