//! # The declaration language
//!
//! What [`mechanism!`](crate::mechanism) reads, inline or from a `.mech` file, and what
//! `mechanism simulate FILE.mech` derives at run time ([`Interpreted`](crate#features)):
//! one grammar, written in Rust tokens (`//` comments; `///` lines before the struct become
//! its docs). This page is the reference: the grammar, every section, every function, and
//! the mistakes that are refused at compile time.
//!
//! ## A complete declaration
//!
//! The seed paper's spatial crank-slider, in energies and constraints:
//!
//! ```
//! use mechanism::prelude::*;
//!
//! mechanism! {
//!     /// The seed paper's spatial crank-slider.
//!     pub struct CrankSlider;
//!     parameters {
//!         h = 0.12; l1 = 0.08; l2 = 0.3; d = 0.1; alpha = 0.0;   // m, rad
//!         m1 = 0.12; m2 = 0.5; m3 = 2.0; J1 = 1e-4; a1 = 0.04;   // kg, kg m^2, m
//!         g = 9.81; tau0 = 0.005; Omega = 2*pi;
//!     }
//!     coordinates { phi = 0.0; beta = 0.46; gamma = 0.84; x_c = 0.2; }
//!     independent { phi = 0.0; der(phi) = 2*pi; }
//!     kinetic = 1/2*(J1 + m2/2*l1^2)*der(phi)^2 + 1/2*(m2/2 + m3)*der(x_c)^2;
//!     potential = m1*g*(a1*cos(phi) + h) + m2/2*g*(l1*cos(phi) + h);
//!     constraints {
//!         l1*sin(phi)*sin(alpha) + l2*sin(gamma)*cos(beta) - x_c;
//!         -l1*sin(phi)*cos(alpha) + l2*sin(gamma)*sin(beta) - d;
//!         h + l1*cos(phi) - l2*cos(gamma);
//!     }
//!     forces { phi: tau0*sin(Omega*t); }
//!     point O = [0, 0, h];
//!     point A = [l1*sin(phi)*sin(alpha), -l1*sin(phi)*cos(alpha), h + l1*cos(phi)];
//!     point C = [x_c, d, 0];
//!     draw { line O, A, C; trace A; }
//! }
//!
//! assert_eq!(CrankSlider::COORDINATES, ["phi", "beta", "gamma", "x_c"]);
//! assert_eq!((CrankSlider::N, CrankSlider::M), (4, 3));
//! ```
//!
//! The same text in a file is `mechanism!(file = "crank_slider.mech");` (the path relative
//! to the crate's `CARGO_MANIFEST_DIR`, or else to the invoking source file). An error in a
//! file is reported at the path literal with the file's line and column and the line itself:
//!
//! ```text
//! error: broken.mech:8:20: parse error: expected a number, a name or `(`, found `;`
//!        8 | potential = m*g*y +;
//!          |                    ^
//! ```
//!
//! ## Grammar
//!
//! ```text
//! declaration := doc* ["pub"] "struct" NAME ";" section*
//! section     := "parameters"  "{" (NAME "=" expr [range] ";")* "}"
//!              | "coordinates" "{" (NAME "=" expr ";")* "}"
//!              | "independent" "{" ((NAME | "der" "(" NAME ")") "=" expr ";")* "}"
//!              | "kinetic" "=" expr ";"
//!              | "potential" "=" expr ";"
//!              | "constraints" "{" (row ";")* "}"
//!              | "velocity_constraints" "{" (row ";")* "}"
//!              | "forces" "{" (NAME ":" expr ";")* "}"
//!              | body_section
//! range       := "positive" | "nonnegative"
//! row         := expr ["=" expr] | vector ["=" vector]
//! vector      := "[" expr ("," expr)* "]"
//!
//! expr        := product (("+" | "-") product)*
//! product     := unary (("*" | "/") unary)*
//! unary       := ("-" | "+") unary | postfix ["^" unary]
//! postfix     := atom ("." ("x" | "y" | "z"))*           (vector expressions only)
//! atom        := NUMBER | NAME | NAME "(" [expr ("," expr)*] ")" | "(" expr ")"
//!              | "[" expr ("," expr)* "]"                 (vector expressions only)
//!
//! body_section := "gravity" "=" vexpr ";"
//!               | "point" NAME "=" vexpr ";"  |  "axis" NAME "=" vexpr ";"
//!               | "body" NAME "{" (body_item ";")* "}"
//!               | "link" NAME "{" (link_item ";")* "}"
//!               | "spring" NAME "{" "between" "=" vexpr "," vexpr ";"
//!                     "stiffness" "=" vexpr ";" ["free_length" "=" vexpr ";"] "}"
//!               | "damper" NAME "{" "between" "=" vexpr "," vexpr ";" "coefficient" "=" vexpr ";" "}"
//!               | "joints" "{" (joint ";")* "}"
//!               | "draw" "{" (("line" NAME ("," NAME)+ | "trace" NAME ("," NAME)*) ";")* "}"
//! body_item    := "mass" "=" vexpr | "position" "=" vexpr | "orientation" "=" vexpr
//!               | "inertia" "=" vexpr | "point" NAME "=" vexpr | "axis" NAME "=" vexpr
//! link_item    := "parent" "=" NAME
//!               | "joint" "=" ("revolute" | "continuous" | "prismatic") "(" NAME "," vexpr ")"
//!               | "joint" "=" "fixed"
//!               | "xyz" "=" vexpr | "rpy" "=" vexpr | "limit" "=" vexpr
//!               | "velocity_limit" "=" expr | "effort_limit" "=" expr
//!               | "mass" "=" vexpr | "com" "=" vexpr | "com_rpy" "=" vexpr | "inertia" "=" vexpr
//!               | "point" NAME "=" vexpr | "axis" NAME "=" vexpr
//! joint        := "spherical" "(" P "," Q ")" | "revolute" "(" P "," Q "," a "," b ")"
//!               | "prismatic" "(" P "," Q "," a "," b ")" | "distance" "(" P "," Q "," L ")"
//!               | "rolling" "(" B "," a "," r ")"
//!               | vexpr ["=" vexpr]
//! ```
//!
//! Sections come in any order, each of the first eight at most once; every statement of a
//! block ends with `;` (the last one too). `vexpr` is an expression of the vector language:
//! the same operators, plus `[..]` columns (`[[..], [..], [..]]` by rows), components
//! `P.x`, `P.y`, `P.z`, the matrix product for `*`, and the vector functions below.
//!
//! ## Sections
//!
//! | section | meaning |
//! |---|---|
//! | `pub struct Name;` | the generated struct (`pub` optional) and its `NameParameters` |
//! | `parameters { l1 = 0.08 positive; Omega = 2*pi; }` | run-time constants with defaults: fields of the struct, changeable without a rebuild. A default is a constant expression (numbers, `pi`, arithmetic, functions, earlier parameters), never a coordinate or `t`; it is evaluated once, with the defaults before it (setting `l1` later does not change a default written with `l1`). A default may be followed by its range: `positive` (> 0: a length, a radius) or `nonnegative` (>= 0: a mass, a moment of inertia). The default must lie in it, and `set_parameter`, `--set` and sweeps refuse a value outside it with the reason |
//! | `coordinates { phi = 0.0; x_c = l1/2; }` | the redundant coordinates q and their initial guesses, which pick the assembly branch. A guess may be written with parameters: it is evaluated at their current values (after `--set`, `set_parameter` or a change of a field) |
//! | `independent { phi = 0.0; der(phi) = Omega; }` | the coordinates set at t = 0 (position, and rate, default 0); the others follow from Phi(q, 0) = 0 and Phi_q q' = -Phi_t. They must fix every degree of freedom. An open tree of links needs none (every coordinate is independent). Values written with parameters follow their current values, as the guesses do |
//! | `kinetic = ...;` | T(q, q', t), a quadratic form in the rates `der(x)` with M positive semi-definite (optional with bodies); t in T or Pi is for the interpreter route only (`mechanism!` refuses it: its `mass_matrix(q)` and `gravity(q)` take no time) |
//! | `potential = ...;` | Pi(q, t) (optional; no rates) |
//! | `constraints { f; lhs = rhs; [a, b] = [c, d]; }` | holonomic rows Phi(q, t) = 0: `lhs = rhs` is lhs - rhs, a vector equation is one row per component. Redundant rows are allowed |
//! | `velocity_constraints { -sin(theta)*der(x) + cos(theta)*der(y); }` | velocity rows A(q, t) q' + a(q, t) = 0, linear in the rates `der(x)` (a row that is not is refused at the row), not integrable to positions: wheels, skates, knife edges. Stacked under the position rows of Phi_q, Phi_t and gamma. A row that is a combination of the rows above it at the assembled state is refused at assembly: redundant, or contradicting them |
//! | `forces { phi: tau0*sin(Omega*t); }` | generalised forces tau(t, q, q') on named coordinates (optional) |
//! | `gravity = [0, 0, -g];` | the gravity vector for bodies and links |
//! | `point P = [..];`, `axis a = [..];` | a world point in q, t and the parameters (ground when it depends on neither q nor t), a world direction |
//! | `body NAME { .. }` | a rigid body: `mass`, `position` (centre of mass, world), `orientation` (body to world: a product of `rot_x`, `rot_y`, `rot_z` or a 3x3 rotation), `inertia` (about the centre, body axes: `diag(..)` or a symmetric 3x3), body-frame `point`s and `axis`es. Without `orientation` it is a point mass |
//! | `link NAME { .. }` | a frame of a kinematic tree, as in URDF: `parent` (default `world`), `joint` (`revolute(q, axis)`, `continuous`, `prismatic`, `fixed`; the joint declares its coordinate; or `floating(base)` on the root link alone: a free-flyer, q = [`base_x`, `base_y`, `base_z`, `base_qx`, .., `base_qw`, joints], v = [`base_vx`, .., `base_wz` in the root's axes, joint rates], and the macro emits `FloatingBase<NQ, NV>` instead of `Mechanism`), `xyz`, `rpy` (joint frame in the parent, R = rot_z(yaw) rot_y(pitch) rot_x(roll)), `limit`, `velocity_limit`, `effort_limit` (not enforced; runs report where they are passed), `mass`, `com`, `com_rpy`, `inertia` (about the com), link-frame `point`s and `axis`es |
//! | `spring NAME { between = P, Q; stiffness = k; free_length = L0; }` | a linear spring: Pi += k/2 (\|P - Q\| - L0)^2 |
//! | `damper NAME { between = P, Q; coefficient = c; }` | a linear damper along P - Q: its generalised forces |
//! | `joints { .. }` | constraint rows between points and axes: `spherical(P, Q)` (3 rows, P = Q), `revolute(P, Q, a, b)` (5 rows: P = Q, a parallel to b), `prismatic(P, Q, a, b)` (5 rows: a parallel to b, P - Q along b, and the turn about the axis kept as declared, at the coordinates' guesses), `distance(P, Q, L)` (1 row, \|P - Q\|^2 = L^2), `rolling(B, a, r)` (a thin wheel, body B of radius r with axle a, rolling on z = 0: its contact height as a position row and the contact point's x and y velocity as two velocity rows; refused when the axle is vertical at the guesses), or any vector equation `P = Q;`, `P.z = 0;`. A row of a statement that is identically zero (the z row and the axis rows of a joint between bodies that move in one plane) is left out, and the equations text names it under Phi; a statement all of whose rows vanish is an error |
//! | `draw { line O, A, B; trace B; }` | the picture: polylines through named points and the points whose paths are traced (the animation page and the strobe figure); a point that moves with neither q nor t is drawn as ground |
//!
//! With bodies, links or springs, T, Pi, M, the spring potentials and the damper forces are
//! derived; a hand-written `kinetic` or `potential` is added to them.
//!
//! ## Expressions and functions
//!
//! | form | meaning |
//! |---|---|
//! | `+ - * /`, `^` | arithmetic; `^` is a power, right-associative and tighter than unary minus (`-x^2 = -(x^2)`) |
//! | `1/2`, `3` | integers and their quotients stay exact rationals |
//! | `0.04`, `1e-4` | floating-point constants |
//! | `pi`, `t` | pi; time (s) |
//! | `der(x)` | the rate x' of coordinate x (in `kinetic`, `forces`, `independent`) |
//! | `sin cos tan exp ln sqrt abs` | the real functions of one argument |
//! | `atan2(y, x)`, `pow(x, e)` | the two-argument functions |
//! | `rot_x(a) rot_y(a) rot_z(a)` | 3x3 rotations about the world axes (vector expressions) |
//! | `diag(a, b, c)` | a diagonal 3x3 matrix (vector expressions) |
//! | `dot(u, v)`, `cross(u, v)`, `norm(u)` | vector products and length (vector expressions) |
//!
//! `der2` is reserved: accelerations cannot be declared. `sin`, `cos` and `tan` of exact
//! multiples of pi/2 are exact.
//!
//! ## What is refused, at compile time
//!
//! Each at the offending token (inline) or at the file's line and column: an unknown symbol
//! (with a did-you-mean and the known names), a missing `;`, a duplicate name or section, a
//! rate inside `potential` or `constraints`, an unknown function or a wrong number of
//! arguments, `der` of a parameter, an empty `coordinates`, a force on an unknown
//! coordinate, a non-constant parameter default, a missing file, a kinetic energy that is
//! not a quadratic form in the rates or whose M is not positive semi-definite at the
//! declared values, constants whose folded value overflows, a body without `mass`, a
//! negative mass, a `rolling` wheel whose radius is zero or negative, a parameter default
//! outside its declared range (or a word after a default that is no range), an inertia that is not symmetric or breaks the triangle inequality, an
//! `orientation` that is not a rotation, and `der(y)` in `independent` for a `y` the section
//! does not set. Derivations have a budget (2^24 expression nodes, `MECHANISM_MAX_SIZE`;
//! 2^27 nonzero entries of dM/dq, `MECHANISM_MAX_ENTRIES`; 2^31 units of work,
//! `MECHANISM_MAX_WORK`); see RELIABILITY.md.
//!
//! ## What the macro emits
//!
//! A struct `NameParameters` (one `pub f64` field per parameter, `Default` the declared
//! values) and the mechanism `Name`, which holds them (readable and writable as fields
//! through `Deref`) with the values that depend on parameters only, computed once per
//! parameter set; constants `NAME`, `N`, `M`, `COORDINATES`, `PARAMETERS`,
//! `PARAMETER_DEFAULTS`, `PARAMETER_RANGES`, `INITIAL_GUESS` and `INDEPENDENT` (the
//! initial values at the declared defaults), the drawing's `DRAW_POINTS`, `DRAW_LINES` and
//! `DRAW_TRACES`, a link tree's `JOINT_LIMITS`, the bodies' `ORIENTATIONS` (their rotation
//! sequences, by which a singularity of their angles is named); and `impl` [`Mechanism<N, M>`](crate::Mechanism) with every method of
//! that trait as straight-line, allocation-free code: among them `initial_guess()` and
//! `independent(k)`, the initial values evaluated from the parameters as they are now, and
//! `set_parameter`, which refuses a value outside the declared range
//! ([`ParameterError`](crate::ParameterError)); a field written directly is not checked. A tree of links also gets the
//! robotics methods (`frame_placement`, `frame_jacobian`, `inverse_dynamics`,
//! `mass_and_bias`, `bias`); `forward_dynamics` is generated for every mechanism without
//! constraint rows.
