//! The exact solution of the IFToMM A02 chain of N four-bar loops (41 rockers and 40
//! couplers for N = 40, 1 m and 1 kg each, gravity 9.81 m/s^2 along -y): on the branch the
//! benchmark follows, every rocker keeps one angle th from +x and the couplers stay
//! horizontal, so with T = ((N+1)/3 + N)/2 th'^2 and Pi = ((N+1)/2 + N) g sin th,
//!
//! ```text
//! ((N+1)/3 + N) th'' = -((N+1)/2 + N) g cos th,   th(0) = pi/2,  th'(0) = -1 rad/s.
//! ```
//!
//! Shared by the runtime test and the A02 benchmark, so both measure against one truth.

/// Gravity of the benchmark (m/s^2).
pub const G: f64 = 9.81;

/// (th, th') of the exact branch of the chain with `n` couplers at each of `times`
/// (ascending), by classical RK4 at h = 1e-4 s (global error below 1e-9 rad over 20 s).
pub fn branch(n: usize, times: &[f64]) -> Vec<(f64, f64)> {
    let (a, b) = (
        (n + 1) as f64 / 3.0 + n as f64,
        (n + 1) as f64 / 2.0 + n as f64,
    );
    let k = b * G / a;
    let f = |y: [f64; 2]| [y[1], -k * y[0].cos()];
    let (mut y, mut t) = ([std::f64::consts::FRAC_PI_2, -1.0], 0.0);
    let mut out = Vec::with_capacity(times.len());
    for &target in times {
        while t < target - 1e-12 {
            let h = (target - t).min(1e-4);
            let k1 = f(y);
            let k2 = f([y[0] + h / 2.0 * k1[0], y[1] + h / 2.0 * k1[1]]);
            let k3 = f([y[0] + h / 2.0 * k2[0], y[1] + h / 2.0 * k2[1]]);
            let k4 = f([y[0] + h * k3[0], y[1] + h * k3[1]]);
            for i in 0..2 {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
            t += h;
        }
        out.push((y[0], y[1]));
    }
    out
}

/// The times in (0, t_end) where the branch lies flat (sin th = 0, all rockers
/// horizontal): the singular positions a run must pass, to ~1e-8 s by linear interpolation
/// on a 1e-4 s grid.
pub fn crossings(n: usize, t_end: f64) -> Vec<f64> {
    let h = 1e-4;
    let steps = (t_end / h).round() as usize;
    let grid: Vec<f64> = (0..=steps).map(|i| i as f64 * h).collect();
    let th = branch(n, &grid);
    let mut out = Vec::new();
    for i in 1..grid.len() {
        let (a, b) = (th[i - 1].0.sin(), th[i].0.sin());
        if a * b < 0.0 {
            out.push(grid[i - 1] + h * a / (a - b));
        }
    }
    out
}

/// The `.mech` text of A02 in rocker and coupler angles with `n` windows (1 m, 1 kg bars,
/// every window a rhombus; `benches/scale/a02_angles.py` writes the same), its coordinates
/// declared window by window (th0, ps1, th1, ...) or, with `grouped`, by kind (all rockers,
/// then all couplers); released with every rocker vertical and th0' = 1 rad/s.
pub fn angles_declaration(n: usize, grouped: bool) -> String {
    let names: Vec<String> = if grouped {
        let th = (0..=n).map(|i| format!("th{i}"));
        th.chain((1..=n).map(|i| format!("ps{i}"))).collect()
    } else {
        let pairs = (1..=n).flat_map(|i| [format!("ps{i}"), format!("th{i}")]);
        std::iter::once("th0".to_string()).chain(pairs).collect()
    };
    let start = |x: &str| {
        if x.starts_with("th") {
            "1.5707963267948966"
        } else {
            "0.0"
        }
    };
    let mut s = format!("pub struct A02Angles{n};\nparameters {{ g = {G}; }}\ncoordinates {{\n");
    for x in &names {
        s += &format!("    {x} = {};\n", start(x));
    }
    s += "}\nindependent { th0 = 1.5707963267948966; der(th0) = 1.0; }\n";
    let mut kinetic: Vec<String> = (0..=n).map(|i| format!("der(th{i})^2/6")).collect();
    let mut potential: Vec<String> = (0..=n).map(|i| format!("g*sin(th{i})/2")).collect();
    let mut rows = String::new();
    for i in 1..=n {
        let (t, p, t1) = (format!("th{}", i - 1), format!("ps{i}"), format!("th{i}"));
        kinetic.push(format!(
            "der({t})^2/2 + cos({t} - {p})*der({t})*der({p})/2 + der({p})^2/6"
        ));
        potential.push(format!("g*(sin({t}) + sin({p})/2)"));
        rows += &format!("    cos({t}) + cos({p}) - 1 - cos({t1});\n");
        rows += &format!("    sin({t}) + sin({p}) - sin({t1});\n");
    }
    s += &format!("kinetic = {};\n", kinetic.join(" + "));
    s += &format!("potential = {};\n", potential.join(" + "));
    s + &format!("constraints {{\n{rows}}}\n")
}
