//! Hand-derived test systems for the runtime tests (the macro does not exist yet).
//! Each implements `System` directly; the equations are derived in the comments.
#![allow(dead_code)]

use std::f64::consts::PI;
use std::sync::Arc;

use mechanism::nalgebra::DMatrix;
use mechanism::{
    ConstraintRow, Evaluation, Independent, Kinematic, ParameterError, ParameterRange, System,
    SystemInfo, Trajectory,
};

/// A generalised force on one coordinate as a function of (t, q, q').
pub type Force = Arc<dyn Fn(f64, &[f64], &[f64]) -> f64 + Send + Sync>;

fn info(
    name: &str,
    coords: &[&str],
    params: &[&str],
    guess: Vec<f64>,
    independent: Vec<Independent>,
    m: usize,
) -> SystemInfo {
    SystemInfo {
        name: name.into(),
        coordinates: coords.iter().map(|s| s.to_string()).collect(),
        parameters: params.iter().map(|s| s.to_string()).collect(),
        parameter_ranges: vec![ParameterRange::Any; params.len()],
        initial_guess: guess,
        independent,
        constraints: m,
        constraint_rows: (0..m).map(ConstraintRow::unnamed).collect(),
        velocity_rows: 0,
        energy_depends_on_time: false,
        drawing: Default::default(),
        orientations: Vec::new(),
        joint_limits: Vec::new(),
        frames: Vec::new(),
    }
}

// ---------------------------------------------------------------------------------------
/// Cartesian pendulum: point mass m at (x, y) on a massless rod of length l from the origin.
/// T = m/2 (x'^2 + y'^2), Pi = m g y, Phi = x^2 + y^2 - l^2, Phi_q = [2x, 2y],
/// gamma = -(d/dt Phi_q) q' = -2 (x'^2 + y'^2). M = m I, C q' = 0, g = [0, m g].
#[derive(Clone)]
pub struct Pendulum {
    pub p: [f64; 3], // m, l, g
    pub info: SystemInfo,
    /// Duplicate the constraint (2 Phi = 0 as a second row) to make it redundant.
    pub redundant: bool,
}

impl Pendulum {
    /// Released from rest at angle theta0 from the downward vertical (x = l sin theta0).
    pub fn new(theta0: f64) -> Self {
        let (m, l, g) = (1.0, 1.0, 9.81);
        let ind = vec![Independent {
            coordinate: 0,
            position: l * theta0.sin(),
            velocity: 0.0,
        }];
        Self {
            p: [m, l, g],
            info: info(
                "Pendulum",
                &["x", "y"],
                &["m", "l", "g"],
                vec![0.0, -l],
                ind,
                1,
            ),
            redundant: false,
        }
    }
    pub fn redundant() -> Self {
        let mut s = Self::new(0.3);
        s.redundant = true;
        s.info.constraints = 2;
        s
    }
}

impl Kinematic for Pendulum {
    fn info(&self) -> &SystemInfo {
        &self.info
    }
    fn constraints(&self, _t: f64, q: &[f64], phi: &mut [f64]) {
        let l = self.p[1];
        phi[0] = q[0] * q[0] + q[1] * q[1] - l * l;
        if self.redundant {
            phi[1] = 2.0 * phi[0];
        }
    }
    fn constraint_jacobian(&self, _t: f64, q: &[f64], phi_q: &mut DMatrix<f64>, phi_t: &mut [f64]) {
        phi_q[(0, 0)] = 2.0 * q[0];
        phi_q[(0, 1)] = 2.0 * q[1];
        if self.redundant {
            phi_q[(1, 0)] = 4.0 * q[0];
            phi_q[(1, 1)] = 4.0 * q[1];
        }
        phi_t.fill(0.0);
    }
}

