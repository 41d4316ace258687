"""The peers' side of BENCHMARKS.md: SymPy derivation, SymPy-cse C code and scipy DOP853.

Run through `benches/baselines/run.sh` (it creates the venv). Models:
- the seed crank-slider, the planar four-bar and the RSSR are read from the same `.mech`
  files `mechanism!` compiles (a small reader below: `^` is power, `der(x)` is x');
- the closed N-bar chain is built as a SymPy user would (issue 2's definition), for the
  derivation timings, and read from `benches/mechanisms/closed_chain_N.mech` for the C code.

Everything is written to target/bench-results/baselines.json (and .md).
"""

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

import numpy as np
import sympy as sp
from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
RESULTS = os.path.join(ROOT, "target", "bench-results")


# ---------------------------------------------------------------- .mech reader
def _block(text, name):
    m = re.search(name + r"\s*\{(.*?)\}", text, re.S)
    return [s.strip() for s in m.group(1).split(";") if s.strip()] if m else []


def _value(text, name):
    m = re.search(r"\b" + name + r"\s*=(.*?);", text, re.S)
    return m.group(1).strip()


def read_mech(path):
    """Parses a .mech declaration into SymPy: q, qd, params (symbol -> default), T, Pi, Phi, tau."""
    raw = open(path).read()
    text = "\n".join(l.split("//")[0] for l in raw.splitlines())
    coords = [c.split("=")[0].strip() for c in _block(text, "coordinates")]
    guesses = [float(c.split("=")[1]) for c in _block(text, "coordinates")]
    params = [(p.split("=")[0].strip(), p.split("=")[1].strip()) for p in _block(text, "parameters")]
    q = [sp.Symbol(c) for c in coords]
    qd = [sp.Symbol(c + "_d") for c in coords]
    t = sp.Symbol("t")
    local = {c: s for c, s in zip(coords, q)}
    local.update({"pi": sp.pi, "t": t})
    psyms = {}
    for name, default in params:
        psyms[name] = sp.Symbol(name)
        local[name] = psyms[name]

    def expr(s):
        s = " ".join(s.split()).replace("^", "**")
        s = re.sub(r"der\((\w+)\)", r"\1_d", s)
        loc = dict(local)
        loc.update({c + "_d": v for c, v in zip(coords, qd)})
        return sp.parse_expr(s, local_dict=loc)

    defaults = {}
    for name, default in params:
        defaults[psyms[name]] = float(expr(default).subs(defaults))
    tau = [sp.Integer(0)] * len(q)
    for f in _block(text, "forces"):
        name, e = f.split(":", 1)
        tau[coords.index(name.strip())] = expr(e)
    return dict(
        q=q, qd=qd, t=t, params=defaults, guesses=guesses,
        T=expr(_value(text, "kinetic")), Pi=expr(_value(text, "potential")),
        Phi=[expr(c) for c in _block(text, "constraints")], tau=tau,
    )


# ---------------------------------------------------------------- derivation
def direct(model):
    """M, C q', g, Phi, Phi_q, gamma by differentiation and jacobians."""
    q, qd, T, Pi = model["q"], model["qd"], model["T"], model["Pi"]
    qv, qdv = sp.Matrix(q), sp.Matrix(qd)
    M = sp.hessian(T, qd)
    dTdqd = sp.Matrix([sp.diff(T, v) for v in qd])
    Cqd = dTdqd.jacobian(q) * qdv - sp.Matrix([sp.diff(T, v) for v in q])
    g = sp.Matrix([sp.diff(Pi, v) for v in q])
    Phi = sp.Matrix(model["Phi"])
    Phi_q = Phi.jacobian(qv)
    gamma = -(Phi_q * qdv).jacobian(qv) * qdv
    return dict(M=M, Cqd=Cqd, g=g, Phi=Phi, Phi_q=Phi_q, gamma=gamma)


