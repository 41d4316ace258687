//! `mechanism linearize` of the Whipple bicycle far beyond its speeds (issue 53, item 2):
//! the eigenvalues printed are those of the state matrix written, the lean and steer are
//! never taken for structural zeros, and where double precision cannot resolve the answer
//! the command refuses with the reason.

use super::{assert_one_line_error, mechanism, out_dir, stderr};

/// Reads the state matrix S, the variables, the structural zeros and the eigenvalues
/// printed (stdout) and written.
struct Written {
    variables: Vec<String>,
    s: Vec<Vec<f64>>,
    structural: Vec<String>,
    printed: Vec<(f64, f64)>,
    all: Vec<(f64, f64)>,
}

fn linearize(name: &str, args: &[&str]) -> Written {
    let dir = out_dir(name);
    let mut argv = vec![
        "linearize",
        "whipple_bicycle",
        "--out",
        dir.to_str().unwrap(),
    ];
    argv.extend_from_slice(args);
    let o = mechanism(&argv);
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    // The printed lines "  -1.4e1 +0.0e0 i" below "eigenvalues without the structural zeros".
    let printed = stdout
        .lines()
        .skip_while(|l| !l.starts_with("eigenvalues without"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .map(|l| {
            let w: Vec<f64> = l
                .split_whitespace()
                .take(2)
                .map(|x| x.parse().unwrap())
                .collect();
            (w[0], w[1])
        })
        .collect();
    let text = std::fs::read_to_string(dir.join("linearization.json")).unwrap();
    let j: serde_json::Value = serde_json::from_str(&text).unwrap();
    let strings = |v: &serde_json::Value| -> Vec<String> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_str().unwrap().to_string())
            .collect()
    };
    let pairs = |v: &serde_json::Value| -> Vec<(f64, f64)> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
            .collect()
    };
    Written {
        variables: strings(&j["variables"]),
        s: j["state_matrix"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| {
                r.as_array()
                    .unwrap()
                    .iter()
                    .map(|x| x.as_f64().unwrap())
                    .collect()
            })
            .collect(),
        structural: strings(&j["structural_zeros"]),
        printed,
        all: pairs(&j["eigenvalues"]),
    }
}

/// Complex arithmetic on (re, im) pairs, enough for the characteristic polynomial.
fn mul(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}
fn add(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    (a.0 + b.0, a.1 + b.1)
}
fn scale(a: (f64, f64), k: f64) -> (f64, f64) {
    (a.0 * k, a.1 * k)
}
fn abs(a: (f64, f64)) -> f64 {
    a.0.hypot(a.1)
}