impl System for Pendulum {
    fn parameter_values(&self, out: &mut [f64]) {
        out.copy_from_slice(&self.p);
    }
    fn set_parameter(&mut self, index: usize, value: f64) -> Result<(), ParameterError> {
        let count = self.p.len();
        let p = self.p.get_mut(index);
        p.map(|p| *p = value)
            .ok_or(ParameterError::NoSuchParameter { index, count })
    }
    fn evaluate(&self, t: f64, q: &[f64], qd: &[f64], e: &mut Evaluation) {
        let [m, _, g] = self.p;
        e.mass.fill(0.0);
        e.mass[(0, 0)] = m;
        e.mass[(1, 1)] = m;
        e.coriolis.fill(0.0);
        e.gravity[0] = 0.0;
        e.gravity[1] = m * g;
        e.forces.fill(0.0);
        let mut phi = [0.0; 2];
        self.constraints(t, q, &mut phi[..self.info.constraints]);
        let mc = self.info.constraints;
        e.phi.as_mut_slice().copy_from_slice(&phi[..mc]);
        let mut pt = [0.0; 2];
        self.constraint_jacobian(t, q, &mut e.phi_q, &mut pt[..self.info.constraints]);
        e.phi_t.fill(0.0);
        let gm = -2.0 * (qd[0] * qd[0] + qd[1] * qd[1]);
        e.gamma[0] = gm;
        if self.redundant {
            e.gamma[1] = 2.0 * gm;
        }
        e.kinetic = 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1]);
        e.potential = m * g * q[1];
    }
}

// ---------------------------------------------------------------------------------------
/// Planar four-bar with absolute angles th1 (crank AB), th2 (coupler BC), th3 (rocker DC);
/// A = (0, 0), D = (d, 0); uniform rods; gravity g along -y.
///
/// Loop: l1 c1 + l2 c2 - l3 c3 - d = 0, l1 s1 + l2 s2 - l3 s3 = 0.
/// Phi_q = [[-l1 s1, -l2 s2, l3 s3], [l1 c1, l2 c2, -l3 c3]].
/// gamma = [l1 c1 w1^2 + l2 c2 w2^2 - l3 c3 w3^2, l1 s1 w1^2 + l2 s2 w2^2 - l3 s3 w3^2].
/// T = 1/2 (m1 l1^2/3) w1^2 + 1/2 m2 (l1^2 w1^2 + l1 l2 c12 w1 w2 + l2^2/4 w2^2)
///     + 1/2 (m2 l2^2/12) w2^2 + 1/2 (m3 l3^2/3) w3^2,  c12 = cos(th1 - th2), so
/// M = [[m1 l1^2/3 + m2 l1^2, a c12, 0], [a c12, m2 l2^2/3, 0], [0, 0, m3 l3^2/3]], a = m2 l1 l2/2,
/// C q' = [a s12 w2^2, -a s12 w1^2, 0], s12 = sin(th1 - th2).
/// Pi = g (m1 l1/2 s1 + m2 (l1 s1 + l2/2 s2) + m3 l3/2 s3).
#[derive(Clone)]
pub struct FourBar {
    pub p: [f64; 8], // l1 m1 l2 m2 l3 m3 d g
    pub info: SystemInfo,
    pub torque: Option<Force>,
}

impl FourBar {
    /// The crank-rocker of the brief, th1 = pi/2, th1' = 10 rad/s, C above the x-axis.
    pub fn crank_rocker() -> Self {
        let ind = vec![Independent {
            coordinate: 0,
            position: PI / 2.0,
            velocity: 10.0,
        }];
        Self {
            p: [0.1, 0.2, 0.4, 0.5, 0.3, 0.4, 0.35, 9.81],
            info: info(
                "FourBar",
                &["th1", "th2", "th3"],
                &["l1", "m1", "l2", "m2", "l3", "m3", "d", "g"],
                vec![PI / 2.0, 0.5, 1.6],
                ind,
                2,
            ),
            torque: None,
        }
    }
    /// A four-bar whose crank cannot turn fully: l1 = 0.2, l2 = 0.2, l3 = 0.3, d = 0.35,
    /// so l2 + l3 = 0.5 < l1 + d = 0.55; the coupler and rocker stretch into line (a dead
    /// point) at cos th1* = (l1^2 + d^2 - (l2 + l3)^2) / (2 l1 d) = -0.625.
    pub fn locking() -> Self {
        let mut s = Self::crank_rocker();
        s.p[0] = 0.2;
        s.p[2] = 0.2;
        s.p[4] = 0.3;
        s.info.initial_guess = vec![PI / 2.0, 0.0, 1.5];
        s
    }
}

