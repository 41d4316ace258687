"""The peers' side of BENCHMARKS.md: SymPy's derivation, the C code SymPy generates, and
scipy's DOP853 on SymPy-lambdified equations.

Used by `benches/run.sh` (which creates the venv), or alone with that venv's python for the
derivation timings (`--chains`, `--lagranges`). Models:
- the seed crank-slider, the planar four-bar and the RSSR are read from the same `.mech`
  files `mechanism!` compiles (a small reader below: `^` is power, `der(x)` is x');
- the closed N-bar chain is built as a SymPy user would (issue 2's definition), for the
  derivation timings, and read from `benches/mechanisms/closed_chain_N.mech` for the C code.

The C generators (`c_code`: one function after one joint `sympy.cse`; `c_code_per_routine`:
`sympy.utilities.codegen`'s one routine per matrix) are built and timed by `c_peer.py`; the
scipy problems (`seed_rhs_strict`: lambdify(cse=True) with a preallocated KKT matrix;
`seed_rhs_default`: lambdify's defaults and `np.block` per call) are timed by
`benches/rounds.py`. This file's own run writes the derivation times, with the load average
and the process CPU time, to target/bench-results/baselines.json (merged into earlier
results).
"""

import argparse
import json
import os
import re
import subprocess
import sys
import time

import numpy as np
import sympy as sp
from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols

VARIANTS = {
    "derivation": "SymPy derivation of the closed N-bar chain: direct_s = differentiation and jacobians on plain symbols; lagranges_s = sympy.physics.mechanics.LagrangesMethod(...).form_lagranges_equations() with the loop closure as hol_coneqs.",
}

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from target_dir import RESULTS  # noqa: E402


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


def load_avg():
    """The 1, 5 and 15 minute load averages (as `uptime` shows them), recorded with each number."""
    try:
        return " ".join(open("/proc/loadavg").read().split()[:3])
    except OSError:
        return None


def timed(f, *a):
    t0 = time.perf_counter()
    r = f(*a)
    return time.perf_counter() - t0, r


def timed_cpu(f, *a):
    """(wall s, this thread's CPU s, result): CPU time is what a busy shared machine distorts least."""
    t0, c0 = time.perf_counter(), time.thread_time()
    r = f(*a)
    return time.perf_counter() - t0, time.thread_time() - c0, r


# ---------------------------------------------------------------- C code
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


C_PER_ROUTINE = [("mass_matrix", "M"), ("coriolis", "Cqd"), ("gravity", "g"), ("constraints", "Phi"), ("constraint_jacobian", "Phi_q")]


def libm_calls(obj):
    """Calls into libm in an object file (objdump -dr relocations): {name: count}."""
    dis = subprocess.run(["objdump", "-dr", obj], check=True, capture_output=True, text=True).stdout
    calls = {}
    for name in re.findall(r"R_X86_64_PLT32\s+(\w+)", dis):
        if name in ("sin", "cos", "sincos", "tan", "pow", "sqrt", "exp", "log", "atan2"):
            calls[name] = calls.get(name, 0) + 1
    return calls


def c_code_per_routine(model, d):
    """What `sympy.utilities.codegen` gives a user who asks for CSE: one C routine per matrix.

    `codegen([(name, matrix), ...], code_gen=C99CodeGen(cse=True))` (SymPy 1.14's `codegen()`
    has no `cse=` keyword; CSE is the code generator's `cse` flag) runs `cse` on each matrix
    on its own and emits one function per matrix with its own arguments, in alphabetical
    order. The caller (a separate file, as a user's program would be) calls the five one after
    another, so each routine computes its own sin/cos. Returns (routines source, caller source,
    nx, nout, ops)."""
    from sympy.utilities.codegen import C99CodeGen

    inputs = model["q"] + model["qd"] + list(model["params"].keys()) + [model.get("t", sp.Symbol("t"))]
    index = {s.name: i for i, s in enumerate(inputs)}
    gen = C99CodeGen(project="mechanism", cse=True)
    routines = [gen.routine(name, d[key], None, None) for name, key in C_PER_ROUTINE]
    [(_, src), (_, header)] = gen.write(routines, "routines", header=False, empty=False)
    ops = 0
    calls, offset = [], 0
    for r, (_, key) in zip(routines, C_PER_ROUTINE):
        ops += sum(sp.count_ops(v.expr) for v in r.local_vars) + sum(sp.count_ops(a.expr) for a in r.arguments if hasattr(a, "expr"))
        args = []
        for a in r.arguments:
            if a.__class__.__name__ == "InputArgument":
                args.append(f"x[{index[str(a.name)]}]")
            else:
                args.append(f"out + {offset}")
        offset += len(d[key])
        calls.append(f"  {r.name}({', '.join(args)});")
    caller = '#include "routines.h"\nvoid all5(const double *x, double *out) {\n' + "\n".join(calls) + "\n}\n"
    return src, header, caller, len(inputs), offset, int(ops)