def chain_direct(n):
    """The closed N-bar chain (issue 2) with plain symbols, for the direct route."""
    th = sp.symbols(f"th1:{n + 1}")
    thd = sp.symbols(f"th1:{n + 1}_d")
    T, Pi = 0, 0
    for i in range(n):
        vx = sum(-sp.sin(th[j]) * thd[j] for j in range(i)) - sp.Rational(1, 2) * sp.sin(th[i]) * thd[i]
        vy = sum(sp.cos(th[j]) * thd[j] for j in range(i)) + sp.Rational(1, 2) * sp.cos(th[i]) * thd[i]
        T += sp.Rational(1, 2) * (vx**2 + vy**2) + sp.Rational(1, 24) * thd[i] ** 2
        Pi += sp.Float(9.81) * (sum(sp.sin(th[j]) for j in range(i)) + sp.Rational(1, 2) * sp.sin(th[i]))
    Phi = [sum(sp.cos(x) for x in th) - sp.Rational(n, 2), sum(sp.sin(x) for x in th)]
    return dict(q=list(th), qd=list(thd), T=T, Pi=Pi, Phi=Phi)


def chain_lagranges(n):
    """The chain through sympy.physics.mechanics.LagrangesMethod with multipliers."""
    th = dynamicsymbols(f"th1:{n + 1}")
    t = dynamicsymbols._t
    thd = [x.diff(t) for x in th]
    T, Pi = 0, 0
    for i in range(n):
        vx = sum(-sp.sin(th[j]) * thd[j] for j in range(i)) - sp.Rational(1, 2) * sp.sin(th[i]) * thd[i]
        vy = sum(sp.cos(th[j]) * thd[j] for j in range(i)) + sp.Rational(1, 2) * sp.cos(th[i]) * thd[i]
        T += sp.Rational(1, 2) * (vx**2 + vy**2) + sp.Rational(1, 24) * thd[i] ** 2
        Pi += sp.Float(9.81) * (sum(sp.sin(th[j]) for j in range(i)) + sp.Rational(1, 2) * sp.sin(th[i]))
    Phi = [sum(sp.cos(x) for x in th) - sp.Rational(n, 2), sum(sp.sin(x) for x in th)]
    lm = LagrangesMethod(T - Pi, th, hol_coneqs=Phi)
    lm.form_lagranges_equations()
    return lm.mass_matrix_full, lm.forcing_full


def timed(f, *a):
    t0 = time.perf_counter()
    r = f(*a)
    return time.perf_counter() - t0, r


# ---------------------------------------------------------------- C code
C_MAIN = r"""
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
void all5(const double *x, double *out);
static double now(void) { struct timespec ts; clock_gettime(CLOCK_MONOTONIC, &ts); return ts.tv_sec + 1e-9 * ts.tv_nsec; }
static int cmp(const void *a, const void *b) { double d = *(const double *)a - *(const double *)b; return (d > 0) - (d < 0); }
int main(int argc, char **argv) {
    double x[NX], out[NOUT];
    for (int i = 0; i < NX; i++) x[i] = atof(argv[1 + i]);
    long iters = ITERS; double samples[21], sink = 0;
    for (int r = 0; r < 21; r++) {
        double t0 = now();
        for (long k = 0; k < iters; k++) {
            x[0] += 1e-15;
            all5(x, out);
            __asm__ volatile("" : : "r"(out) : "memory");
            sink += out[0];
        }
        samples[r] = (now() - t0) / iters * 1e9;
    }
    qsort(samples, 21, sizeof(double), cmp);
    printf("%.3f %g\n", samples[10], sink);
    return 0;
}
"""