impl Kinematic for FourBar {
    fn info(&self) -> &SystemInfo {
        &self.info
    }
    fn constraints(&self, _t: f64, q: &[f64], phi: &mut [f64]) {
        let [l1, _, l2, _, l3, _, d, _] = self.p;
        phi[0] = l1 * q[0].cos() + l2 * q[1].cos() - l3 * q[2].cos() - d;
        phi[1] = l1 * q[0].sin() + l2 * q[1].sin() - l3 * q[2].sin();
    }
    fn constraint_jacobian(&self, _t: f64, q: &[f64], j: &mut DMatrix<f64>, phi_t: &mut [f64]) {
        let [l1, _, l2, _, l3, _, _, _] = self.p;
        let (s1, c1) = q[0].sin_cos();
        let (s2, c2) = q[1].sin_cos();
        let (s3, c3) = q[2].sin_cos();
        j[(0, 0)] = -l1 * s1;
        j[(0, 1)] = -l2 * s2;
        j[(0, 2)] = l3 * s3;
        j[(1, 0)] = l1 * c1;
        j[(1, 1)] = l2 * c2;
        j[(1, 2)] = -l3 * c3;
        phi_t.fill(0.0);
    }
}

impl System for FourBar {
    fn parameter_values(&self, out: &mut [f64]) {
        out.copy_from_slice(&self.p);
    }
    fn set_parameter(&mut self, index: usize, value: f64) -> Result<(), ParameterError> {
        let count = self.p.len();
        let p = self.p.get_mut(index);
        p.map(|p| *p = value)
            .ok_or(ParameterError::NoSuchParameter { index, count })
    }
    fn evaluate(&self, t: f64, q: &[f64], qd: &[f64], e: &mut Evaluation) {
        let [l1, m1, l2, m2, l3, m3, _d, g] = self.p;
        let (s1, c1) = q[0].sin_cos();
        let (s2, c2) = q[1].sin_cos();
        let (s3, c3) = q[2].sin_cos();
        let (s12, c12) = (q[0] - q[1]).sin_cos();
        let (w1, w2, w3) = (qd[0], qd[1], qd[2]);
        let a = m2 * l1 * l2 / 2.0;
        e.mass.fill(0.0);
        e.mass[(0, 0)] = m1 * l1 * l1 / 3.0 + m2 * l1 * l1;
        e.mass[(0, 1)] = a * c12;
        e.mass[(1, 0)] = a * c12;
        e.mass[(1, 1)] = m2 * l2 * l2 / 3.0;
        e.mass[(2, 2)] = m3 * l3 * l3 / 3.0;
        e.coriolis[0] = a * s12 * w2 * w2;
        e.coriolis[1] = -a * s12 * w1 * w1;
        e.coriolis[2] = 0.0;
        e.gravity[0] = g * (m1 * l1 / 2.0 + m2 * l1) * c1;
        e.gravity[1] = g * m2 * l2 / 2.0 * c2;
        e.gravity[2] = g * m3 * l3 / 2.0 * c3;
        e.forces.fill(0.0);
        if let Some(f) = &self.torque {
            e.forces[0] = f(t, q, qd);
        }
        let mut phi = [0.0; 2];
        self.constraints(t, q, &mut phi);
        e.phi.copy_from_slice(&phi);
        let mut pt = [0.0; 2];
        self.constraint_jacobian(t, q, &mut e.phi_q, &mut pt);
        e.phi_t.fill(0.0);
        e.gamma[0] = l1 * c1 * w1 * w1 + l2 * c2 * w2 * w2 - l3 * c3 * w3 * w3;
        e.gamma[1] = l1 * s1 * w1 * w1 + l2 * s2 * w2 * w2 - l3 * s3 * w3 * w3;
        e.kinetic = 0.5 * (m1 * l1 * l1 / 3.0) * w1 * w1
            + 0.5 * m2 * (l1 * l1 * w1 * w1 + l1 * l2 * c12 * w1 * w2 + l2 * l2 / 4.0 * w2 * w2)
            + 0.5 * (m2 * l2 * l2 / 12.0) * w2 * w2
            + 0.5 * (m3 * l3 * l3 / 3.0) * w3 * w3;
        e.potential =
            g * (m1 * l1 / 2.0 * s1 + m2 * (l1 * s1 + l2 / 2.0 * s2) + m3 * l3 / 2.0 * s3);
    }
}