# ---------------------------------------------------------------- scipy
def seed_rhs_strict(model):
    """y' for scipy from lambdify(cse=True) with the parameters substituted, the KKT matrix
    filled into preallocated arrays; returns (rhs, y0, Phi(t, y))."""
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

    y0 = seed_initial_state(ps, lambda q0: Phiq_f(*q0, *np.zeros(n), 0.0))
    return rhs, y0, lambda t, y: Phi_f(*y, t)


def seed_rhs_default(model):
    """The plain SymPy user's route: `sympy.lambdify` with its defaults (no cse, modules =
    scipy + numpy), one function per matrix taking (q, q', p, t) with the parameters as a
    vector argument, the KKT system built with `np.block` on every call and solved with
    `numpy.linalg.solve`; same initial state as `seed_rhs_strict`."""
    d = direct(model)
    n, m = len(model["q"]), len(model["Phi"])
    ps = model["params"]
    q, qd, p, t = model["q"], model["qd"], list(ps.keys()), model["t"]
    pv = np.array(list(ps.values()))
    f = lambda e: sp.lambdify((q, qd, p, t), sp.Matrix(e))
    M_f, C_f, g_f, tau_f = f(d["M"]), f(d["Cqd"]), f(d["g"]), f(model["tau"])
    Phiq_f, gamma_f, Phi_f = f(d["Phi_q"]), f(d["gamma"]), f(d["Phi"])

    def rhs(t, y):
        q, qd = y[:n], y[n:]
        M = M_f(q, qd, pv, t)
        J = Phiq_f(q, qd, pv, t)
        A = np.block([[M, J.T], [J, np.zeros((m, m))]])
        F = tau_f(q, qd, pv, t) - C_f(q, qd, pv, t) - g_f(q, qd, pv, t)
        b = np.concatenate([F.ravel(), gamma_f(q, qd, pv, t).ravel()])
        x = np.linalg.solve(A, b)
        return np.concatenate([qd, x[:n]])

    y0 = seed_initial_state(ps, lambda q0: Phiq_f(q0, np.zeros(n), pv, 0.0))
    return rhs, y0, lambda t, y: Phi_f(y[:n], y[n:], pv, t)


def seed_solve(problem, rtol, reference=None):
    """One timed solve_ivp(DOP853, rtol = atol = rtol) of 10 s of a `seed_rhs_*` problem."""
    from scipy.integrate import solve_ivp

    rhs, y0, phi = problem
    n = len(y0) // 2
    t0, c0 = time.perf_counter(), time.thread_time()
    sol = solve_ivp(rhs, (0, 10), y0, method="DOP853", rtol=rtol, atol=rtol)
    wall, cpu = time.perf_counter() - t0, time.thread_time() - c0
    qend = sol.y[:n, -1]
    max_phi = max(np.abs(phi(sol.t[k], sol.y[:, k])).max() for k in range(sol.y.shape[1]))
    err = float(np.abs(qend - np.array(reference)).max()) if reference is not None else None
    return dict(wall_s=wall, cpu_s=cpu, steps=int(len(sol.t) - 1), rhs=int(sol.nfev), us_per_rhs=wall / sol.nfev * 1e6,
                q_end=list(map(float, qend)), max_phi=float(max_phi), error=err)


