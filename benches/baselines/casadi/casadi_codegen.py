"""CasADi's side of the CasADi baseline (run by casadi_bench.py in the CasADi environment):
Pinocchio's own algorithms traced into CasADi SX expressions by `cmeel-casadi-kin-dyn`
(`CasadiKinDyn(urdf).crba()`, `.rnea()`, `.aba()`, with its Pinocchio 2.6), one function per
routine, each built with common subexpressions eliminated (`cse: True`), written as C by
`casadi.CodeGenerator`:

    crba(q) -> M                 rnea(q, v, a) -> tau
    bias(q, v) -> rnea(q, v, 0)  mass_bias(q, v) -> (M, rnea(q, v, 0))
    aba(q, v, tau) -> a

    python casadi_codegen.py ROBOTS.json OUT_DIR

ROBOTS.json: {name: {"urdf": path, "lock": [joint, ...]}}; the locked joints are fixed at
q = 0 (`fixed_joints`). Writes OUT_DIR/<name>/casadi.c and .h and OUT_DIR/<name>/meta.json:
the joint names in CasADi's order, and per function its arithmetic operation count (every
SX instruction but inputs, outputs and constants), CasADi's `n_instructions` and its work
sizes.
"""

import json
import os
import sys

import casadi as cs
from casadi_kin_dyn.casadi_kin_dyn import CasadiKinDyn

# SX operations that are not arithmetic: reading inputs, writing outputs, constants.
NOT_ARITHMETIC = {cs.OP_INPUT, cs.OP_OUTPUT, cs.OP_CONST, cs.OP_PARAMETER}


def arithmetic(f):
    """The arithmetic operations of an SXFunction, and of them the calls (sin, cos, sqrt...)."""
    ops = calls = 0
    simple = {cs.OP_ADD, cs.OP_SUB, cs.OP_MUL, cs.OP_DIV, cs.OP_NEG, cs.OP_SQ, cs.OP_TWICE, cs.OP_ASSIGN}
    for k in range(f.n_instructions()):
        op = f.instruction_id(k)
        if op in NOT_ARITHMETIC:
            continue
        ops += 1
        if op not in simple:
            calls += 1
    return ops, calls


def functions(kd):
    n = kd.nv()
    q, v, a, tau = (cs.SX.sym(name, n) for name in ("q", "v", "a", "tau"))
    m = kd.crba()(q)
    bias = kd.rnea()(q, v, cs.SX.zeros(n))
    options = {"cse": True}
    return [
        cs.Function("crba", [q], [m], options),
        cs.Function("bias", [q, v], [bias], options),
        cs.Function("mass_bias", [q, v], [m, bias], options),
        cs.Function("rnea", [q, v, a], [kd.rnea()(q, v, a)], options),
        cs.Function("aba", [q, v, tau], [kd.aba()(q, v, tau)], options),
    ]


def main():
    robots = json.load(open(sys.argv[1]))
    out_dir = sys.argv[2]
    for name, r in robots.items():
        urdf = open(r["urdf"]).read()
        fixed = {j: 0.0 for j in r["lock"]}
        kd = CasadiKinDyn(urdf, CasadiKinDyn.JointType.OMIT, False, fixed)
        d = os.path.join(out_dir, name)
        os.makedirs(d, exist_ok=True)
        cg = cs.CodeGenerator("casadi.c", {"with_header": True})
        meta = dict(nq=kd.nq(), joints=[j for j in kd.joint_names() if j != "universe"], functions={})
        for f in functions(kd):
            cg.add(f)
            ops, calls = arithmetic(f)
            meta["functions"][f.name()] = dict(ops=ops, calls=calls, n_instructions=f.n_instructions(),
                                               sz_arg=f.sz_arg(), sz_res=f.sz_res(), sz_iw=f.sz_iw(),
                                               sz_w=f.sz_w())
        cg.generate(d + os.sep)
        with open(os.path.join(d, "meta.json"), "w") as fh:
            json.dump(meta, fh, indent=1)
        print(f"{name}: nq {kd.nq()}, " + ", ".join(f"{k} {v['ops']} ops" for k, v in meta["functions"].items()))


if __name__ == "__main__":
    main()