// ---------------------------------------------------------------------------------------
/// The seed's spatial crank-slider, q = [phi, beta, gamma, x_c].
/// T = 1/2 (J1 + m2/2 l1^2) phi'^2 + 1/2 (m2/2 + m3) x_c'^2 (constant, singular M: zero rows
/// for beta and gamma), Pi = m1 g (a1 cos phi + h) + m2/2 g (l1 cos phi + h), so
/// g(q) = [-(m1 a1 + m2/2 l1) g sin phi, 0, 0, 0] (ERRATA item 4), C q' = 0.
/// f1 = l1 sin phi sin alpha + l2 sin gamma cos beta - x_c
/// f2 = -l1 sin phi cos alpha + l2 sin gamma sin beta - d
/// f3 = h + l1 cos phi - l2 cos gamma
/// gamma_acc (= -(dPhi_q/dt) q'):
///   1: l1 sa sphi wphi^2 + l2 sg cb (wb^2 + wg^2) + 2 l2 cg sb wb wg
///   2: -l1 ca sphi wphi^2 + l2 sg sb (wb^2 + wg^2) - 2 l2 cg cb wb wg
///   3: l1 cphi wphi^2 - l2 cg wg^2
/// tau_phi = 0.005 sin(2 pi t) unless replaced.
#[derive(Clone)]
pub struct CrankSlider {
    pub p: [f64; 11], // h l1 l2 d alpha m1 m2 m3 J1 a1 g
    pub info: SystemInfo,
    pub torque: Option<Force>,
}

impl CrankSlider {
    pub fn seed() -> Self {
        let ind = vec![Independent {
            coordinate: 0,
            position: 0.0,
            velocity: 2.0 * PI,
        }];
        Self {
            p: [0.12, 0.08, 0.3, 0.1, 0.0, 0.12, 0.5, 2.0, 1e-4, 0.04, 9.81],
            info: info(
                "CrankSlider",
                &["phi", "beta", "gamma", "x_c"],
                &[
                    "h", "l1", "l2", "d", "alpha", "m1", "m2", "m3", "J1", "a1", "g",
                ],
                vec![0.0, 0.5, 0.8, 0.25],
                ind,
                3,
            ),
            torque: Some(Arc::new(|t, _, _| 0.005 * (2.0 * PI * t).sin())),
        }
    }
    pub fn unforced() -> Self {
        let mut s = Self::seed();
        s.torque = None;
        s
    }
}

impl Kinematic for CrankSlider {
    fn info(&self) -> &SystemInfo {
        &self.info
    }
    fn constraints(&self, _t: f64, q: &[f64], f: &mut [f64]) {
        let [h, l1, l2, d, al, ..] = self.p;
        let (sp, cp) = q[0].sin_cos();
        let (sb, cb) = q[1].sin_cos();
        let (sg, cg) = q[2].sin_cos();
        let (sa, ca) = al.sin_cos();
        f[0] = l1 * sp * sa + l2 * sg * cb - q[3];
        f[1] = -l1 * sp * ca + l2 * sg * sb - d;
        f[2] = h + l1 * cp - l2 * cg;
    }
    fn constraint_jacobian(&self, _t: f64, q: &[f64], j: &mut DMatrix<f64>, phi_t: &mut [f64]) {
        let [_, l1, l2, _, al, ..] = self.p;
        let (sp, cp) = q[0].sin_cos();
        let (sb, cb) = q[1].sin_cos();
        let (sg, cg) = q[2].sin_cos();
        let (sa, ca) = al.sin_cos();
        j.fill(0.0);
        j[(0, 0)] = l1 * cp * sa;
        j[(0, 1)] = -l2 * sg * sb;
        j[(0, 2)] = l2 * cg * cb;
        j[(0, 3)] = -1.0;
        j[(1, 0)] = -l1 * cp * ca;
        j[(1, 1)] = l2 * sg * cb;
        j[(1, 2)] = l2 * cg * sb;
        j[(2, 0)] = -l1 * sp;
        j[(2, 2)] = l2 * sg;
        phi_t.fill(0.0);
    }
}

