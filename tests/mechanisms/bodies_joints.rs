//! Joint helpers in motion: a rigid body in six absolute coordinates held by `revolute` (a
//! compound pendulum) or `prismatic` (a block on an inclined guide) moves exactly as the
//! one-degree-of-freedom model predicts; two rods in planar coordinates, joined by the same
//! spatial joints, swing at the compound double pendulum's two frequencies, and a slider-crank
//! of planar bodies moves as the energy-style one.

use mechanism::{
    AssemblyOptions, IntegratorOptions, Interpreted, Kinematic, Method, SimulationOptions,
    SteadyOptions, Trajectory, linearize, linearize_steady, simulate,
};

fn run(source: &str, t_end: f64) -> Trajectory {
    let s = Interpreted::from_source(source).expect("the declaration derives");
    let o = SimulationOptions {
        t_end,
        output_rate: 100.0,
        integrator: IntegratorOptions {
            method: Method::Dop853,
            rtol: 1e-12,
            atol: 1e-12,
            ..Default::default()
        },
        ..Default::default()
    };
    simulate(&s, &o).expect("the simulation runs")
}

/// A uniform rod (m = 1.5 kg, L = 0.8 m, radius 2 cm) along its body z axis, hinged at its
/// top end to the ground by `revolute` about the world x axis; six coordinates
/// (x, y, z, a, b, c), R = rot_x(a) rot_y(b) rot_z(c), five joint rows.
const HINGED_ROD: &str = "
/// Compound pendulum in absolute coordinates.
pub struct HingedRod;
parameters { m = 1.5; L = 0.8; r = 0.02; g = 9.81; }
coordinates { x = 0.0; y = 0.19; z = -0.35; a = 0.5; b = 0.0; c = 0.0; }
independent { a = 0.5; der(a) = 0.0; }
gravity = [0, 0, -g];
point O = [0, 0, 0];
axis hinge = [1, 0, 0];
body rod {
    mass = m;
    position = [x, y, z];
    orientation = rot_x(a) * rot_y(b) * rot_z(c);
    inertia = diag(m*L^2/12, m*L^2/12, m*r^2/2);
    point P = [0, 0, L/2];
    axis pin = [1, 0, 0];
}
joints { revolute(P, O, pin, hinge); }
";

/// The same pendulum with one coordinate: T = 1/2 (m L^2/3) a'^2, Pi = -m g L/2 cos(a).
const PENDULUM: &str = "
/// Compound pendulum.
pub struct Pendulum;
parameters { m = 1.5; L = 0.8; g = 9.81; }
coordinates { a = 0.5; }
independent { a = 0.5; der(a) = 0.0; }
kinetic = 1/2*(m*L^2/3)*der(a)^2;
potential = -m*g*L/2*cos(a);
";

/// The hinge leaves one degree of freedom, the rotation a about x: a(t) equals the
/// one-coordinate pendulum's to 1e-9 rad over 2 s (both integrated at 1e-12), while b, c and
/// x stay 0 to 1e-10 (the parallel-axes rows hold the axis).
#[test]
fn revolute_gives_the_compound_pendulum() {
    let free = run(HINGED_ROD, 2.0);
    let one = run(PENDULUM, 2.0);
    assert_eq!(free.info.m(), 5);
    let mut worst = 0.0_f64;
    let mut off_axis = 0.0_f64;
    for (s, p) in free.samples().zip(one.samples()) {
        worst = worst.max((s.q[3] - p.q[0]).abs());
        off_axis = off_axis
            .max(s.q[0].abs())
            .max(s.q[4].abs())
            .max(s.q[5].abs());
    }
    println!("revolute: max |a - a_1dof| = {worst:e}, max |x|, |b|, |c| = {off_axis:e}");
    assert!(worst < 1e-9, "{worst:e}");
    assert!(off_axis < 1e-10, "{off_axis:e}");
    // It swings: a crosses zero within the first half period (~0.75 s).
    assert!(free.samples().any(|s| s.q[3] < 0.0));
}

