# IFToMM A02 (the N four-bar mechanism) in rocker and coupler angles, in either
# declaration order: python3 a02_angles.py N interleaved|grouped > a02.mech
#
# N + 1 rockers (angle th_i from the ground, pivot at (i, 0)) and N couplers (angle ps_i,
# joining the tips of rockers i-1 and i), every bar a uniform rod of 1 m and 1 kg:
# 2 N + 1 coordinates, 2 N rows (the closure of each window in x and y), one degree of
# freedom. "interleaved" declares th0, ps1, th1, ps2, ...; "grouped" all rockers, then all
# couplers. The same mechanism either way: the solvers must cost the same (issue 54).
# Rocker: T = th'^2 / 6, Pi = g sin(th) / 2. Coupler on the tip A of rocker i-1:
# T = th'^2 / 2 + cos(th - ps) th' ps' / 2 + ps'^2 / 6, Pi = g (sin(th) + sin(ps) / 2).
import sys
n = int(sys.argv[1])
kind = sys.argv[2] if len(sys.argv) > 2 else "interleaved"
if kind == "interleaved":
    names = ["th0"] + [x for i in range(1, n + 1) for x in (f"ps{i}", f"th{i}")]
elif kind == "grouped":
    names = [f"th{i}" for i in range(n + 1)] + [f"ps{i}" for i in range(1, n + 1)]
else:
    sys.exit("order must be interleaved or grouped")
# Start: every rocker vertical (th = pi/2), every coupler horizontal (ps = 0); th0 driven
# at 1 rad/s to start.
start = {x: ("1.5707963267948966" if x.startswith("th") else "0.0") for x in names}
o = [f"pub struct A02Angles{n};", "parameters { g = 9.81; }    // m/s^2"]
o.append("coordinates {\n" + "\n".join(f"    {x} = {start[x]};" for x in names) + "\n}")
o.append("independent { th0 = 1.5707963267948966; der(th0) = 1.0; }")
kin, pot = [], []
for i in range(n + 1):
    kin.append(f"der(th{i})^2/6")
    pot.append(f"g*sin(th{i})/2")
for i in range(1, n + 1):
    t, p = f"th{i - 1}", f"ps{i}"
    kin.append(f"der({t})^2/2 + cos({t} - {p})*der({t})*der({p})/2 + der({p})^2/6")
    pot.append(f"g*(sin({t}) + sin({p})/2)")
o.append("kinetic = " + "\n    + ".join(kin) + ";")
o.append("potential = " + "\n    + ".join(pot) + ";")
rows = []
for i in range(1, n + 1):
    t0, p, t1 = f"th{i - 1}", f"ps{i}", f"th{i}"
    rows.append(f"    cos({t0}) + cos({p}) - 1 - cos({t1});    // window_{i}_x")
    rows.append(f"    sin({t0}) + sin({p}) - sin({t1});    // window_{i}_y")
o.append("constraints {\n" + "\n".join(rows) + "\n}")
print("\n".join(o))