impl System for CrankSlider {
    fn parameter_values(&self, out: &mut [f64]) {
        out.copy_from_slice(&self.p);
    }
    fn set_parameter(&mut self, index: usize, value: f64) -> Result<(), ParameterError> {
        let count = self.p.len();
        let p = self.p.get_mut(index);
        p.map(|p| *p = value)
            .ok_or(ParameterError::NoSuchParameter { index, count })
    }
    fn evaluate(&self, t: f64, q: &[f64], qd: &[f64], e: &mut Evaluation) {
        let [h, l1, l2, _d, al, m1, m2, m3, j1, a1, g] = self.p;
        let (sp, cp) = q[0].sin_cos();
        let (sb, cb) = q[1].sin_cos();
        let (sg, cg) = q[2].sin_cos();
        let (sa, ca) = al.sin_cos();
        let (wp, wb, wg) = (qd[0], qd[1], qd[2]);
        e.mass.fill(0.0);
        e.mass[(0, 0)] = j1 + m2 / 2.0 * l1 * l1;
        e.mass[(3, 3)] = m2 / 2.0 + m3;
        e.coriolis.fill(0.0);
        e.gravity.fill(0.0);
        e.gravity[0] = -(m1 * a1 + m2 / 2.0 * l1) * g * sp;
        e.forces.fill(0.0);
        if let Some(f) = &self.torque {
            e.forces[0] = f(t, q, qd);
        }
        let mut phi = [0.0; 3];
        self.constraints(t, q, &mut phi);
        e.phi.copy_from_slice(&phi);
        let mut pt = [0.0; 3];
        self.constraint_jacobian(t, q, &mut e.phi_q, &mut pt);
        e.phi_t.fill(0.0);
        e.gamma[0] = l1 * sa * sp * wp * wp
            + l2 * sg * cb * (wb * wb + wg * wg)
            + 2.0 * l2 * cg * sb * wb * wg;
        e.gamma[1] = -l1 * ca * sp * wp * wp + l2 * sg * sb * (wb * wb + wg * wg)
            - 2.0 * l2 * cg * cb * wb * wg;
        e.gamma[2] = l1 * cp * wp * wp - l2 * cg * wg * wg;
        e.kinetic =
            0.5 * (j1 + m2 / 2.0 * l1 * l1) * wp * wp + 0.5 * (m2 / 2.0 + m3) * qd[3] * qd[3];
        e.potential = m1 * g * (a1 * cp + h) + m2 / 2.0 * g * (l1 * cp + h);
    }
}

/// Finite-difference check helper: max |a - b|.
pub fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

/// Energy balance of a run: max |T + Pi - W - (T + Pi - W)(0)| over the samples, absolute
/// (J) and relative to max(|T| + |Pi|).
pub fn drift(tr: &Trajectory) -> (f64, f64) {
    let s0 = tr.sample(0);
    let e0 = s0.kinetic + s0.potential - s0.work;
    let scale = tr
        .samples()
        .map(|s| s.kinetic.abs() + s.potential.abs())
        .fold(0.0, f64::max);
    let d = tr
        .samples()
        .map(|s| (s.kinetic + s.potential - s.work - e0).abs())
        .fold(0.0, f64::max);
    (d, d / scale)
}

/// The library's slider-crank with its crank driven by the row th - pi/4 - 10 t instead of
/// its torque: no degree of freedom left, and a constraint row that moves with t.
pub fn driven_slider_crank_source() -> String {
    include_str!("../../mechanisms/planar_slider_crank.mech")
        .replace("constraints {", "constraints {\n    th - pi/4 - 10*t;")
        .replace("independent { th = pi/4; der(th) = 0.0; }", "")
        .replace("forces { th: tau0 - c*der(th); }", "")
}

/// The chain of `n` revolute links of `benches/scale/serial_chain.py`: axes alternating z,
/// y, x, each joint 0.1 m above the last, 1 kg links with a full inertia tensor.
pub fn chain_source(n: usize) -> String {
    let mut text =
        String::from("pub struct Chain;\nparameters { g = 9.81; }\ngravity = [0, 0, -g];\n");
    let axes = ["[0, 0, 1]", "[0, 1, 0]", "[1, 0, 0]"];
    for i in 1..=n {
        let parent = match i {
            1 => String::new(),
            _ => format!("parent = l{}; xyz = [0, 0, 0.1]; ", i - 1),
        };
        text += &format!(
            "link l{i} {{ {parent}joint = revolute(q{i}, {}); mass = 1; com = [0.01, 0, 0.05];
             inertia = [[0.0042, 0.0001, -0.0002], [0.0001, 0.0041, 0.0003], [-0.0002, 0.0003, 0.0008]]; }}\n",
            axes[(i - 1) % 3]
        );
    }
    text
}
