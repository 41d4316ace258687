//! The emitted code equals the interpreter route, for every library mechanism.
//!
//! Route 1: the struct `mechanism!` expanded from `mechanisms/<name>.mech` at build time
//! (specialised, CSE'd Rust). Route 2: the same text parsed at run time, derived, and
//! evaluated node by node by `mechanism_codegen::eval`. Both evaluate the same expression
//! DAG, so they agree up to rounding: the emitted code may reorder sums, pair sin/cos and
//! use `powi`. Tolerance: 1e-12 relative to the largest entry of the quantity compared (an
//! entry is a sum of terms bounded by that scale, so its rounding error is too), at random
//! states and with randomly perturbed parameters.

use mechanism::builtin::{
    CartesianPendulum, ClosedChain4, PlanarFourBar, PlanarSliderCrank, SpatialCrankSlider,
    SpatialFourBar, builtin, builtin_names, builtin_source,
};
use mechanism::{Evaluation, Mechanism};
use mechanism_codegen::{Equations, Id, Matrix, Model, SymbolId, derive, eval, parse_model_str};
use nalgebra::{DMatrix, SMatrix, SVector};

const TOL: f64 = 1e-12;
const STATES: usize = 25;

/// A small deterministic generator (xorshift64*): uniform in [-1, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        x as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// One random state: (t, q, q', parameters).
struct State {
    t: f64,
    q: Vec<f64>,
    qd: Vec<f64>,
    params: Vec<f64>,
}

/// The interpreter route at one state.
struct Interpreted {
    model: Model,
    eqs: Equations,
}

impl Interpreted {
    fn new(name: &str) -> Self {
        let text = builtin_source(name).expect("a library mechanism");
        let mut model = parse_model_str(text).expect("the library file parses");
        let eqs = derive(&mut model).expect("the library file derives");
        Self { model, eqs }
    }

    fn random_state(&self, rng: &mut Rng) -> State {
        let n = self.model.coordinates.len();
        State {
            t: 2.0 * rng.next(),
            // Around the guess, off the constraint manifold on purpose: the equations are
            // defined everywhere, and an error would show anywhere.
            q: self
                .model
                .coordinates
                .iter()
                .map(|c| c.guess + 0.5 * rng.next())
                .collect(),
            qd: (0..n).map(|_| 3.0 * rng.next()).collect(),
            params: self
                .model
                .parameters
                .iter()
                .map(|p| {
                    let v = p.default * (1.0 + 0.2 * rng.next()) + 0.01 * rng.next();
                    // Within the declared range (`J1 = 1e-4 nonnegative`), as set_parameter
                    // requires: its size is what is random.
                    match p.range {
                        mechanism_codegen::ParameterRange::Any => v,
                        _ => v.abs(),
                    }
                })
                .collect(),
        }
    }

    fn value(&self, s: &State, id: Id) -> f64 {
        let arena = &self.model.arena;
        let sym = |x: Id| arena.as_symbol(x);
        let env = |k: SymbolId| -> Option<f64> {
            if sym(self.model.time) == Some(k) {
                return Some(s.t);
            }
            for (i, c) in self.model.coordinates.iter().enumerate() {
                if sym(c.q) == Some(k) {
                    return Some(s.q[i]);
                }
                if sym(c.qd) == Some(k) {
                    return Some(s.qd[i]);
                }
            }
            for (i, p) in self.model.parameters.iter().enumerate() {
                if sym(p.symbol) == Some(k) {
                    return Some(s.params[i]);
                }
            }
            None
        };
        eval(arena, id, &env).expect("the interpreter evaluates the derived equations")
    }

    fn matrix(&self, s: &State, m: &Matrix) -> DMatrix<f64> {
        DMatrix::from_fn(m.rows(), m.cols(), |i, j| self.value(s, m.get(i, j)))
    }
}

/// |a - b| <= TOL * scale, entry by entry, with scale the largest |b| (at least 1e-300).
fn assert_close(what: &str, name: &str, a: &[f64], b: &[f64]) {
    assert_eq!(a.len(), b.len(), "{name}: {what} sizes differ");
    let scale = b.iter().fold(1e-300_f64, |s, x| s.max(x.abs()));
    for (k, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= TOL * scale,
            "{name}: {what}[{k}] emitted {x:e} vs interpreted {y:e} (scale {scale:e})"
        );
    }
}