def c_code(model, exprs):
    """SymPy cse + ccode of `exprs` over inputs x = [q, qd, params, t]; returns (source, nx, nout, ops)."""
    inputs = model["q"] + model["qd"] + list(model["params"].keys()) + [model.get("t", sp.Symbol("t"))]
    safe = sp.symbols(f"in0:{len(inputs)}")
    sub = dict(zip(inputs, safe))
    exprs = [sp.sympify(e).xreplace(sub) for e in exprs]
    repl, red = sp.cse(exprs, symbols=sp.numbered_symbols("c"))
    ops = sum(sp.count_ops(r) for _, r in repl) + sum(sp.count_ops(r) for r in red)
    lines = ["#include <math.h>", "__attribute__((noinline)) void all5(const double *x, double *out) {"]
    lines += [f"  const double {s} = x[{i}];" for i, s in enumerate(safe)]
    lines += [f"  const double {s} = {sp.ccode(r)};" for s, r in repl]
    lines += [f"  out[{k}] = {sp.ccode(r)};" for k, r in enumerate(red)]
    lines.append("}")
    return "\n".join(lines), len(inputs), len(red), int(ops)


def time_c(model, exprs, values, iters=2_000_000):
    src, nx, nout, ops = c_code(model, exprs)
    with tempfile.TemporaryDirectory() as d:
        open(os.path.join(d, "f.c"), "w").write(src)
        open(os.path.join(d, "main.c"), "w").write(C_MAIN)
        exe = os.path.join(d, "bench")
        subprocess.run(["gcc", "-O3", "-march=native", f"-DNX={nx}", f"-DNOUT={nout}", f"-DITERS={iters}",
                        os.path.join(d, "f.c"), os.path.join(d, "main.c"), "-lm", "-o", exe], check=True)
        ns = float(subprocess.run([exe] + [repr(v) for v in values], check=True, capture_output=True, text=True).stdout.split()[0])
    return ns, ops


def five(d):
    return list(d["M"]) + list(d["Cqd"]) + list(d["g"]) + list(d["Phi"]) + list(d["Phi_q"])


def c_inputs(model):
    q = model["guesses"] if "guesses" in model else [0.3] * len(model["q"])
    return list(q) + [1.0] * len(model["qd"]) + list(model["params"].values()) + [0.3]


# ---------------------------------------------------------------- scipy
def seed_scipy(model, rtol, reference=None):
    from scipy.integrate import solve_ivp

    d = direct(model)
    n, m = len(model["q"]), len(model["Phi"])
    ps = model["params"]
    args = model["q"] + model["qd"] + [model["t"]]
    f = lambda e: sp.lambdify(args, sp.Matrix(e).subs(ps), modules="numpy", cse=True)
    M_f, rhs_f = f(d["M"]), f(sp.Matrix(model["tau"]) - d["Cqd"] - d["g"])
    Phiq_f, gamma_f, Phi_f = f(d["Phi_q"]), f(d["gamma"]), f(d["Phi"])
    A = np.zeros((n + m, n + m))
    b = np.zeros(n + m)

    def rhs(t, y):
        a = (*y, t)
        A[:n, :n] = M_f(*a)
        J = Phiq_f(*a)
        A[n:, :n] = J
        A[:n, n:] = J.T
        b[:n] = rhs_f(*a).ravel()
        b[n:] = gamma_f(*a).ravel()
        x = np.linalg.solve(A, b)
        return np.concatenate([y[n:], x[:n]])

    # Consistent initial state (ERRATA item 2): closed forms, then Phi_q q' = 0 with phi' = 2 pi.
    P = {s.name: v for s, v in ps.items()}
    g0 = np.arccos((P["h"] + P["l1"]) / P["l2"])
    b0 = np.arcsin(P["d"] / (P["l2"] * np.sin(g0)))
    q0 = np.array([0.0, b0, g0, 0.2])
    J = Phiq_f(*q0, *np.zeros(n), 0.0)
    qd0 = np.zeros(n)
    qd0[0] = 2 * np.pi
    qd0[1:] = np.linalg.solve(J[:, 1:], -J[:, 0] * qd0[0])
    y0 = np.concatenate([q0, qd0])
    t0 = time.perf_counter()
    sol = solve_ivp(rhs, (0, 10), y0, method="DOP853", rtol=rtol, atol=rtol)
    wall = time.perf_counter() - t0
    qend = sol.y[:n, -1]
    max_phi = max(np.abs(Phi_f(*sol.y[:, k], sol.t[k])).max() for k in range(sol.y.shape[1]))
    err = float(np.abs(qend - np.array(reference)).max()) if reference is not None else None
    return dict(wall_s=wall, steps=int(len(sol.t) - 1), rhs=int(sol.nfev), q_end=list(map(float, qend)), max_phi=float(max_phi), error=err)


