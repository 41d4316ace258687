//! The drawings of the mechanism library: every mechanism draws, with ground points and
//! moving points told apart; the drawn points are the declared points (closed forms of the
//! seed and the four-bar at states along a run); the compiled and interpreted routes draw
//! the same.

use mechanism::builtin::{builtin, builtin_names, builtin_source};
use mechanism::{Interpreted, Kinematic, SimulationOptions, System, simulate};

/// States along 1 s of the declared motion.
fn states(system: &dyn System) -> Vec<(f64, Vec<f64>)> {
    let options = SimulationOptions {
        t_end: 1.0,
        output_rate: 20.0,
        ..Default::default()
    };
    let trajectory = simulate(system, &options).unwrap();
    trajectory.samples().map(|s| (s.t, s.q.to_vec())).collect()
}

/// The drawn points of `system` at (t, q), by name.
fn drawn(system: &dyn System, t: f64, q: &[f64]) -> impl Fn(&str) -> [f64; 3] {
    let d = &system.info().drawing;
    let mut out = vec![f64::NAN; 3 * d.points.len()];
    system.draw_points(t, q, &mut out);
    let names: Vec<String> = d.points.iter().map(|p| p.name.clone()).collect();
    move |name: &str| {
        let i = names.iter().position(|n| n == name).expect("a drawn point");
        [out[3 * i], out[3 * i + 1], out[3 * i + 2]]
    }
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[test]
fn every_mechanism_draws_ground_and_moving_points() {
    for name in builtin_names() {
        let system = builtin(name).unwrap();
        let d = &system.info().drawing;
        assert!(!d.lines.is_empty(), "{name} has no drawing");
        assert!(d.points.iter().any(|p| p.ground), "{name}: no ground point");
        assert!(
            d.points.iter().any(|p| !p.ground),
            "{name}: no moving point"
        );
        assert!(!d.traces.is_empty(), "{name}: nothing traced");
    }
}

#[test]
fn the_seed_draws_its_crank_rod_and_slider() {
    let seed = builtin("spatial_crank_slider").unwrap();
    let ground: Vec<(&str, bool)> = seed
        .info()
        .drawing
        .points
        .iter()
        .map(|p| (p.name.as_str(), p.ground))
        .collect();
    assert_eq!(
        ground,
        [
            ("P0", true),
            ("O", true),
            ("A", false),
            ("C", false),
            ("G1", true),
            ("G2", true)
        ]
    );
    let (h, l1, l2, d) = (0.12, 0.08, 0.3, 0.1);
    for (t, q) in states(seed.as_ref()) {
        let p = drawn(seed.as_ref(), t, &q);
        // The closed forms of the declaration (alpha = 0): O = (0, 0, h),
        // A = O + l1 (0, -sin phi, cos phi), C = (x_c, d, 0); and the loop closes: |A - C| = l2.
        assert_eq!(p("O"), [0.0, 0.0, h]);
        let a = [0.0, -l1 * q[0].sin(), h + l1 * q[0].cos()];
        assert!(distance(p("A"), a) < 1e-15, "A at t = {t}");
        assert_eq!(p("C"), [q[3], d, 0.0]);
        assert!(
            (distance(p("A"), p("C")) - l2).abs() < 1e-12,
            "rod length at t = {t}"
        );
        assert!((distance(p("O"), p("A")) - l1).abs() < 1e-15);
    }
}

#[test]
fn the_four_bar_draws_its_links_at_their_lengths() {
    let four_bar = builtin("planar_four_bar").unwrap();
    let (l1, l2, l3, dx) = (0.1, 0.4, 0.3, 0.35);
    for (t, q) in states(four_bar.as_ref()) {
        let p = drawn(four_bar.as_ref(), t, &q);
        assert_eq!((p("A"), p("D")), ([0.0; 3], [dx, 0.0, 0.0]));
        // (Generated code takes sin and cos from the inline sin_cos: 1 ulp from std's.)
        let b = [l1 * q[0].cos(), l1 * q[0].sin(), 0.0];
        assert!(distance(p("B"), b) < 1e-16, "B at t = {t}");
        assert!((distance(p("A"), p("B")) - l1).abs() < 1e-15);
        assert!((distance(p("B"), p("C")) - l2).abs() < 1e-15);
        // C is written through the crank and coupler; the rocker closes the loop on it.
        assert!(
            (distance(p("C"), p("D")) - l3).abs() < 1e-10,
            "rocker at t = {t}"
        );
    }
}

#[test]
fn compiled_and_interpreted_draw_the_same() {
    for name in ["spatial_crank_slider", "spatial_four_bar_bodies", "bricard"] {
        let compiled = builtin(name).unwrap();
        let interpreted = Interpreted::from_source(builtin_source(name).unwrap()).unwrap();
        assert_eq!(
            compiled.info().drawing,
            interpreted.info().drawing,
            "{name}"
        );
        for (t, q) in states(compiled.as_ref()).into_iter().step_by(5) {
            let n = 3 * compiled.info().drawing.points.len();
            let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
            compiled.draw_points(t, &q, &mut a);
            interpreted.draw_points(t, &q, &mut b);
            // One derived program on both routes: the same bits.
            assert_eq!(a, b, "{name} at t = {t}");
        }
    }
}

#[test]
fn a_short_output_slice_is_left_untouched() {
    let seed = builtin("spatial_crank_slider").unwrap();
    let mut out = [7.0; 5];
    seed.draw_points(0.0, &[0.0, 0.46, 0.84, 0.2], &mut out);
    assert_eq!(out, [7.0; 5]);
}

#[test]
fn a_long_run_is_decimated_to_the_frame_limit_keeping_the_last_sample() {
    use mechanism::output::{MAX_FRAMES, Scene};
    let four_bar = builtin("planar_four_bar").unwrap();
    let options = SimulationOptions {
        t_end: 40.0,
        output_rate: 100.0,
        ..Default::default()
    };
    let trajectory = simulate(four_bar.as_ref(), &options).unwrap();
    assert_eq!(trajectory.len(), 4001);
    let scene = Scene::new(four_bar.as_ref(), &trajectory, MAX_FRAMES).unwrap();
    // k = ceil(4001 / 1499) = 3: samples 0, 3, .., 3999 and the last, 4000.
    assert_eq!(scene.decimation, 3);
    assert!(scene.frames() <= MAX_FRAMES);
    assert_eq!(scene.frames(), 1335);
    assert_eq!(scene.times[1], trajectory.sample(3).t);
    assert_eq!(*scene.times.last().unwrap(), trajectory.last().unwrap().t);
    assert!(
        scene.note.contains("one sample in 3 of 4001"),
        "{}",
        scene.note
    );
}
