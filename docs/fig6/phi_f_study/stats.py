"""Robust statistics of the ensembles. Usage: python stats.py ens96.pkl [ens_mid.pkl ...]
stall (speed) : settled fitted speed < 0.6 sqrt(gl)
backward mode : >= 3 dominoes (n >= 1) that fall backwards (max_backward > 60 deg)
'through' speed: (x_29 - x_5)/(t_29 - t_5) in sqrt(gl) (NaN if wave did not reach 29)"""
import pickle, sys, numpy as np
from scipy import stats as st
rng = np.random.default_rng(1)
def boot_ci(x, fn, n=4000):
    x = x[np.isfinite(x)]
    b = [fn(rng.choice(x, x.size)) for _ in range(n)]
    return np.percentile(b, [16, 84])
res = {}
for f in sys.argv[1:]:
    res.update(pickle.load(open(f, "rb")))
print("| d/l | phi_f | members (settled) | mean +- s.e. | median [68% boot] | 20% trimmed mean | speed<0.6 | backward mode | not settled | through-speed median | mean |slip| cm | mech II % | mech III % |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
table = {}
for (phi, d) in sorted(res, key=lambda k: (k[1], k[0])):
    rows = res[(phi, d)]
    sp = np.array([r["speed"] for r in rows]); ok = np.isfinite(sp)
    M = len(rows)
    back = np.array([np.sum(r["ev"]["max_backward"][1:] > np.radians(60)) >= 3 for r in rows])
    vs = 1.0
    thr = []
    for r in rows:
        a, x = r["arrival"], r["positions"] if "positions" in r else None
        thr.append(np.nan)
    if "positions" in rows[0]:
        thr = np.array([(r["positions"][29]-r["positions"][5])/(r["arrival"][29]-r["arrival"][5])/((9.81*0.05)**0.5) if np.isfinite(r["arrival"][29]) else 0.0 for r in rows])
    else:
        thr = np.full(M, np.nan)
    slip = np.mean([np.mean(np.abs(r["ev"]["slip_final"][:-1])) for r in rows]) * 100
    mech = np.concatenate([r["ev"]["mechanism"][1:] for r in rows])
    s = sp[ok]
    lo, hi = boot_ci(s, np.median)
    table[(phi, d)] = s
    print(f"| {d} | {phi} | {M} ({ok.sum()}) | {s.mean():.3f} +- {s.std(ddof=1)/np.sqrt(s.size):.3f} | {np.median(s):.3f} [{lo:.2f}, {hi:.2f}] | "
          f"{st.trim_mean(s, 0.2):.3f} | {np.mean(s < 0.6)*100:.0f} % ({np.sum(s<0.6)}) | {back.mean()*100:.0f} % ({back.sum()}) | {M-ok.sum()} | "
          f"{np.median(thr):.3f} | {slip:.1f} | {np.mean(mech==2)*100:.0f} | {np.mean(mech==3)*100:.0f} |")
print()
print("pairwise phi_f = 0.6 vs 0.3 (settled members):")
for d in sorted({k[1] for k in table}):
    if (0.3, d) in table and (0.6, d) in table:
        a, b = table[(0.3, d)], table[(0.6, d)]
        u = st.mannwhitneyu(b, a)
        # bootstrap of median ratio
        br = [np.median(rng.choice(b, b.size)) / np.median(rng.choice(a, a.size)) for _ in range(4000)]
        a_ns = a[a >= 0.6]; b_ns = b[b >= 0.6]
        print(f"d/l={d}: mean ratio {b.mean()/a.mean()-1:+.1%} ({(b.mean()-a.mean())/np.hypot(a.std(ddof=1)/np.sqrt(a.size), b.std(ddof=1)/np.sqrt(b.size)):.1f} comb. s.e.), "
              f"median ratio {np.median(b)/np.median(a)-1:+.1%} [68%: {np.percentile(br,16)-1:+.1%}, {np.percentile(br,84)-1:+.1%}], "
              f"trimmed {st.trim_mean(b,0.2)/st.trim_mean(a,0.2)-1:+.1%}, Mann-Whitney p={u.pvalue:.2g}; "
              f"non-stalling (>=0.6) means {a_ns.mean():.3f}+-{a_ns.std(ddof=1)/np.sqrt(a_ns.size):.3f} (n={a_ns.size}) vs {b_ns.mean():.3f}+-{b_ns.std(ddof=1)/np.sqrt(b_ns.size):.3f} (n={b_ns.size}): {b_ns.mean()/a_ns.mean()-1:+.1%}")
