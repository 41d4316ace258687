//! Kinks of a prescribed motion: a drive q_k = f(t) whose rate f' jumps at some t*
//! (`0.3 + 0.2*abs(t - 0.5)`) has an infinite acceleration there, so its driving force is
//! an impulse that no sample shows. Inverse dynamics samples f at fixed times, so the jump is
//! looked for between every two samples, not only at them.
//!
//! On [a, b] a smooth f has f'(b) - f'(a) = integral of f'' <= (b - a) max |f''|. The
//! interval is suspect when |f'(b) - f'(a)| exceeds twice (b - a) times the largest |f''| of
//! a, b and the midpoint (a well-sampled smooth f stays within about 1 + O((b - a)^2) of
//! it). A suspect interval is halved [`HALVINGS`] times, keeping the half with the larger
//! change of f'. A smooth f' changes over the last piece, 2^-60 (b - a) long, by about
//! that length times f''; a kink keeps its whole jump. The jump is a kink when it is still
//! above [`KINK_JUMP`] times max(1, |f'(a)|, |f'(b)|).

use crate::algorithms::kinematics::Drive;
use crate::error::Error;

/// Halvings of a suspect interval (2^-60 of a 0.01 s sample interval is 9e-21 s, below
/// the spacing of f64 near 1 s: the last piece is as short as t can resolve).
const HALVINGS: usize = 60;

/// A jump of f' above this fraction of max(1, |f'|) is a kink (a smooth f' changes by
/// about 1e-16 over the last piece).
pub const KINK_JUMP: f64 = 1e-6;

/// [`Error::DriveKink`] if the rate of `drive` (of the coordinate `name`) jumps between
/// `a` and `b` or at either (one-sided rates, where f' itself is not finite).
pub fn check_kink(drive: &Drive, name: &str, a: f64, b: f64) -> Result<(), Error> {
    let rate = |t: f64| (drive.f)(t)[1];
    let accel = |t: f64| (drive.f)(t)[2];
    let scale = |x: f64, y: f64| 1f64.max(x.abs()).max(y.abs());
    let (mut lo, mut hi) = (a, b);
    let (mut r_lo, mut r_hi) = (rate(lo), rate(hi));
    if !r_hi.is_finite() {
        return check_kink_at(drive, name, b); // a kink on the sample itself
    }
    if !r_lo.is_finite() {
        return Ok(()); // the previous sample was tested
    }
    let bound = 2.0
        * (b - a)
        * accel(a)
            .abs()
            .max(accel(b).abs())
            .max(accel(0.5 * (a + b)).abs());
    // A NaN bound (f'' undefined at a test point) goes on to the halvings.
    if (r_hi - r_lo).abs() <= bound {
        return Ok(());
    }
    for _ in 0..HALVINGS {
        let mid = 0.5 * (lo + hi);
        if !(mid > lo && mid < hi) {
            break;
        }
        let r_mid = rate(mid);
        if !r_mid.is_finite() {
            // f' undefined at mid (the kink itself): compare the rates beside it.
            (lo, hi, r_lo, r_hi) = one_sided(&rate, mid, r_lo, r_hi);
            break;
        }
        if (r_mid - r_lo).abs() >= (r_hi - r_mid).abs() {
            (hi, r_hi) = (mid, r_mid);
        } else {
            (lo, r_lo) = (mid, r_mid);
        }
    }
    let jump = r_hi - r_lo;
    if jump.abs() > KINK_JUMP * scale(r_lo, r_hi) {
        return Err(Error::DriveKink {
            coordinate: name.to_string(),
            t: 0.5 * (lo + hi),
            before: r_lo,
            after: r_hi,
        });
    }
    Ok(())
}

/// The rates just before and after `t` (1e-9 of max(1, |t|) away), where f' is not finite
/// at t itself; `r_lo`, `r_hi` are kept if those are not finite either.
fn one_sided(rate: &impl Fn(f64) -> f64, t: f64, r_lo: f64, r_hi: f64) -> (f64, f64, f64, f64) {
    let eps = 1e-9 * t.abs().max(1.0);
    let (before, after) = (rate(t - eps), rate(t + eps));
    if before.is_finite() && after.is_finite() {
        (t - eps, t + eps, before, after)
    } else {
        (t - eps, t + eps, r_lo, r_hi)
    }
}

/// [`Error::DriveKink`] if the rate of `drive` is not finite at `t` while it is finite just
/// before and after and jumps there (a kink that falls on a sample).
pub fn check_kink_at(drive: &Drive, name: &str, t: f64) -> Result<(), Error> {
    let rate = |s: f64| (drive.f)(s)[1];
    let (lo, hi, before, after) = one_sided(&rate, t, f64::NAN, f64::NAN);
    if before.is_finite() && after.is_finite() {
        return check_kink(drive, name, lo, hi);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// f = 0.3 + 0.2 |t - c| with its derivatives (f' undefined at c, as the derived
    /// drive gives it: 0/0).
    fn abs_drive(c: f64) -> Drive {
        Drive::new(0, move |t| {
            let u = t - c;
            [0.3 + 0.2 * u.abs(), 0.2 * u / u.abs(), 0.0]
        })
    }

    #[test]
    fn a_kink_between_samples_is_located_and_its_jump_measured() {
        let err = check_kink(&abs_drive(0.505), "x", 0.5, 0.51).expect_err("kink");
        match err {
            Error::DriveKink {
                t, before, after, ..
            } => {
                // 60 halvings of 0.01 s: located to f64 resolution near 0.5.
                assert!((t - 0.505).abs() < 1e-12, "{t}");
                assert_eq!((before, after), (-0.2, 0.2));
            }
            other => panic!("{other}"),
        }
        // On a sample: f' is NaN there, the rates beside it jump.
        assert!(check_kink(&abs_drive(0.5), "x", 0.49, 0.5).is_err());
        assert!(check_kink_at(&abs_drive(0.5), "x", 0.5).is_err());
        // Away from the kink: no jump.
        check_kink(&abs_drive(0.505), "x", 0.51, 0.52).expect("smooth there");
    }

    #[test]
    fn a_smooth_drive_sampled_coarsely_passes() {
        // sin(10 t) at 0.1 s samples: 1 rad of phase per interval, far from resolved, still
        // no kink (the halvings find f' continuous).
        let smooth = Drive::new(0, |t| {
            let w = 10.0;
            [(w * t).sin(), w * (w * t).cos(), -w * w * (w * t).sin()]
        });
        for k in 0..100 {
            let a = k as f64 * 0.1;
            check_kink(&smooth, "x", a, a + 0.1).expect("smooth");
        }
    }
}
