"""(a) members without any backward fall: speed and hesitations; (b) fate of backward runs;
(c) small spacing: local interval vs striker slip at impact.  Usage: python anal3.py"""
import pickle, math, numpy as np
ens = pickle.load(open("ens96.pkl", "rb")); con = pickle.load(open("contact48.pkl", "rb"))
def back(e, j):
    return e["mechanism"][j] == 3 and math.radians(60) < e["max_backward"][j] < math.radians(150)
print("(a) members without backward falls")
print("| d/l | phi_f | members | speed median | mean +- s.e. | mech III dominoes / member | hesitations (topple - arrival > 15 ms) / member |")
print("|---|---|---|---|---|---|---|")
for (phi, d) in sorted(ens, key=lambda k: (k[1], k[0])):
    sp, m3, hes = [], [], []
    for r in ens[(phi, d)]:
        e = r["ev"]
        if any(back(e, j) for j in range(1, 30)): continue
        sp.append(r["speed"]); m3.append(np.sum(e["mechanism"][1:29] == 3))
        hes.append(np.sum((e["topple_time"][1:29] - e["arrival"][1:29]) > 0.015))
    sp = np.array(sp); s = sp[np.isfinite(sp)]
    print(f"| {d} | {phi} | {len(sp)} | {np.median(s):.3f} | {s.mean():.3f} +- {s.std(ddof=1)/math.sqrt(s.size):.3f} | {np.mean(m3):.2f} | {np.mean(hes):.2f} |")
print()
print("(b) fate of each run of consecutive backward falls (phi_f = 0.3, 96 members)")
for d in (0.7, 0.8):
    fates = {"to the end of the chain": 0, "wave died": 0, "forward toppling resumed": 0}
    lengths = []
    loc = []
    for r in ens[(0.3, d)]:
        e = r["ev"]; a = r["arrival"]
        flags = [back(e, j) for j in range(30)]
        j = 1
        while j < 30:
            if flags[j]:
                k = j
                while k + 1 < 30 and flags[k + 1]: k += 1
                lengths.append(k - j + 1)
                if j + 1 <= k:
                    loc.extend(list(r["local"][j:k]))
                if k >= 28: fates["to the end of the chain"] += 1
                elif not np.isfinite(a[k + 1]) or not np.isfinite(a[min(k + 2, 29)]): fates["wave died"] += 1
                else: fates["forward toppling resumed"] += 1
                j = k + 1
            else:
                j += 1
    loc = np.array(loc); loc = loc[np.isfinite(loc)]
    print(f"d/l={d}: {len(lengths)} runs, length median {np.median(lengths):.0f} (max {max(lengths)}), fates {fates}; "
          f"local speed inside runs median {np.median(loc):.2f} [10-90 %: {np.percentile(loc,10):.2f}-{np.percentile(loc,90):.2f}] sqrt(gl)")
print()
print("(c) local travel time t_{n+1}-t_n vs striker n's base slip at its impact on n+1 (dominoes 3..27)")
for d in (0.3, 0.6):
    for phi in (0.3, 0.6):
        X, Y, Z = [], [], []
        for r in con[(phi, d)]:
            a = r["arrival"]
            for k in range(3, 27):
                h = r["hits"][k]
                if h is None or not np.isfinite(a[k + 1]): continue
                X.append(h["slip_striker"] * 100); Y.append((a[k + 1] - a[k]) * 1e3); Z.append(h["z_contact"])
        X, Y, Z = map(np.array, (X, Y, Z))
        b = np.polyfit(X, Y, 1)
        print(f"d/l={d} phi={phi}: n={X.size}, slip at impact median {np.median(X):+.2f} cm, interval median {np.median(Y):.1f} ms, "
              f"slope {b[0]:+.2f} ms/cm, corr {np.corrcoef(X,Y)[0,1]:+.2f}, z/l median {np.median(Z):.2f}")