# ---------------------------------------------------------------- main
def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--chains", type=int, nargs="*", default=[4, 8, 16])
    ap.add_argument("--lagranges", type=int, nargs="*", default=[4, 8, 16])
    ap.add_argument("--c-chains", type=int, nargs="*", default=[8, 16])
    ap.add_argument("--skip-scipy", action="store_true")
    a = ap.parse_args()
    os.makedirs(RESULTS, exist_ok=True)
    path = os.path.join(RESULTS, "baselines.json")
    # Merge into earlier results, so that partial reruns (e.g. `--chains` with no sizes)
    # keep the rest.
    out = json.load(open(path)) if os.path.exists(path) else {}
    out["sympy"] = sp.__version__
    for k in ("derivation", "c_code", "scipy"):
        out.setdefault(k, {})

    def save():
        json.dump(out, open(path, "w"), indent=1)

    mechs = {
        "seed": read_mech(os.path.join(ROOT, "mechanisms", "spatial_crank_slider.mech")),
        "four_bar": read_mech(os.path.join(ROOT, "mechanisms", "planar_four_bar.mech")),
        "rssr": read_mech(os.path.join(ROOT, "mechanisms", "spatial_four_bar.mech")),
    }
    for n in a.c_chains:
        mechs[f"chain{n}"] = read_mech(os.path.join(ROOT, "benches", "mechanisms", f"closed_chain_{n}.mech"))
    for name, model in mechs.items():
        dt, d = timed(direct, model)
        ns, ops = time_c(model, five(d), c_inputs(model))
        out["c_code"][name] = dict(ns=ns, ops=ops, derive_s=dt)
        print(f"C (SymPy cse, gcc -O3 -march=native) {name}: M, C q', g, Phi, Phi_q in {ns:.1f} ns, {ops} ops", flush=True)
        save()

    for n in a.chains:
        dt, d = timed(lambda: direct(chain_direct(n)))
        ct, (repl, red) = timed(lambda: sp.cse([e for k in ("M", "Cqd", "g", "Phi", "Phi_q", "gamma") for e in d[k]]))
        ops = int(sum(sp.count_ops(r) for _, r in repl) + sum(sp.count_ops(r) for r in red))
        entry = dict(direct_s=dt, cse_s=ct, ops_after_cse=ops)
        print(f"SymPy direct chain N = {n}: {dt:.2f} s (+ cse {ct:.2f} s, {ops} ops)", flush=True)
        if n in a.lagranges:
            lt, _ = timed(chain_lagranges, n)
            entry["lagranges_s"] = lt
            print(f"SymPy LagrangesMethod chain N = {n}: {lt:.2f} s", flush=True)
        out["derivation"][str(n)] = entry
        save()

    if not a.skip_scipy:
        ref = None
        sim = os.path.join(RESULTS, "simulation.json")
        if os.path.exists(sim):
            ref = json.load(open(sim)).get("seed_reference_q")
        r = seed_scipy(mechs["seed"], 1e-10, ref)
        out["scipy"]["seed_dop853_1e-10"] = r
        print(f"scipy DOP853 seed 10 s at 1e-10: {r['wall_s']:.3f} s, {r['steps']} steps, {r['rhs']} RHS, error {r['error']}, max |Phi| {r['max_phi']:.1e}", flush=True)
        save()
    print(f"wrote {path}")


if __name__ == "__main__":
    sys.exit(main())