/// Every method of the statically typed struct against the interpreter.
fn check_methods<T: Mechanism<N, M> + Default, const N: usize, const M: usize>(
    name: &str,
    seed: u64,
) {
    let route = Interpreted::new(name);
    let mut rng = Rng(seed);
    assert_eq!(route.eqs.n, N);
    assert_eq!(route.eqs.m, M);
    for _ in 0..STATES {
        let s = route.random_state(&mut rng);
        let mut mech = T::default();
        for (i, &p) in s.params.iter().enumerate() {
            assert!(mech.set_parameter(i, p).is_ok());
        }
        let q = SVector::<f64, N>::from_column_slice(&s.q);
        let qd = SVector::<f64, N>::from_column_slice(&s.qd);
        let e = &route.eqs;
        let pairs: [(&str, Vec<f64>, &Matrix); 9] = [
            ("M", mech.mass_matrix(&q).as_slice().to_vec(), &e.mass),
            (
                "C",
                mech.coriolis_matrix(&q, &qd).as_slice().to_vec(),
                // These mechanisms declare energies: `derive` forms Khang's C.
                e.coriolis_matrix.as_ref().expect("Khang's C"),
            ),
            (
                "C q'",
                mech.coriolis_forces(&q, &qd).as_slice().to_vec(),
                &e.coriolis_forces,
            ),
            ("g", mech.gravity(&q).as_slice().to_vec(), &e.gravity),
            (
                "tau",
                mech.generalized_forces(s.t, &q, &qd).as_slice().to_vec(),
                &e.forces,
            ),
            ("Phi", mech.constraints(s.t, &q).as_slice().to_vec(), &e.phi),
            (
                "Phi_q",
                mech.constraint_jacobian(s.t, &q).as_slice().to_vec(),
                &e.phi_q,
            ),
            (
                "Phi_t",
                mech.constraint_time_derivative(s.t, &q).as_slice().to_vec(),
                &e.phi_t,
            ),
            (
                "gamma",
                mech.constraint_gamma(s.t, &q, &qd).as_slice().to_vec(),
                &e.gamma,
            ),
        ];
        for (what, emitted, symbolic) in pairs {
            // nalgebra stores column-major: compare against the interpreted matrix's
            // column-major slice.
            let interpreted = route.matrix(&s, symbolic);
            assert_close(what, name, &emitted, interpreted.as_slice());
        }
        assert_close(
            "T",
            name,
            &[mech.kinetic_energy(&q, &qd)],
            &[route.value(&s, e.kinetic)],
        );
        assert_close(
            "Pi",
            name,
            &[mech.potential_energy(&q)],
            &[route.value(&s, e.potential)],
        );

        // The combined evaluation returns exactly what the single methods return.
        let all = mech.evaluate(s.t, &q, &qd);
        assert_close(
            "evaluate.mass",
            name,
            all.mass.as_slice(),
            mech.mass_matrix(&q).as_slice(),
        );
        assert_close(
            "evaluate.coriolis",
            name,
            all.coriolis.as_slice(),
            mech.coriolis_forces(&q, &qd).as_slice(),
        );
        assert_close(
            "evaluate.gravity",
            name,
            all.gravity.as_slice(),
            mech.gravity(&q).as_slice(),
        );
        assert_close(
            "evaluate.forces",
            name,
            all.forces.as_slice(),
            mech.generalized_forces(s.t, &q, &qd).as_slice(),
        );
        assert_close(
            "evaluate.phi",
            name,
            all.phi.as_slice(),
            mech.constraints(s.t, &q).as_slice(),
        );
        assert_close(
            "evaluate.phi_q",
            name,
            all.phi_q.as_slice(),
            mech.constraint_jacobian(s.t, &q).as_slice(),
        );
        assert_close(
            "evaluate.phi_t",
            name,
            all.phi_t.as_slice(),
            mech.constraint_time_derivative(s.t, &q).as_slice(),
        );
        assert_close(
            "evaluate.gamma",
            name,
            all.gamma.as_slice(),
            mech.constraint_gamma(s.t, &q, &qd).as_slice(),
        );
        assert_close(
            "evaluate.kinetic",
            name,
            &[all.kinetic],
            &[mech.kinetic_energy(&q, &qd)],
        );
        assert_close(
            "evaluate.potential",
            name,
            &[all.potential],
            &[mech.potential_energy(&q)],
        );
        // Khang's C times q' is C q'.
        let cqd: SVector<f64, N> = mech.coriolis_matrix(&q, &qd) * qd;
        let scale = cqd.amax().max(1.0);
        assert!(
            (cqd - all.coriolis).amax() <= 1e-12 * scale,
            "{name}: C q' differs from (C)(q')"
        );
        let _: SMatrix<f64, M, N> = all.phi_q;
    }
}

