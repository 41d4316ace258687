"""CasADi's automatic differentiation of Pinocchio's algorithms, for the derivatives benchmark
(benches/derivatives.py, which runs this in the CasADi environment): `cmeel-casadi-kin-dyn`
traces `rnea` and `aba` (its Pinocchio 2.6) into SX expressions, `casadi.jacobian` takes
their Jacobians, and each function is built with common subexpressions eliminated
(`cse: True`) and written as C by `casadi.CodeGenerator`:

    rnea_derivatives(q, v, a) -> (dtau/dq, dtau/dv)          (computeRNEADerivatives)
    aba_derivatives(q, v, tau) -> (da/dq, da/dv, da/dtau)     (computeABADerivatives)

    python derivatives_codegen.py ROBOT URDF OUT_DIR [LOCKED_JOINT ...]

The locked joints are fixed at q = 0; a floating root is omitted (the base fixed, as our
import writes it). Writes OUT_DIR/casadi_derivatives.c and .h, and prints one JSON line: nq
and each function's arithmetic operation count (SX instructions other than inputs, outputs
and constants, as casadi_codegen.py counts them).
"""

import json
import os
import sys

import casadi as cs
from casadi_kin_dyn.casadi_kin_dyn import CasadiKinDyn

from casadi_codegen import arithmetic


def main():
    robot, urdf, out_dir, locked = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
    kd = CasadiKinDyn(open(urdf).read(), CasadiKinDyn.JointType.OMIT, False, {j: 0.0 for j in locked})
    n = kd.nv()
    q, v, a, tau = (cs.SX.sym(name, n) for name in ("q", "v", "a", "tau"))
    options = {"cse": True}
    t = kd.rnea()(q, v, a)
    qdd = kd.aba()(q, v, tau)
    fs = [cs.Function("rnea_derivatives", [q, v, a], [cs.jacobian(t, q), cs.jacobian(t, v)], options),
          cs.Function("aba_derivatives", [q, v, tau],
                      [cs.jacobian(qdd, q), cs.jacobian(qdd, v), cs.jacobian(qdd, tau)], options)]
    os.makedirs(out_dir, exist_ok=True)
    cg = cs.CodeGenerator("casadi_derivatives.c", {"with_header": True})
    for f in fs:
        cg.add(f)
    cg.generate(out_dir + os.sep)
    print(json.dumps(dict(robot=robot, nq=n, ops={f.name(): arithmetic(f)[0] for f in fs})))


if __name__ == "__main__":
    main()
