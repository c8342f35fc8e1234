"""(a) 60-domino ensembles (ens60.pkl); (b) how often an 8-member draw from the 96-member
ensembles gives a phi_f = 0.6 / 0.3 mean ratio as large as the docs' (ens96.pkl)."""
import pickle, math, numpy as np
from scipy import stats as st
def back(e, j):
    return e["mechanism"][j] == 3 and math.radians(60) < e["max_backward"][j] < math.radians(150)
r60 = pickle.load(open("ens60.pkl", "rb"))
print("| N | d/l | phi_f | members (settled) | mean +- s.e. | median | 20 % trimmed | stalling (< 0.6) | members with a backward fall | backward dominoes / member |")
print("|---|---|---|---|---|---|---|---|---|---|")
for (phi, d) in sorted(r60, key=lambda k: (k[1], k[0])):
    rows = [r for r in r60[(phi, d)] if r["ev"] is not None]
    N = len(rows[0]["arrival"])
    sp = np.array([r["speed"] for r in r60[(phi, d)]]); s = sp[np.isfinite(sp)]
    nb = [sum(back(r["ev"], j) for j in range(1, N)) for r in rows]
    print(f"| {N} | {d} | {phi} | {len(sp)} ({s.size}) | {s.mean():.3f} +- {s.std(ddof=1)/math.sqrt(s.size):.3f} | {np.median(s):.3f} | {st.trim_mean(s,0.2):.3f} | "
          f"{np.mean(s<0.6)*100:.0f} % ({np.sum(s<0.6)}) | {np.mean(np.array(nb)>0)*100:.0f} % | {np.mean(nb):.1f} |")
ens = pickle.load(open("ens96.pkl", "rb"))
rng = np.random.default_rng(2)
print()
for d, docs in ((0.7, 1.44 / 0.99), (0.8, 1.25 / 0.86)):
    a = np.array([r["speed"] for r in ens[(0.3, d)]]); b = np.array([r["speed"] for r in ens[(0.6, d)]])
    rat = []
    for _ in range(20000):
        x = a[rng.choice(96, 8, replace=False)]; y = b[rng.choice(96, 8, replace=False)]
        rat.append(np.nanmean(y) / np.nanmean(x))
    rat = np.array(rat)
    full = np.nanmean(b) / np.nanmean(a)
    print(f"d/l={d}: 96-member mean ratio {full:.3f}; 8-member draws: median ratio {np.median(rat):.3f}, 5-95 % {np.percentile(rat,5):.2f}-{np.percentile(rat,95):.2f}; "
          f"P(ratio >= docs' {docs:.2f}) = {np.mean(rat >= docs):.2f}")
