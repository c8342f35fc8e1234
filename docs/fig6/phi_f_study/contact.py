"""Geometry of every first hit n -> n+1 (which spheres touch, tilt and base slip of the striker)
and what the struck domino does afterwards.  Usage: python contact.py OUT.pkl MEMBERS phi1,phi2 d1,d2
Members built as dominowave.chain.paper_fig6.run_member (seed 0)."""
import sys, time, pickle
import numpy as np
from dominowave.chain.build import ChainParams
from dominowave.chain.scenario import DominoChain
from dominowave.chain.events import contact_intervals, rotate_vectors, forward_tilt

out, M = sys.argv[1], int(sys.argv[2])
phis = [float(x) for x in sys.argv[3].split(",")]
dls = [float(x) for x in sys.argv[4].split(",")]
res = {}
t0 = time.time()
for d in dls:
    for phi in phis:
        chain = DominoChain(ChainParams(n_dominoes=30, d_over_l=d, friction_floor=phi))
        p = chain.params
        vs = (p.g * p.height) ** 0.5
        base = chain.resolve(None)
        shape = chain.shape
        rel0 = shape.centres - shape.centre_of_mass       # (S,3) at frame 0 (upright, no yaw)
        R = shape.radii
        rows = []
        for m in range(M):
            f = 1.0 + 1e-3 * np.random.default_rng([0, m]).standard_normal()
            run = chain.run(base.scaled(f), keep_record=True)
            rec = run.record
            times = rec.times
            theta = forward_tilt(rec)
            ev = run.events
            N = p.n_dominoes
            hits = []
            for k in range(N - 1):
                on, off = contact_intervals(rec, k, k + 1)
                if not on.size:
                    hits.append(None); continue
                fi = min(int(np.searchsorted(times, on[0])), times.size - 1)
                def spheres(j):
                    q = rec.quat[:, j]
                    # relative rotation wrt frame 0 applied to each sphere offset at frame fi
                    rv = rotate_vectors(q[[0, fi]][:, None, :].repeat(rel0.shape[0], 1), rel0)[1]
                    return rec.com[fi, j] + rv
                a, b = spheres(k), spheres(k + 1)
                gap = np.linalg.norm(a[:, None] - b[None], axis=-1) - (R[:, None] + R[None])
                ia, ib = np.unravel_index(np.argmin(gap), gap.shape)
                nvec = b[ib] - a[ia]; nvec /= np.linalg.norm(nvec)
                cpt = a[ia] + R[ia] * nvec
                base_k = a[0]; base_k1 = b[0]
                hits.append(dict(t=on[0], sphere_striker=int(ia), sphere_struck=int(ib),
                                 z_contact=cpt[2] / p.height,
                                 normal_deg=float(np.degrees(np.arctan2(nvec[2], nvec[0]))),
                                 tilt_striker=float(np.degrees(theta[fi, k])),
                                 tilt_struck=float(np.degrees(theta[fi, k + 1])),
                                 slip_striker=float(base_k[0] - run.positions[k]),
                                 slip_struck=float(base_k1[0] - run.positions[k + 1]),
                                 gap=float(gap[ia, ib])))
            sp = run.wave.speed / vs
            rows.append(dict(member=m, speed=sp, arrival=run.arrival.copy(),
                             ev={kk: np.asarray(v).copy() for kk, v in ev.table().items()},
                             hits=hits))
        res[(phi, d)] = rows
        print(f"phi={phi} d={d} done t={time.time()-t0:.0f}s", flush=True)
        with open(out, "wb") as fh:
            pickle.dump(res, fh)
