"""SymPy's C, built once and timed the way the harness times our generated code.

Both sides get the same inputs (the harness's assembled state: x = [q, q', parameters, t]),
write into a buffer the caller owns, and change q_0 (x[0]) by 1e-15 before every call; each
run is one untimed batch and `batches` timed batches of `calls` calls, printed as ns per
call. Variants (see BENCHMARKS.md, "What is compared"):

- `strict`: M, C q', g, Phi, Phi_q in ONE function after ONE joint `sympy.cse` (each angle's
  sin and cos once, gcc merges them into `sincos`): the strongest SymPy-C there is;
- `strict10`: the same for the ten outputs of our `evaluate_into` (adds tau, Phi_t, gamma,
  T and Pi): the like-for-like program;
- `per_routine`: `sympy.utilities.codegen`'s `C99CodeGen(cse=True)`, one CSE'd routine per
  matrix, called in turn from another file (what a SymPy user gets).

gcc -O3 -march=native, one object per file (nothing inlined across files). The C depends on
the `.mech` file, this generator and gcc only, never on our tree: `built` keeps each build
with its key and builds again only when one of them changed.
"""

import hashlib
import json
import os
import subprocess
import time

import sympy as sp

from baselines import c_code, c_code_per_routine, direct, libm_calls, read_mech

C_MAIN = r"""
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
void all5(const double *x, double *out);
static double now(void) { struct timespec ts; clock_gettime(CLOCK_MONOTONIC, &ts); return ts.tv_sec + 1e-9 * ts.tv_nsec; }
int main(int argc, char **argv) {
    long batches = atol(argv[1]), calls = atol(argv[2]);
    double x[NX], out[NOUT];
    for (int i = 0; i < NX; i++) x[i] = atof(argv[3 + i]);
    for (long b = -1; b < batches; b++) {
        double t0 = now();
        for (long k = 0; k < calls; k++) {
            x[0] += 1e-15;
            all5(x, out);
            __asm__ volatile("" : : "r"(out) : "memory");
        }
        double ns = (now() - t0) / calls * 1e9;
        if (b >= 0) printf("%.4f\n", ns);
    }
    return 0;
}
"""

VARIANTS = ("strict", "strict10", "per_routine")


def five(d):
    """M, C q', g, Phi, Phi_q, entry by entry."""
    return list(d["M"]) + list(d["Cqd"]) + list(d["g"]) + list(d["Phi"]) + list(d["Phi_q"])


def ten(d, model):
    """The ten outputs of our evaluate: M, C q', g, tau, Phi, Phi_q, Phi_t, gamma, T, Pi."""
    t = model["t"]
    phi_t = [sp.diff(e, t) for e in d["Phi"]]
    return (list(d["M"]) + list(d["Cqd"]) + list(d["g"]) + list(model["tau"]) + list(d["Phi"])
            + list(d["Phi_q"]) + phi_t + list(d["gamma"]) + [model["T"], model["Pi"]])


def built(mech_path, workdir):
    """{variant: build info} of the SymPy C of the `.mech` file at `mech_path`, built under
    `workdir/<variant>`, or the builds already there when their key (the file, the
    generators' sources, SymPy's and gcc's versions) is this one. `build_s` is the time the
    build took when it was made."""
    here = os.path.dirname(os.path.abspath(__file__))
    key = hashlib.sha256()
    for path in (mech_path, os.path.join(here, "c_peer.py"), os.path.join(here, "baselines.py")):
        with open(path, "rb") as f:
            key.update(f.read())
    gcc = subprocess.run(["gcc", "--version"], capture_output=True, text=True).stdout
    key.update((sp.__version__ + gcc).encode())
    key = key.hexdigest()
    stamp = os.path.join(workdir, "built.json")
    if os.path.exists(stamp):
        with open(stamp) as f:
            old = json.load(f)
        if old.get("key") == key and all(os.path.exists(i["exe"]) for i in old["variants"].values()):
            return old["variants"]
    model = read_mech(mech_path)
    d = direct(model)
    out = {}
    for v in VARIANTS:
        t0 = time.perf_counter()
        out[v] = build(model, d, v, os.path.join(workdir, v))
        out[v]["build_s"] = time.perf_counter() - t0
    with open(stamp, "w") as f:
        json.dump(dict(key=key, variants=out), f, indent=1)
    return out


def build(model, d, variant, workdir):
    """Compiles `variant` of `model`'s SymPy C (`d`: its direct derivation) into `workdir`;
    returns a dict with the executable, nx, nout, the operation count and the libm calls of
    the computing object."""
    os.makedirs(workdir, exist_ok=True)
    if variant == "per_routine":
        src, header, caller, nx, nout, ops = c_code_per_routine(model, d)
        files = {"routines.c": src, "routines.h": header, "calls.c": caller}
        computing = "routines.o"
    else:
        exprs = five(d) if variant == "strict" else ten(d, model)
        src, nx, nout, ops = c_code(model, exprs)
        files = {"f.c": src}
        computing = "f.o"
    files["main.c"] = C_MAIN
    objs = []
    for name, text in files.items():
        with open(os.path.join(workdir, name), "w") as f:
            f.write(text)
    for name in files:
        if name.endswith(".c"):
            o = os.path.join(workdir, name[:-2] + ".o")
            subprocess.run(["gcc", "-O3", "-march=native", f"-DNX={nx}", f"-DNOUT={nout}", "-c",
                            os.path.join(workdir, name), "-o", o], check=True, cwd=workdir)
            objs.append(o)
    exe = os.path.join(workdir, "bench")
    subprocess.run(["gcc"] + objs + ["-lm", "-o", exe], check=True)
    return dict(exe=exe, nx=nx, nout=nout, ops=ops, libm=libm_calls(os.path.join(workdir, computing)))


def run(exe, x, batches, calls):
    """ns per call of each timed batch."""
    out = subprocess.run([exe, str(batches), str(calls)] + [repr(float(v)) for v in x],
                         check=True, capture_output=True, text=True).stdout
    return [float(v) for v in out.split()]
