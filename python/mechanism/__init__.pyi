"""Type stubs of the `mechanism` package (the native module `mechanism._native` and the
result classes of `mechanism._results`), so that editors complete the API."""

from typing import Any, Dict, List, Literal, Mapping, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

from ._results import InverseResult as InverseResult
from ._results import Linearization as Linearization
from ._results import Trajectory as Trajectory

ArrayLike = npt.ArrayLike
Frame = Union[str, int]

class MechanismError(Exception):
    """Every failure of this package; its message is the command-line tool's one line."""

class DeclarationError(MechanismError):
    """A declaration or URDF that cannot be read, parsed, checked or derived
    (`file:line:column: message` where it has a place)."""

class InputError(MechanismError):
    """An argument that cannot be used: an unknown name, a value out of range, a wrong shape."""

class SolverError(MechanismError):
    """A computation that cannot go on at the state it reached."""

class AssemblyError(SolverError):
    """The constraints cannot be closed from the given state."""

class SingularError(SolverError):
    """The motion or a drive is not determined there (singular configuration, conflicting
    drives, no steady state)."""

class IntegrationError(SolverError):
    """A run that stops midway (step size, NaN, divergence, too many steps)."""

class Model:
    """A mechanism loaded by `load`: its declaration, parameter values and the system
    derived from them. Immutable; a call's `set` runs on a copy. Pickles to its text and
    parameter values."""

    @property
    def name(self) -> str:
        """The declared struct's name."""
    @property
    def coordinates(self) -> List[str]:
        """The coordinate names, in the order of q."""
    @property
    def parameters(self) -> List[Tuple[str, float]]:
        """(name, value) of every parameter, in declaration order."""
    @property
    def independent(self) -> List[str]:
        """The independent coordinates a run starts from."""
    @property
    def frames(self) -> List[str]:
        """The link frames (`link` sections, a URDF's links), in declaration order."""
    @property
    def n(self) -> int:
        """Coordinates n."""
    @property
    def m(self) -> int:
        """Constraint rows m (position and velocity rows)."""
    @property
    def source(self) -> str:
        """The declaration text (for a URDF, the declaration it imports as)."""
    def equations(self, latex: bool = False) -> str:
        """The derived equations as text, or LaTeX."""
    def mass_matrix(self, q: ArrayLike, t: float = 0.0) -> np.ndarray:
        """M(q): (n, n) for one state, (rows, n, n) for a batch of rows."""
    def bias(self, q: ArrayLike, v: ArrayLike, t: float = 0.0) -> np.ndarray:
        """b = C(q, v) v + g(q) - tau(t, q, v): (n,) or (rows, n)."""
    def inverse_dynamics(
        self, q: ArrayLike, v: ArrayLike, a: ArrayLike, t: float = 0.0
    ) -> np.ndarray:
        """u = M(q) a + b, the effort giving the accelerations a with no constraint acting
        (Pinocchio's `rnea`): (n,) or (rows, n)."""
    def forward_dynamics(
        self, q: ArrayLike, v: ArrayLike, tau: ArrayLike, t: float = 0.0
    ) -> np.ndarray:
        """q'' under the effort tau added to the declared forces, the constraints acting
        (Pinocchio's `aba` for a robot): (n,) or (rows, n)."""
    def inverse_dynamics_derivatives(
        self, q: ArrayLike, v: ArrayLike, a: ArrayLike, t: float = 0.0
    ) -> Tuple[np.ndarray, np.ndarray]:
        """(du/dq, du/dv) of the inverse dynamics u = M(q) a + C(q, v) v + g(q) - tau
        (Pinocchio's `computeRNEADerivatives`; du/da is `mass_matrix`): (n, n) each, or
        (rows, n, n) for a batch."""
    def inverse_dynamics_parameter_derivatives(
        self, q: ArrayLike, v: ArrayLike, a: ArrayLike, t: float = 0.0
    ) -> np.ndarray:
        """du/dp by the declared parameters (columns in the order of `parameters`):
        (n, p) or (rows, n, p)."""
    def forward_dynamics_derivatives(
        self, q: ArrayLike, v: ArrayLike, tau: ArrayLike, t: float = 0.0
    ) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(dq''/dq, dq''/dv, dq''/dtau) of `forward_dynamics`, the constraints acting
        (Pinocchio's `computeABADerivatives` for a robot: dq''/dtau = M^-1): (n, n) each,
        or (rows, n, n)."""
    def constrained_dynamics_derivatives(
        self, q: ArrayLike, v: ArrayLike, tau: ArrayLike, t: float = 0.0
    ) -> Dict[str, np.ndarray]:
        """q'' and the multipliers lambda of the augmented system and their derivatives:
        keys `qdd` (n,), `lambda` (m,), `dqdd_dq`, `dqdd_dv`, `dqdd_dtau` (n, n),
        `dlambda_dq`, `dlambda_dv`, `dlambda_dtau` (m, n); a batch adds a leading axis of
        rows. Rows found redundant keep lambda = 0 and zero derivatives."""
    def frame_placement(self, frame: Frame, q: ArrayLike) -> np.ndarray:
        """The frame's placement as 4 x 4 transforms [[R, p], [0, 0, 0, 1]] (world axes):
        (4, 4) or (rows, 4, 4)."""
    def frame_jacobian(self, frame: Frame, q: ArrayLike) -> np.ndarray:
        """J with [v; w] = J q' in world axes (Pinocchio's LOCAL_WORLD_ALIGNED):
        (6, n) or (rows, 6, n)."""
    def simulate(
        self,
        *,
        t_end: float = 10.0,
        rtol: float = 1e-10,
        atol: float = 1e-10,
        integrator: str = "dop853",
        step: Optional[float] = None,
        samples_per_second: float = 100.0,
        stabilization: str = "projection",
        set: Optional[Mapping[str, float]] = None,
        init: Optional[Mapping[str, float]] = None,
    ) -> Trajectory:
        """Simulates from the state assembled from the independent coordinates, as
        `mechanism simulate` does (integrator: rk4, dopri5, dop853 or hht; stabilization:
        projection, baumgarte or none; init: {"x": position, "der(x)": rate})."""
    def inverse(
        self,
        drives: Sequence[str],
        *,
        t_end: float = 1.0,
        samples_per_second: float = 100.0,
        set: Optional[Mapping[str, float]] = None,
        init: Optional[Mapping[str, float]] = None,
    ) -> InverseResult:
        """The driving forces along prescribed motions (`"phi = 2*pi*t"`), as
        `mechanism inverse` computes them."""
    def linearize(
        self,
        *,
        set: Optional[Mapping[str, float]] = None,
        init: Optional[Mapping[str, float]] = None,
    ) -> Linearization:
        """The linearisation about the equilibrium or steady motion the independent
        coordinates give, in minimal variables, as `mechanism linearize` computes it."""

@overload
def load(
    name_or_path: str,
    *,
    lock: Optional[Sequence[str]] = None,
    set: Optional[Mapping[str, float]] = None,
    damping: bool = False,
    floating: Literal[True],
) -> FloatingModel: ...
@overload
def load(
    name_or_path: str,
    *,
    lock: Optional[Sequence[str]] = None,
    set: Optional[Mapping[str, float]] = None,
    damping: bool = False,
    floating: bool = False,
) -> Union[Model, FloatingModel]:
    """A built-in name (`builtin_names()`), a `.mech` file or a URDF (`.urdf`, with the
    joints `lock` fixed at 0, when `damping` its joints' damping, when `floating` its root
    link free), derived at run time; `set` changes parameters from their declared values.
    A declaration whose root link floats gives a `FloatingModel`, any other a `Model`."""

def from_source(
    text: str, *, name: str = "<text>", set: Optional[Mapping[str, float]] = None
) -> Union[Model, FloatingModel]:
    """The model of a declaration text given directly (a `FloatingModel` when its root
    floats)."""

class FloatingModel:
    """A robot whose root link floats, in Pinocchio's free-flyer layout: q = [position (3),
    quaternion x, y, z, w, joints] (nq = 7 + joints), v = [velocity, angular velocity (both
    in the root's axes), joint rates] (nv = 6 + joints)."""

    @property
    def name(self) -> str: ...
    @property
    def nq(self) -> int: ...
    @property
    def nv(self) -> int: ...
    @property
    def configuration(self) -> List[str]:
        """The names of q's entries."""
    @property
    def velocities(self) -> List[str]:
        """The names of v's entries."""
    @property
    def parameters(self) -> List[Tuple[str, float]]: ...
    def neutral(self) -> npt.NDArray[np.float64]:
        """The root at the origin, quaternion (0, 0, 0, 1), the joints at their guesses."""
    def mass_matrix(self, q: ArrayLike) -> npt.NDArray[np.float64]:
        """M(q), nv x nv (Pinocchio's crba)."""
    def bias(self, q: ArrayLike, v: ArrayLike, t: float = 0.0) -> npt.NDArray[np.float64]:
        """C(q, v) v + g(q) - tau (Pinocchio's nonLinearEffects)."""
    def gravity(self, q: ArrayLike) -> npt.NDArray[np.float64]:
        """g(q) (Pinocchio's computeGeneralizedGravity)."""
    def inverse_dynamics(
        self, q: ArrayLike, v: ArrayLike, a: ArrayLike, t: float = 0.0
    ) -> npt.NDArray[np.float64]:
        """M a + C v + g - tau (Pinocchio's rnea)."""
    def forward_dynamics(
        self, q: ArrayLike, v: ArrayLike, tau: Optional[ArrayLike] = None, t: float = 0.0
    ) -> npt.NDArray[np.float64]:
        """a = M^-1 (tau - b) (Pinocchio's aba); SingularError where M is singular."""
    def integrate(self, q: ArrayLike, v: ArrayLike, dt: float) -> npt.NDArray[np.float64]:
        """q moved by v for dt on SE(3) x R^joints (Pinocchio's integrate(q, v dt))."""
    def kinetic_energy(self, q: ArrayLike, v: ArrayLike) -> float: ...
    def potential_energy(self, q: ArrayLike) -> float: ...
    def simulate(
        self,
        t_end: float,
        *,
        q0: Optional[ArrayLike] = None,
        v0: Optional[ArrayLike] = None,
        step: float = 1e-3,
        every: int = 10,
    ) -> Dict[str, Any]:
        """Fixed RK4 steps with the quaternion projected onto unit norm; a dict of `t`,
        `q` (k x nq), `v` (k x nv), `configuration` and `velocities`."""

def builtin_names() -> List[str]:
    """The names `load` takes without a path."""

def sweep(
    model: Model,
    sets: Sequence[Mapping[str, float]],
    *,
    t_end: float = 10.0,
    rtol: float = 1e-10,
    atol: float = 1e-10,
    integrator: str = "dop853",
    step: Optional[float] = None,
    samples_per_second: float = 100.0,
    stabilization: str = "projection",
    init: Optional[Mapping[str, float]] = None,
    threads: Optional[int] = None,
) -> List[Trajectory]:
    """One simulation per parameter set, in parallel on this machine; the trajectories in
    the order of `sets`, each equal to `model.simulate(set=s, ...)`."""

__all__: List[str]