/// A block (m = 2 kg) whose body x axis slides along the ground axis
/// u = (cos 0.3, 0, sin 0.3) through the origin (`prismatic`), gravity along -z: it slides
/// down with s'' = -g sin(0.3), so x(t) = -1/2 g sin(0.3) cos(0.3) t^2, z(t) = x(t) tan(0.3);
/// and it cannot turn: a = c = 0, b = -0.3. To 1e-9 over 1 s (the closed form is exact).
#[test]
fn prismatic_gives_the_inclined_slide() {
    let source = "
        /// Block on an inclined guide.
        pub struct Slide;
        parameters { m = 2.0; g = 9.81; th = 0.3; }
        coordinates { x = 0.0; y = 0.0; z = 0.0; a = 0.0; b = -0.3; c = 0.0; }
        independent { x = 0.0; der(x) = 0.0; }
        gravity = [0, 0, -g];
        point O = [0, 0, 0];
        axis guide = [cos(th), 0, sin(th)];
        body block {
            mass = m;
            position = [x, y, z];
            orientation = rot_x(a) * rot_y(b) * rot_z(c);
            inertia = diag(0.1, 0.2, 0.3);
            point P = [0, 0, 0];
            axis slider = [1, 0, 0];
        }
        joints { prismatic(P, O, slider, guide); }
    ";
    let tr = run(source, 1.0);
    assert_eq!(tr.info.m(), 5);
    let (g, th) = (9.81_f64, 0.3_f64);
    let mut worst = 0.0_f64;
    for s in tr.samples() {
        let x = -0.5 * g * th.sin() * th.cos() * s.t * s.t;
        let expected = [x, 0.0, x * th.tan(), 0.0, -th, 0.0];
        for (v, e) in s.q.iter().zip(expected) {
            worst = worst.max((v - e).abs());
        }
    }
    println!("prismatic: max deviation from the closed form {worst:e}");
    assert!(worst < 1e-9, "{worst:e}");
}

/// `distance(P, O, L)` on a point mass is the spherical pendulum's rod: released
/// horizontally at rest from (L, 0, 0) it swings through the lowest point (0, 0, -L) with
/// speed sqrt(2 g h) (energy, to 1e-7 relative: the coordinate projection after each step
/// moves the energy by ~1e-9 relative here), and |P - O| = L throughout (projection keeps it
/// to 1e-12).
#[test]
fn distance_keeps_the_length() {
    let source = "
        /// Point mass on a rod.
        pub struct Bob;
        parameters { m = 1.0; L = 0.5; g = 9.81; }
        coordinates { x = 0.5; y = 0.0; z = -0.01; }
        independent { x = 0.5; der(x) = 0.0; y = 0.0; der(y) = 0.0; }
        gravity = [0, 0, -g];
        point O = [0, 0, 0];
        body bob { mass = m; position = [x, y, z]; }
        joints { distance(bob, O, L); }
    ";
    let tr = run(source, 0.5);
    let (l, g) = (0.5_f64, 9.81_f64);
    let mut best = (f64::INFINITY, 0.0);
    for s in tr.samples() {
        let r = (s.q[0].powi(2) + s.q[1].powi(2) + s.q[2].powi(2)).sqrt();
        assert!((r - l).abs() < 1e-12, "|P - O| = {r} at t = {}", s.t);
        let speed = (s.qd[0].powi(2) + s.qd[1].powi(2) + s.qd[2].powi(2)).sqrt();
        if s.q[2] < best.0 {
            best = (s.q[2], speed);
        }
    }
    // The lowest sample is within a 10 ms step of the bottom: z within ~1e-3 of -L.
    assert!((best.0 + l).abs() < 2e-3, "lowest z {}", best.0);
    let expected = (2.0 * g * -best.0).sqrt();
    assert!(
        (best.1 - expected).abs() < 1e-7 * expected,
        "speed {} vs sqrt(2 g h) {expected}",
        best.1
    );
}