/// At v = 1e5 and 1e6 m/s (entries of S up to 2e10 and 2e12): the lean phi and steer delta
/// with their rates are the variables that are not structural (their columns hold the
/// gravity and speed terms), the others are (the ground position, the heading and the
/// wheels' angles are ignorable, the rear wheel's rate is conserved), and the four printed
/// eigenvalues are the roots of the characteristic polynomial of the written matrix's
/// lean-steer block, det(lambda^2 I - lambda C - K) with K = dq''/dq and C = dq''/dq' of
/// (phi, delta): each with a relative residual |p(lambda)| / p~(|lambda|) (p~ the same
/// expansion with every term's magnitude) within the solver's round-off, and together with the sum tr C and
/// the product det K of the roots. On main the lean and steer were taken for structural
/// zeros beside the large entries and two wrong eigenvalues were printed.
#[test]
fn the_bicycle_far_beyond_its_speeds_prints_the_eigenvalues_of_its_state_matrix() {
    for v in ["1e5", "1e6"] {
        let w = linearize(
            &format!("linearize-scale-{v}"),
            &["--set", &format!("v={v}")],
        );
        let at = |name: &str| w.variables.iter().position(|n| n == name).unwrap();
        let (phi, delta, dphi, ddelta) = (at("phi"), at("delta"), at("der(phi)"), at("der(delta)"));
        let mut structural = w.structural.clone();
        structural.sort();
        assert_eq!(
            structural,
            ["der(thR)", "psi", "thF", "thR", "x", "y"],
            "v = {v}"
        );
        // The block's own rows: phi' = der(phi), delta' = der(delta), exactly.
        for (row, one) in [(phi, dphi), (delta, ddelta)] {
            for (j, x) in w.s[row].iter().enumerate() {
                assert_eq!(*x, if j == one { 1.0 } else { 0.0 }, "v = {v}");
            }
        }
        let k = |i: usize, j: usize| w.s[i][j];
        let (k00, k01, k10, k11) = (
            k(dphi, phi),
            k(dphi, delta),
            k(ddelta, phi),
            k(ddelta, delta),
        );
        let (c00, c01, c10, c11) = (
            k(dphi, dphi),
            k(dphi, ddelta),
            k(ddelta, dphi),
            k(ddelta, ddelta),
        );
        assert!(k00 != 0.0 && k10 != 0.0, "phi's column is not zero");
        assert_eq!(w.printed.len(), 4, "v = {v}: {:?}", w.printed);
        for &l in &w.printed {
            let l2 = mul(l, l);
            let d0 = add(l2, scale(l, -c00));
            let d1 = add(l2, scale(l, -c11));
            let p = add(
                mul(add(d0, (-k00, 0.0)), add(d1, (-k11, 0.0))),
                scale(
                    mul(
                        add(scale(l, c01), (k01, 0.0)),
                        add(scale(l, c10), (k10, 0.0)),
                    ),
                    -1.0,
                ),
            );
            let m = abs(l);
            let magnitude = (m * m + m * c00.abs() + k00.abs())
                * (m * m + m * c11.abs() + k11.abs())
                + (m * c01.abs() + k01.abs()) * (m * c10.abs() + k10.abs());
            // A root from a backward stable eigen solver is exact for a matrix within about
            // eps ||B|| of the balanced S, ||B|| ~ 1e5 to 1e6 here; for the capsize root,
            // 1e-10 to 1e-12 of that, this is a relative error of up to eps 1e12 ~ 1e-4 in
            // it, and a coefficient-wise residual of the polynomial up to ~1e-7 (measured:
            // 1.8e-8 at v = 1e5). 1e-6 stays far below the 0.05 to 0.2 of a wrong root.
            let r = abs(p) / magnitude;
            println!("v = {v}: lambda = {l:?}, residual {r:.1e}");
            assert!(r < 1e-6, "v = {v}: lambda = {l:?}, residual {r:e}");
        }
        // Vieta: the four roots sum to tr C (1e-9: 15 printed digits, the large roots to
        // round-off) and multiply to det K (the product carries the capsize root's relative
        // error, above: measured 8e-8 at v = 1e5, so 1e-6).
        let sum = w.printed.iter().fold((0.0, 0.0), |a, &l| add(a, l));
        let product = w.printed.iter().fold((1.0, 0.0), |a, &l| mul(a, l));
        let trace = c00 + c11;
        assert!((sum.0 - trace).abs() < 1e-9 * trace.abs() && sum.1.abs() < 1e-9 * trace.abs());
        let det = k00 * k11 - k01 * k10;
        let terms = (k00 * k11).abs() + (k01 * k10).abs();
        assert!(
            (product.0 - det).abs() < 1e-6 * terms,
            "v = {v}: {product:?} vs {det:e}"
        );
        // The written spectrum: the four printed (each within 1e-6 of itself, the capsize
        // root's accuracy above, plus 1e-12 of the largest, the solver's round-off), and
        // six zeros (at most 1e-12 of the largest; the capsize root is 1e-10 of it).
        let big = w.printed.iter().map(|&l| abs(l)).fold(0.0, f64::max);
        let mut rest = w.all.clone();
        for &l in &w.printed {
            let k = rest
                .iter()
                .position(|&a| abs(add(a, scale(l, -1.0))) <= 1e-6 * abs(l) + 1e-12 * big)
                .unwrap_or_else(|| panic!("v = {v}: {l:?} not among {:?}", w.all));
            rest.remove(k);
        }
        assert_eq!(rest.len(), 6, "v = {v}");
        assert!(
            rest.iter().all(|&a| abs(a) <= 1e-12 * big),
            "v = {v}: {rest:?}"
        );
    }
}

/// At v = 1e7 the gravity terms lie at 1e-13 of their rows, where round-off of the yaw
/// column also falls; at 1e9 m/s (and at a rear wheel rate of 1e9 rad/s, v = 3e8 m/s) S
/// spans 1 to 2e18. Each is refused with the reason, exit 1, nothing written (on main:
/// exit 0, with lean and steer as structural zeros and two wrong eigenvalues).
#[test]
fn the_bicycle_where_double_precision_cannot_resolve_it_is_refused() {
    for (args, why) in [
        (
            &["--set", "v=1e7"][..],
            "whether they give structural zero eigenvalues cannot be told",
        ),
        (
            &["--set", "v=1e9"][..],
            "a spread beyond the 1e15 that double precision resolves",
        ),
        (&["--init", "der(thR)=1e9"][..], "a spread beyond the 1e15"),
    ] {
        let dir = out_dir(&format!("linearize-refused-{}", args[1]));
        let mut argv = vec![
            "linearize",
            "whipple_bicycle",
            "--out",
            dir.to_str().unwrap(),
        ];
        argv.extend_from_slice(args);
        let o = mechanism(&argv);
        assert_one_line_error(&o, "its eigenvalues cannot be resolved in double precision");
        assert!(stderr(&o).contains(why), "{}", stderr(&o));
        assert!(!dir.exists(), "{args:?}: nothing written");
    }
}
