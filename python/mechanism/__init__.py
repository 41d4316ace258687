"""Closed-loop mechanisms and robots from Python.

A declaration (a built-in name, a ``.mech`` file or a robot's URDF) is derived at run time
by the ``mechanism`` crate's interpreter route; the model simulates it with its loops
closed to machine precision, computes driving forces along prescribed motions, linearises
it, and evaluates a robot's dynamics, frames and Jacobians for one state or a batch.

>>> import mechanism
>>> seed = mechanism.load("spatial_crank_slider")
>>> run = seed.simulate(t_end=1.0)
>>> run.q.shape
(101, 4)
"""

from ._native import (
    AssemblyError,
    DeclarationError,
    FloatingModel,
    InputError,
    IntegrationError,
    MechanismError,
    Model,
    SingularError,
    SolverError,
    builtin_names,
    from_source,
    load,
    sweep,
)
from ._results import InverseResult, Linearization, Trajectory

__all__ = [
    "AssemblyError",
    "DeclarationError",
    "FloatingModel",
    "InputError",
    "IntegrationError",
    "InverseResult",
    "Linearization",
    "MechanismError",
    "Model",
    "SingularError",
    "SolverError",
    "Trajectory",
    "builtin_names",
    "from_source",
    "load",
    "sweep",
]