/// A block on a rail along the world x axis, its body z axis along the rail
/// (R = rot_y(pi/2) rot_z(sw) rot_x(r1) rot_y(r2)), declared at the twist `sw0` about the
/// rail: the prismatic joint keeps that twist (and r1 = r2 = 0) while the block slides at
/// its initial 1 m/s, whatever perpendiculars the joint's rows are written with. (With the
/// twist fixed at a perpendicular of the tool's choosing, sw0 = 0 could not be assembled and
/// sw0 = 1.5 was turned to pi/2.)
#[test]
fn prismatic_keeps_the_declared_twist() {
    for sw0 in [0.0, 1.5, -0.4] {
        let source = format!(
            "pub struct Rail;
             parameters {{ m = 1.0; g = 9.81; }}
             coordinates {{ x = 0.0; y = 0.0; z = 0.0; sw = {sw0:?}; r1 = 0.0; r2 = 0.0; }}
             independent {{ x = 0.0; der(x) = 1.0; }}
             gravity = [0, 0, -g];
             point O = [0, 0, 0];
             axis ax = [1, 0, 0];
             body blk {{
                 mass = m; position = [x, y, z];
                 orientation = rot_y(pi/2) * rot_z(sw) * rot_x(r1) * rot_y(r2);
                 inertia = diag(0.01, 0.02, 0.03);
                 point P = [0, 0, 0];
                 axis a = [0, 0, 1];
             }}
             joints {{ prismatic(P, O, a, ax); }}"
        );
        let tr = run(&source, 0.5);
        let worst = tr
            .samples()
            .map(|s| {
                let pose = [s.q[1], s.q[2], s.q[3] - sw0, s.q[4], s.q[5]];
                let slide = s.q[0] - s.t;
                pose.iter()
                    .chain([&slide])
                    .fold(0.0_f64, |w, v| w.max(v.abs()))
            })
            .fold(0.0, f64::max);
        // Gravity is across the rail and the rail takes it: uniform motion, the pose as
        // declared, to the integration tolerance (1e-12) and the projection's round-off.
        assert!(worst < 1e-10, "sw0 = {sw0}: {worst}");
    }
}

/// Two uniform rods (m = 2 kg, l = 1 m, no spin inertia) hinged in a chain, in planar
/// coordinates (th, x, y of each centre) with spatial joints: the joints' z rows, and the
/// axis rows of `revolute`, vanish identically and are left out.
fn double_pendulum(joints: &str) -> String {
    format!(
        "/// Compound double pendulum.
        pub struct DoublePendulum;
        parameters {{ l = 1.0; m = 2.0; g = 9.81; }}
        coordinates {{ th1 = 0.3; th2 = 0.5; x1 = 0.0; y1 = 0.0; x2 = 0.0; y2 = 0.0; }}
        independent {{ th1 = 0.3; th2 = 0.5; }}
        gravity = [0, -g, 0];
        point O = [0, 0, 0];
        axis k = [0, 0, 1];
        body rod1 {{
            mass = m;
            orientation = rot_z(th1);
            position = [x1, y1, 0];
            inertia = diag(0, m*l^2/12, m*l^2/12);
            point A = [-l/2, 0, 0];
            point B = [l/2, 0, 0];
            axis n1 = [0, 0, 1];
        }}
        body rod2 {{
            mass = m;
            orientation = rot_z(th2);
            position = [x2, y2, 0];
            inertia = diag(0, m*l^2/12, m*l^2/12);
            point C = [-l/2, 0, 0];
            axis n2 = [0, 0, 1];
        }}
        joints {{ {joints} }}"
    )
}

/// Hanging straight down (th = -pi/2), the rods' small oscillations solve
/// det(K - w^2 M) = 0 with M = m l^2 [[4/3, 1/2], [1/2, 1/3]] and K = m g l diag(3/2, 1/2):
/// w^2 l / g = 3 -+ 6 sqrt(7) / 7, closed form. Both declarations (`revolute`, and the
/// point equalities `A = O`) keep 4 rows of their 10 and 6. Two routes give these
/// frequencies: `linearize_steady` from the exact tangents, to 1e-12 relative (round-off
/// of the 4 x 4 eigenproblem; measured 1.5e-15), and `linearize` by central differences
/// (h = 1e-5 (1 + pi/2)), to 1e-8: its truncation error h^2/6 times a ratio of derivatives
/// is about 1e-10 relative, its round-off eps/h about 1e-11 (measured 1.4e-11 and 5.5e-10).
#[test]
fn planar_bodies_swing_at_the_double_pendulums_frequencies() {
    let (l, g) = (1.0_f64, 9.81_f64);
    let root = 6.0 * 7.0_f64.sqrt() / 7.0;
    let exact = [((3.0 - root) * g / l).sqrt(), ((3.0 + root) * g / l).sqrt()];
    for joints in [
        "revolute(A, O, n1, k); revolute(C, B, n2, n1);",
        "A = O; C = B;",
    ] {
        let model = mechanism_codegen::parse_model_str(&double_pendulum(joints)).expect("parses");
        let s = Interpreted::for_linearization(model).expect("derives");
        assert_eq!((s.info().n(), s.info().m()), (6, 4), "{joints}");
        let down = -std::f64::consts::FRAC_PI_2;
        let q = [down, down, 0.0, -l / 2.0, 0.0, -1.5 * l];
        let lin = linearize(&s, 0.0, &q, &[0.0; 6], &[0, 1], &AssemblyOptions::default())
            .expect("linearises");
        let steady = linearize_steady(&s, 0.0, &q, &[0.0; 6], &SteadyOptions::default())
            .expect("linearises exactly");
        let mut exact_route: Vec<f64> = steady
            .reduced
            .iter()
            .filter(|e| e.im > 0.0)
            .map(|e| e.norm())
            .collect();
        exact_route.sort_by(f64::total_cmp);
        let differences = &lin.frequencies_rad_s;
        println!(
            "{joints}: omega = {exact_route:?} (exact tangents), {differences:?} (differences), closed form {exact:?}"
        );
        assert_eq!((exact_route.len(), differences.len()), (2, 2));
        for ((w, d), e) in exact_route.iter().zip(differences).zip(exact) {
            assert!((w / e - 1.0).abs() < 1e-12, "{joints}: {w} against {e}");
            assert!((d / e - 1.0).abs() < 1e-8, "{joints}: {d} against {e}");
        }
    }
}