#[test]
fn spatial_crank_slider() {
    check_methods::<SpatialCrankSlider, 4, 3>("spatial_crank_slider", 1);
}

#[test]
fn planar_four_bar() {
    check_methods::<PlanarFourBar, 3, 2>("planar_four_bar", 2);
}

#[test]
fn spatial_four_bar() {
    check_methods::<SpatialFourBar, 4, 3>("spatial_four_bar", 3);
}

#[test]
fn closed_chain() {
    check_methods::<ClosedChain4, 4, 2>("closed_chain", 4);
}

#[test]
fn planar_slider_crank() {
    check_methods::<PlanarSliderCrank, 3, 2>("planar_slider_crank", 5);
}

#[test]
fn cartesian_pendulum() {
    check_methods::<CartesianPendulum, 2, 1>("cartesian_pendulum", 6);
}

/// The run-time registry: every name resolves, and the boxed `System` (through `Compiled`)
/// gives the interpreter's values too, including after `set_parameter`.
#[test]
fn registry_systems_match_the_interpreter() {
    // Every declaration under mechanisms/ is compiled in, and nothing else is.
    let mut files: Vec<String> =
        std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/mechanisms"))
            .expect("mechanisms/ exists")
            .filter_map(|e| {
                let p = e.ok()?.path();
                if p.extension()? != "mech" {
                    return None;
                }
                Some(p.file_stem()?.to_string_lossy().into_owned())
            })
            .collect();
    files.sort();
    let mut names: Vec<String> = builtin_names().iter().map(|s| s.to_string()).collect();
    names.sort();
    assert_eq!(names, files);
    assert!(builtin("no_such_mechanism").is_none());
    assert!(builtin_source("no_such_mechanism").is_none());
    for (k, name) in builtin_names().iter().enumerate() {
        let route = Interpreted::new(name);
        let mut system = builtin(name).expect("registered");
        let (n, m) = (route.eqs.n, route.eqs.m);
        assert_eq!((system.info().n(), system.info().m()), (n, m), "{name}");
        let mut rng = Rng(100 + k as u64);
        let s = route.random_state(&mut rng);
        for (i, &p) in s.params.iter().enumerate() {
            assert!(system.set_parameter(i, p).is_ok());
        }
        let mut out = Evaluation::zeros(n, m);
        system.evaluate(s.t, &s.q, &s.qd, &mut out);
        assert_close(
            "M",
            name,
            out.mass.as_slice(),
            route.matrix(&s, &route.eqs.mass).as_slice(),
        );
        assert_close(
            "gamma",
            name,
            out.gamma.as_slice(),
            route.matrix(&s, &route.eqs.gamma).as_slice(),
        );
        assert_close(
            "Phi_q",
            name,
            out.phi_q.as_slice(),
            route.matrix(&s, &route.eqs.phi_q).as_slice(),
        );
    }
}

/// Expands a declaration with `mechanism!` and keeps the same tokens as text (`$source`),
/// so that the interpreter route reads exactly what the macro compiled.
macro_rules! declared_twice {
    ($source:ident; $($declaration:tt)*) => {
        mechanism::mechanism! { $($declaration)* }
        const $source: &str = stringify!($($declaration)*);
    };
}