def seed_scipy(model, rtol, reference=None):
    """scipy DOP853 on the seed with lambdify(cse=True) (see `seed_rhs_strict`)."""
    return seed_solve(seed_rhs_strict(model), rtol, reference)


def seed_scipy_default(model, rtol, reference=None):
    """scipy DOP853 on the seed with lambdify's defaults (see `seed_rhs_default`)."""
    return seed_solve(seed_rhs_default(model), rtol, reference)


def seed_initial_state(ps, phiq):
    """Consistent initial state (ERRATA item 2): closed forms, then Phi_q q' = 0 with phi' = 2 pi."""
    P = {s.name: v for s, v in ps.items()}
    g0 = np.arccos((P["h"] + P["l1"]) / P["l2"])
    b0 = np.arcsin(P["d"] / (P["l2"] * np.sin(g0)))
    q0 = np.array([0.0, b0, g0, 0.2])
    J = phiq(q0)
    qd0 = np.zeros(len(q0))
    qd0[0] = 2 * np.pi
    qd0[1:] = np.linalg.solve(J[:, 1:], -J[:, 0] * qd0[0])
    return np.concatenate([q0, qd0])


# ---------------------------------------------------------------- main
def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--chains", type=int, nargs="*", default=[4, 8, 16])
    ap.add_argument("--lagranges", type=int, nargs="*", default=[4, 8, 16])
    a = ap.parse_args()
    os.makedirs(RESULTS, exist_ok=True)
    path = os.path.join(RESULTS, "baselines.json")
    # Merge into earlier results, so that partial reruns (e.g. `--chains` with no sizes)
    # keep the rest.
    # Only what this run measured is written: `save` rereads the file and merges this run's
    # entries into it (two entries deep), so that concurrent runs (e.g. a long N = 32
    # LagrangesMethod run in the background) do not overwrite each other.
    out = {"sympy": sp.__version__, "variants": VARIANTS}

    def save():
        old = json.load(open(path)) if os.path.exists(path) else {}
        for k, v in out.items():
            if isinstance(v, dict) and isinstance(old.get(k), dict):
                for kk, vv in v.items():
                    if isinstance(vv, dict) and isinstance(old[k].get(kk), dict):
                        old[k][kk].update(vv)
                    else:
                        old[k][kk] = vv
            else:
                old[k] = v
        tmp = path + f".tmp{os.getpid()}"
        json.dump(old, open(tmp, "w"), indent=1)
        os.replace(tmp, path)

    out.setdefault("derivation", {})
    for n in a.chains:
        dt, dc, d = timed_cpu(lambda: direct(chain_direct(n)))
        ct, (repl, red) = timed(lambda: sp.cse([e for k in ("M", "Cqd", "g", "Phi", "Phi_q", "gamma") for e in d[k]]))
        ops = int(sum(sp.count_ops(r) for _, r in repl) + sum(sp.count_ops(r) for r in red))
        entry = dict(direct_s=dt, direct_cpu_s=dc, cse_s=ct, ops_after_cse=ops, direct_load=load_avg())
        print(f"SymPy direct chain N = {n}: {dt:.2f} s (cpu {dc:.2f} s; + cse {ct:.2f} s, {ops} ops), load {entry['direct_load']}", flush=True)
        out["derivation"][str(n)] = entry
        save()  # before LagrangesMethod, which takes minutes at N = 32
        if n in a.lagranges:
            lt, lc, _ = timed_cpu(chain_lagranges, n)
            entry["lagranges_s"] = lt
            entry["lagranges_cpu_s"] = lc
            entry["lagranges_load"] = load_avg()
            print(f"SymPy LagrangesMethod chain N = {n}: {lt:.2f} s (cpu {lc:.2f} s), load {entry['lagranges_load']}", flush=True)
            save()

    print(f"wrote {path}")


if __name__ == "__main__":
    sys.exit(main())
