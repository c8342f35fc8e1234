"""Analysis of contact48.pkl: contact height of first hits, outcome of the struck domino,
persistence of the backward (base-kick) mode.  Usage: python anac.py contact48.pkl"""
import pickle, sys, numpy as np
res = pickle.load(open(sys.argv[1], "rb"))
BACK = lambda e, j: e["mechanism"][j] == 3 and np.radians(60) < e["max_backward"][j] < np.radians(150)
bins = [0, 0.3, 0.4, 0.45, 0.5, 0.55, 0.6, 0.7, 1.01]
print("P(struck domino falls backwards | contact height z/l), first hits by a forward-toppling striker (dominoes 1..28)")
print("| d/l | phi_f | hits | z/l median [10%,90%] | share z<0.45 | " + " | ".join(f"{bins[i]:.2f}-{bins[i+1]:.2f}" for i in range(len(bins)-1)) + " | striker slip at impact cm median [10,90] | corr(slip, z) |")
summary = {}
for (phi, d) in sorted(res, key=lambda k: (k[1], k[0])):
    Z, B, S, T = [], [], [], []
    pers_n = pers_b = 0; trig = []
    for r in res[(phi, d)]:
        e, hits = r["ev"], r["hits"]
        first_back = None
        for k in range(1, 28):
            h = hits[k]
            if h is None:
                continue
            if BACK(e, k):   # striker itself fell backwards: base-kick propagation
                pers_n += 1; pers_b += BACK(e, k + 1)
                continue
            Z.append(h["z_contact"]); B.append(BACK(e, k + 1)); S.append(h["slip_striker"] * 100)
            if BACK(e, k + 1) and first_back is None:
                first_back = k + 1
        trig.append((r["speed"], first_back))
    Z, B, S = map(np.array, (Z, B, S))
    cells = []
    for i in range(len(bins) - 1):
        sel = (Z >= bins[i]) & (Z < bins[i + 1])
        cells.append(f"{B[sel].mean()*100:.0f} % ({sel.sum()})" if sel.sum() else "-")
    q = np.percentile(Z, [10, 50, 90]); qs = np.percentile(S, [10, 50, 90])
    print(f"| {d} | {phi} | {Z.size} | {q[1]:.2f} [{q[0]:.2f}, {q[2]:.2f}] | {np.mean(Z<0.45)*100:.0f} % | " + " | ".join(cells)
          + f" | {qs[1]:.2f} [{qs[0]:.2f}, {qs[2]:.2f}] | {np.corrcoef(S, Z)[0,1]:.2f} |")
    summary[(phi, d)] = (pers_n, pers_b, trig)
print()
print("Persistence of the backward mode: P(n+1 falls backwards | n fell backwards), and members by trigger")
print("| d/l | phi_f | pairs (n back) | P(n+1 back) | members with a backward fall | their speed median | members without: speed median |")
print("|---|---|---|---|---|---|---|")
for (phi, d), (pn, pb, trig) in sorted(summary.items(), key=lambda kv: (kv[0][1], kv[0][0])):
    sp_b = np.array([s for s, f in trig if f is not None]); sp_n = np.array([s for s, f in trig if f is None])
    print(f"| {d} | {phi} | {pn} | {pb/pn*100 if pn else float('nan'):.0f} % | {sp_b.size}/{len(trig)} | "
          f"{np.nanmedian(sp_b) if sp_b.size else float('nan'):.2f} | {np.nanmedian(sp_n) if sp_n.size else float('nan'):.2f} |")
