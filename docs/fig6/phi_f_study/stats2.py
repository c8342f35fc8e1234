"""Robust statistics of the ensembles (ens96.pkl, ens_mid.pkl, ens_mid8.pkl).
Usage: python stats2.py FILE.pkl [...]
 stall        : settled fitted speed < 0.6 sqrt(gl)
 backward fall: a domino n >= 1 with mechanism III (Fig 5A) after its first hit and a
                largest backward lean of 60-150 deg (it falls backwards onto n-1)
 bw member    : member with at least one backward fall
 crashed      : the run raised in the package (ChainRun analysis), counted as not settled"""
import pickle, sys, math, numpy as np
from scipy import stats as st
rng = np.random.default_rng(1)
res = {}
for f in sys.argv[1:]:
    res.update(pickle.load(open(f, "rb")))
def back(e, j):
    return e["mechanism"][j] == 3 and math.radians(60) < e["max_backward"][j] < math.radians(150)
print("| d/l | phi_f | members (settled) | mean +- s.e. | median [68 % bootstrap] | 20 % trimmed mean | stalling (< 0.6) | members with a backward fall | first backward domino (median) | mean abs slip cm | crashed |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
S = {}
for (phi, d) in sorted(res, key=lambda k: (k[1], k[0])):
    rows = res[(phi, d)]
    sp = np.array([r["speed"] for r in rows]); ok = np.isfinite(sp); s = sp[ok]
    good = [r for r in rows if r["ev"] is not None]
    firsts = []
    for r in good:
        nb = [j for j in range(1, 30) if back(r["ev"], j)]
        if nb: firsts.append(nb[0])
    slip = np.mean([np.mean(np.abs(r["ev"]["slip_final"][:-1])) for r in good]) * 100
    med_b = [np.median(rng.choice(s, s.size)) for _ in range(3000)]
    S[(phi, d)] = s
    print(f"| {d} | {phi} | {len(rows)} ({ok.sum()}) | {s.mean():.3f} +- {s.std(ddof=1)/math.sqrt(s.size):.3f} | "
          f"{np.median(s):.3f} [{np.percentile(med_b,16):.2f}, {np.percentile(med_b,84):.2f}] | {st.trim_mean(s, 0.2):.3f} | "
          f"{np.mean(s<0.6)*100:.0f} % ({np.sum(s<0.6)}) | {len(firsts)/len(good)*100:.0f} % ({len(firsts)}) | "
          f"{np.median(firsts) if firsts else float('nan'):.0f} | {slip:.1f} | {len(rows)-len(good)} |")
