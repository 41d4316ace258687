//! `mechanism inverse --init`: guesses of the coordinates that are not driven pick the
//! assembly branch the prescribed motion follows; a driven coordinate or a rate is refused.

use super::{assert_one_line_error, mechanism, out_dir, stderr};

/// The planar four-bar (l1 = 0.1, l2 = 0.4, l3 = 0.3, Dx = 0.35 m) driven at th1 = pi/2 +
/// 2 pi t: from the declared guesses it follows the branch with the coupler joint C above
/// the ground line (th2 = 0.5235), from th2 = -0.5, th3 = -1.6 the mirror branch below it.
/// At t = 0 both rows of the loop close on the second branch and C lies below the line.
#[test]
fn init_picks_the_branch_a_drive_follows() {
    let dir = out_dir("inverse-branch");
    let run = |extra: &[&str]| -> Vec<f64> {
        let d = dir.to_str().unwrap();
        let mut args = vec![
            "inverse",
            "planar_four_bar",
            "--drive",
            "th1 = pi/2 + 2*pi*t",
            "--t-end",
            "0.1",
            "--out",
            d,
        ];
        args.extend(extra);
        let o = mechanism(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        let csv = std::fs::read_to_string(dir.join("inverse.csv")).unwrap();
        let first = csv.lines().nth(1).unwrap();
        first.split(',').map(|v| v.parse().unwrap()).collect()
    };
    let above = run(&[]);
    let below = run(&["--init", "th2=-0.5", "--init", "th3=-1.6"]);
    let (l1, l2, l3, dx) = (0.1_f64, 0.4_f64, 0.3_f64, 0.35_f64);
    for (row, upper) in [(&above, true), (&below, false)] {
        let (t1, t2, t3) = (row[1], row[2], row[3]);
        let cx = l1 * t1.cos() + l2 * t2.cos() - dx - l3 * t3.cos();
        let cy = l1 * t1.sin() + l2 * t2.sin() - l3 * t3.sin();
        // Newton's tolerance, 1e-12 m.
        assert!(cx.abs() < 1e-12 && cy.abs() < 1e-12, "{row:?}");
        // C = B + l2 (cos th2, sin th2), B = (0, l1) at th1 = pi/2.
        let c_y = l1 * t1.sin() + l2 * t2.sin();
        assert_eq!(c_y > 0.0, upper, "{row:?}");
    }
}

#[test]
fn init_of_a_driven_coordinate_or_a_rate_is_refused() {
    let dir = out_dir("inverse-branch-refused");
    let d = dir.to_str().unwrap();
    let base = [
        "inverse",
        "planar_four_bar",
        "--drive",
        "th1 = 2*pi*t",
        "--out",
        d,
    ];
    let o = mechanism(&[&base[..], &["--init", "th1=3"]].concat());
    assert_one_line_error(&o, "--init th1: `th1` is driven; its drive prescribes it");
    let o = mechanism(&[&base[..], &["--init", "der(th2)=3"]].concat());
    assert_one_line_error(
        &o,
        "--init der(th2): in inverse the rates follow from the drives",
    );
}