declared_twice! {
    CRANK_SLIDER_BODIES;
    /// A crank turning about the ground z axis at O, and a slider on the x axis held at the
    /// distance L from the crank tip (a massless coupler).
    pub struct LabelledCrankSlider;
    parameters { m = 1.0; l = 1.0; L = 2.0; g = 9.81; }
    coordinates { x = 0.5; y = 0.0; z = 0.0; th = 0.0; ph = 0.0; ps = 0.0; s = 3.0; }
    independent { th = 0.0; der(th) = 1.0; }
    gravity = [0, -g, 0];
    point O = [0, 0, 0];
    axis up = [0, 0, 1];
    body crank {
        mass = m;
        position = [x, y, z];
        orientation = rot_z(th) * rot_y(ph) * rot_x(ps);
        inertia = diag(m*l^2/1200, m*l^2/12, m*l^2/12);
        point A = [-l/2, 0, 0];
        point B = [l/2, 0, 0];
        axis k = [0, 0, 1];
    }
    body slider { mass = m; position = [s, 0, 0]; }
    joints {
        revolute(A, O, k, up);
        distance(B, slider, L);
    }
}

declared_twice! {
    CONSTRAINT_BLOCK;
    /// A point on a circle in the plane z = 0 of a fourth coordinate w = 0: one scalar
    /// statement, then a vector equation.
    pub struct LabelledBlock;
    parameters { m = 1.0; l = 1.0; }
    coordinates { x = 0.6; y = -0.8; z = 0.0; w = 0.0; }
    independent { x = 0.6; der(x) = 0.0; }
    kinetic = 1/2*m*(der(x)^2 + der(y)^2 + der(z)^2 + der(w)^2);
    constraints {
        x^2 + y^2 - l^2;
        [z, w] = [0, 0];
    }
}

declared_twice! {
    PLANAR_BODIES;
    /// A rod hinged to the ground, in planar coordinates: `revolute`'s z and axis rows
    /// vanish identically and are left out on both routes.
    pub struct PlanarHinge;
    parameters { m = 1.0; l = 1.0; g = 9.81; }
    coordinates { x = 0.5; y = 0.0; th = 0.0; }
    independent { th = 0.0; der(th) = 1.0; }
    gravity = [0, -g, 0];
    point O = [0, 0, 0];
    axis up = [0, 0, 1];
    body rod {
        mass = m;
        position = [x, y, 0];
        orientation = rot_z(th);
        inertia = diag(0, m*l^2/12, m*l^2/12);
        point A = [-l/2, 0, 0];
        axis k = [0, 0, 1];
    }
    joints { revolute(A, O, k, up); }
}

/// The labels of the rows, (joint, component), as `mechanism!` emits them, as `Compiled`
/// carries them, and as the interpreter route reads them from the same text: all equal to
/// `expected`.
fn assert_rows<T: Mechanism<N, M> + Default, const N: usize, const M: usize>(
    source: &str,
    expected: &[(&str, &str)],
) {
    assert_eq!(T::CONSTRAINT_ROWS, expected, "{}: emitted", T::NAME);
    let compiled = mechanism::Compiled::new(T::default());
    let interpreted = mechanism::Interpreted::from_source(source).expect("the text parses");
    let expected: Vec<mechanism::ConstraintRow> = expected
        .iter()
        .map(|&(joint, component)| mechanism::ConstraintRow {
            joint: joint.into(),
            component: component.into(),
        })
        .collect();
    for (route, info) in [
        ("Compiled", mechanism::Kinematic::info(&compiled)),
        ("Interpreted", mechanism::Kinematic::info(&interpreted)),
    ] {
        assert_eq!(info.constraint_rows, expected, "{}: {route}", T::NAME);
        assert_eq!(info.m(), M, "{}: {route}", T::NAME);
    }
}