/// `mechanisms/planar_slider_crank.mech` (energy style, three coordinates) restated with
/// bodies in planar coordinates: crank and rod as uniform rods, the slider a body on
/// `prismatic` along the x axis. Of its 17 joint rows 9 vanish identically (three z rows;
/// the prismatic's axis row about y, its slide row along z and its twist) and are left out;
/// the 8 left hold 9 coordinates to the one degree of freedom.
const SLIDER_CRANK_BODIES: &str = "
/// Planar slider-crank in body style with planar coordinates.
pub struct SliderCrankBodies;
parameters { r = 0.05; l = 0.2; m1 = 0.5; m2 = 0.8; m3 = 1.2; g = 9.81; tau0 = 2.0; }
coordinates {
    th = 0.785398; x1 = 0.0177; y1 = 0.0177;
    ph = -0.177711; x2 = 0.134; y2 = 0.0177;
    x = 0.232206; y3 = 0.0; s = 0.0;
}
independent { th = pi/4; der(th) = 0.0; }
gravity = [0, -g, 0];
point O = [0, 0, 0];
axis gx = [1, 0, 0];
body crank {
    mass = m1; position = [x1, y1, 0]; orientation = rot_z(th);
    inertia = diag(0, m1*r^2/12, m1*r^2/12);
    point O1 = [-r/2, 0, 0]; point A1 = [r/2, 0, 0]; axis k1 = [0, 0, 1];
}
body rod {
    mass = m2; position = [x2, y2, 0]; orientation = rot_z(ph);
    inertia = diag(0, m2*l^2/12, m2*l^2/12);
    point A2 = [-l/2, 0, 0]; point B2 = [l/2, 0, 0];
}
body slider {
    mass = m3; position = [x, y3, 0]; orientation = rot_z(s);
    inertia = diag(5e-4, 5e-4, 1e-3);
    point B3 = [0, 0, 0]; axis sx = [1, 0, 0];
}
joints { O1 = O; A2 = A1; B2 = B3; prismatic(B3, O, sx, gx); }
forces { th: tau0; }
";

/// Driven by the constant torque tau0 from rest, both declarations turn the crank to
/// th(1 s) = 319.3 rad; integrated at 1e-12 they agree to 1e-8 rad over the run (measured
/// 5.6e-11: the two integrations' own errors, 2e-13 of th), and the slider's x to 1e-9 m
/// (measured 1.7e-12).
#[test]
fn planar_bodies_on_a_prismatic_joint_give_the_slider_crank() {
    let bodies = run(SLIDER_CRANK_BODIES, 1.0);
    let energies = run(
        include_str!("../../mechanisms/planar_slider_crank.mech"),
        1.0,
    );
    assert_eq!((bodies.info.n(), bodies.info.m()), (9, 8));
    let (mut th, mut x) = (0.0_f64, 0.0_f64);
    for (b, e) in bodies.samples().zip(energies.samples()) {
        th = th.max((b.q[0] - e.q[0]).abs());
        x = x.max((b.q[6] - e.q[2]).abs());
    }
    let last = energies.samples().last().expect("samples").q[0];
    println!("slider-crank: th(1 s) = {last}, max |th diff| = {th:e}, max |x diff| = {x:e}");
    assert!(last > 300.0, "{last}");
    assert!(th < 1e-8, "{th:e}");
    assert!(x < 1e-9, "{x:e}");
}
