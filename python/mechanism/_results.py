"""The results of a model's runs: plain dataclasses of numpy arrays and figures, so they
pickle (a Ray task or a Dask function can return one) and print readably."""

from dataclasses import dataclass, field
from typing import Dict, List

import numpy as np


@dataclass(repr=False)
class Trajectory:
    """A simulation: the samples (one a row) and the figures ``mechanism simulate`` prints
    and writes to ``summary.json``.

    ``q``, ``qd``, ``qdd`` are (samples x n), ``multipliers`` (samples x m); ``t`` and the
    energies and residuals one value per sample. ``work`` is W, the work since t = 0 of the
    declared forces and of constraint rows that move with t, so T + Pi - W is constant for
    an exact solution; ``max_energy_balance_error`` is its largest change.
    """

    mechanism: str
    coordinates: List[str]
    parameters: Dict[str, float]
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    multipliers: np.ndarray
    kinetic: np.ndarray
    potential: np.ndarray
    work: np.ndarray
    constraint_error: np.ndarray
    velocity_constraint_error: np.ndarray
    q0: np.ndarray
    qd0: np.ndarray
    max_constraint_error: float
    max_velocity_constraint_error: float
    max_energy_balance_error: float
    energy_depends_on_time: bool
    steps: int
    rejected_steps: int
    rhs_evaluations: int
    wall_time_s: float
    singular_passages: int

    def __repr__(self) -> str:
        return (
            f"<Trajectory of {self.mechanism}: {len(self.t)} samples to t = {self.t[-1]:g} s, "
            f"{self.steps} steps ({self.rejected_steps} rejected), "
            f"max |Phi| {self.max_constraint_error:.3e}, "
            f"max |T + Pi - W - (T + Pi)(0)| {self.max_energy_balance_error:.3e} J>"
        )


@dataclass(repr=False)
class InverseResult:
    """Inverse dynamics along prescribed motions: the samples (one a row), the driving
    generalised force on each driven coordinate (``driving``, samples x drives, in the
    order of ``driven``) and the multipliers (samples x m)."""

    coordinates: List[str]
    driven: List[str]
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    driving: np.ndarray
    multipliers: np.ndarray

    def __repr__(self) -> str:
        peaks = ", ".join(
            f"{name}: max |tau| {np.abs(self.driving[:, k]).max():.6e}"
            for k, name in enumerate(self.driven)
        )
        return f"<InverseResult over {len(self.t)} samples; {peaks}>"


@dataclass(repr=False)
class Linearization:
    """The linearisation about an equilibrium or a steady motion in minimal variables:
    ``state_matrix`` A of x' = A x over ``variables``, its ``eigenvalues`` (complex), the
    variables that give structural zeros, and the eigenvalues without them."""

    variables: List[str]
    state_matrix: np.ndarray
    eigenvalues: np.ndarray
    structural_zeros: List[str]
    reduced_eigenvalues: np.ndarray
    parameters: Dict[str, float] = field(default_factory=dict)

    def __repr__(self) -> str:
        return (
            f"<Linearization in {len(self.variables)} variables: "
            f"eigenvalues {np.array2string(np.sort_complex(self.reduced_eigenvalues), precision=6)}>"
        )
