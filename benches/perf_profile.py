"""Where a harness run spends its time: `perf record` of the seed simulation, the self time of
each symbol (perf report --no-children), grouped into the parts the tables name."""

import os
import re
import shutil
import subprocess
import tempfile

# (part, pattern on the symbol), first match wins; anything else is "other".
PARTS = [
    ("generated evaluate", r"Mechanism<.*>>::evaluate|evaluate_into"),
    ("other generated functions", r"Mechanism<.*>>::(constraints|constraint_jacobian|mass_matrix|gravity)"),
    ("null-space factor", r"NullSpace.*factor"),
    ("null-space solve", r"NullSpace.*solve"),
    ("LU factor", r"kernels::factor|Lu::factor"),
    ("LU solve", r"kernels::solve$|kernels::solve<|Lu::solve$"),
    ("condition estimate", r"solve_transpose|condition_estimate"),
    ("Dynamics::solve (assembly, checks)", r"Dynamics::solve"),
    ("Compiled::evaluate (copies)", r"Compiled<.*>.*::evaluate"),
    ("DOP853 stages and error", r"Dop853"),
    ("projection", r"Projector|RowSpans|Envelope|factor_gram"),
    ("right-hand side glue", r"Rhs as .*OdeRhs"),
    ("memcpy, memset", r"memmove|memcpy|memset"),
    ("libm", r"sincos|__sin|__cos"),
]


def perf_available():
    return shutil.which("perf") is not None


def profile(exe, model="seed", runs=40, tol=1e-10):
    """[(part, self %)] for `runs` simulations of `model`, largest first; None without perf."""
    if not perf_available():
        return None
    with tempfile.TemporaryDirectory() as d:
        data = os.path.join(d, "perf.data")
        r = subprocess.run(["perf", "record", "-F", "4999", "-o", data, exe, "simulate", model, str(runs), str(tol)],
                           capture_output=True, text=True)
        if r.returncode != 0:
            return None
        rep = subprocess.run(["perf", "report", "-i", data, "--no-children", "--stdio", "--sort", "symbol"],
                             capture_output=True, text=True).stdout
    shares = {}
    for line in rep.splitlines():
        m = re.match(r"\s+([\d.]+)%\s+\[[.k]\]\s+(.*)$", line)
        if not m:
            continue
        pct, sym = float(m.group(1)), m.group(2).strip()
        part = next((p for p, pat in PARTS if re.search(pat, sym)), "other")
        shares[part] = shares.get(part, 0.0) + pct
    return sorted(shares.items(), key=lambda kv: -kv[1])
