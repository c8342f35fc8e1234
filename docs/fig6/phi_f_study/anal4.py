"""Geometry of hits inside the backward mode and of the trigger hits (contact48.pkl, phi_f=0.3)."""
import pickle, math, numpy as np
con = pickle.load(open("contact48.pkl", "rb"))
def back(e, j):
    return e["mechanism"][j] == 3 and math.radians(60) < e["max_backward"][j] < math.radians(150)
for d in (0.7, 0.8):
    inside, trig = [], []
    for r in con[(0.3, d)]:
        e = r["ev"]
        for k in range(1, 28):
            h = r["hits"][k]
            if h is None or not back(e, k + 1): continue
            (inside if back(e, k) else trig).append(h)
    for name, L in (("trigger hits (striker toppled forward)", trig), ("hits inside the backward mode (striker fell back)", inside)):
        sa = np.array([h["sphere_striker"] for h in L]); sb = np.array([h["sphere_struck"] for h in L])
        z = np.array([h["z_contact"] for h in L]); ta = np.array([h["tilt_striker"] for h in L])
        sl = np.array([h["slip_striker"] for h in L]) * 100
        print(f"d/l={d} {name}: n={len(L)}; striker sphere (0=bottom,9=top) median {np.median(sa):.0f}, struck sphere median {np.median(sb):.0f}; "
              f"z/l median {np.median(z):.2f} [{z.min():.2f}, {z.max():.2f}]; striker tilt median {np.median(ta):+.0f} deg; "
              f"striker base slip at impact median {np.median(sl):+.2f} cm [{np.percentile(sl,10):+.2f}, {np.percentile(sl,90):+.2f}]")
    # final slip of backward-fallen dominoes
    fs = [r["ev"]["slip_final"][j] * 100 for r in con[(0.3, d)] for j in range(1, 29) if back(r["ev"], j)]
    print(f"   final base slip of backward-fallen dominoes: median {np.median(fs):+.1f} cm (gap d = {d*5:.1f} cm); forward in {np.mean(np.array(fs)>0)*100:.0f} %")