/// A body declaration with two joints: each row names its joint as written and its
/// component, in row order, on both routes; `constraint_label` and `joints_of` read them.
#[test]
fn body_joint_rows_are_labelled_on_both_routes() {
    let revolute = "revolute(A, O, k, up)";
    let distance = "distance(B, slider, L)";
    assert_rows::<LabelledCrankSlider, 7, 6>(
        CRANK_SLIDER_BODIES,
        &[
            (revolute, "x"),
            (revolute, "y"),
            (revolute, "z"),
            (revolute, "axis 1"),
            (revolute, "axis 2"),
            (distance, ""),
        ],
    );
    let compiled = mechanism::Compiled::new(LabelledCrankSlider::default());
    let info = mechanism::Kinematic::info(&compiled);
    assert_eq!(info.constraint_label(1), "revolute(A, O, k, up) y");
    assert_eq!(info.constraint_label(3), "revolute(A, O, k, up) axis 1");
    assert_eq!(info.constraint_label(5), "distance(B, slider, L)");
    assert_eq!(info.constraint_label(6), "row 7", "out of range");
    assert_eq!(
        info.joints_of(&[5, 0, 4, 5]),
        ["distance(B, slider, L)", "revolute(A, O, k, up)"]
    );
    assert!(info.joints_of(&[]).is_empty());
}

/// Planar bodies on a spatial joint: the two rows that constrain, on both routes; the
/// emitted equations text names the three left out.
#[test]
fn vanished_joint_rows_are_left_out_on_both_routes() {
    let revolute = "revolute(A, O, k, up)";
    assert_rows::<PlanarHinge, 3, 2>(PLANAR_BODIES, &[(revolute, "x"), (revolute, "y")]);
    let text = PlanarHinge::equations();
    assert!(
        text.contains("(left out, identically zero: revolute(A, O, k, up) (z, axis 1, axis 2))"),
        "{text}"
    );
}

/// A plain `constraints { .. }` block: rows are named by statement (1-based), and a vector
/// equation's rows by component.
#[test]
fn constraint_block_rows_are_labelled_on_both_routes() {
    assert_rows::<LabelledBlock, 4, 3>(
        CONSTRAINT_BLOCK,
        &[
            ("constraint 1", ""),
            ("constraint 2", "x"),
            ("constraint 2", "y"),
        ],
    );
    let compiled = mechanism::Compiled::new(LabelledBlock::default());
    let info = mechanism::Kinematic::info(&compiled);
    assert_eq!(info.constraint_label(0), "constraint 1");
    assert_eq!(info.constraint_label(2), "constraint 2 y");
    assert_eq!(info.joints_of(&[2, 1, 0]), ["constraint 2", "constraint 1"]);
}

/// Every library mechanism: the rows `mechanism!` labelled are the rows codegen labels from
/// the same file (no row left unnamed).
#[test]
fn library_rows_are_labelled_like_the_interpreter() {
    for name in builtin_names() {
        let source = builtin_source(name).expect("registered");
        let compiled = builtin(name).expect("registered");
        let interpreted = mechanism::Interpreted::from_source(source).expect("parses");
        let rows = &compiled.info().constraint_rows;
        assert_eq!(
            rows,
            &mechanism::Kinematic::info(&interpreted).constraint_rows,
            "{name}"
        );
        assert_eq!(rows.len(), compiled.info().m(), "{name}");
        assert!(
            rows.iter().all(|r| !r.joint.starts_with("row ")),
            "{name}: {rows:?}"
        );
    }
}

/// Rows nobody named (what `Compiled::new` records for a hand-written `Mechanism` without
/// `CONSTRAINT_ROWS`) read `row 1`, `row 2`, ..
#[test]
fn unnamed_rows_are_numbered() {
    use mechanism::{ConstraintRow, SystemInfo};
    let info = SystemInfo {
        name: "hand".into(),
        coordinates: vec!["x".into()],
        parameters: vec![],
        parameter_ranges: vec![],
        initial_guess: vec![0.0],
        independent: vec![],
        constraints: 2,
        constraint_rows: (0..2).map(ConstraintRow::unnamed).collect(),
        velocity_rows: 0,
        energy_depends_on_time: false,
        drawing: Default::default(),
        orientations: Vec::new(),
        joint_limits: Vec::new(),
        frames: Vec::new(),
    };
    assert_eq!(info.constraint_label(0), "row 1");
    assert_eq!(info.constraint_label(1), "row 2");
    assert_eq!(info.joints_of(&[1, 1]), ["row 2"]);
}
