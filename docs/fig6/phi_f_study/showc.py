import pickle, sys, numpy as np
res = pickle.load(open(sys.argv[1], "rb"))
key = (float(sys.argv[2]), float(sys.argv[3])); m = int(sys.argv[4])
r = res[key][m]; e = r["ev"]
print("member", m, "speed", r["speed"])
print(" k  sA sB  zc/l  n_deg tiltA tiltB slipA slipB | B: mech maxback slipfin hitsprev")
for k, h in enumerate(r["hits"]):
    if h is None: print(k, "no hit"); continue
    print(f"{k:2d} {h['sphere_striker']:2d} {h['sphere_struck']:2d} {h['z_contact']:.2f} {h['normal_deg']:6.1f} {h['tilt_striker']:5.1f} {h['tilt_struck']:5.1f} {h['slip_striker']*100:5.2f} {h['slip_struck']*100:5.2f} | "
          f"{e['mechanism'][k+1]} {np.degrees(e['max_backward'][k+1]):6.1f} {e['slip_final'][k+1]*100:6.2f} {e['n_hits_from_prev'][k+1]}")
