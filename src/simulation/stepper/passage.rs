//! Steps over a singular position: where an adaptive explicit step puts a predicted
//! singular position t* (the time at which Phi_q loses rank, extrapolated by
//! [`crate::simulation::singular`]'s watch), so that no stage of the step is evaluated
//! near it.
//!
//! Why: near a singular position the right-hand side is ill-conditioned. With w the
//! weakest row independence (w ~ |t - t*| near a simple passage), a position residual
//! eps along the rows that lose rank changes q'' by about eps / w^3 (the motion on the
//! level set Phi = eps turns onto another branch at the crossing), a velocity residual by
//! eps / w^2. Round-off alone (eps ~ 1e-14 for A02) makes q'' at w = 1e-4 uncertain in its
//! third digit. The exact motion is smooth through t*; only the evaluation of f near it is
//! not. A step whose stages all keep a distance from t* measures its truncation error; one
//! that puts a stage near t* measures noise, is rejected, and the smaller step that
//! follows ends nearer still: the step size collapses onto t* (A02 at rtol 1e-10 stopped
//! at its 132nd passage, at 1e-12 at its 17th). So the step that passes t* is placed to
//! put t* at the middle of the widest interval between the method's nodes (DOP853:
//! (1/3, 0.6), every stage at least 0.13 h away; DOPRI5: (0.3, 0.8)), and no step ends
//! just before t*.
//!
//! Why a straddle must not be small: the noise is that of the level set. The projection
//! leaves |Phi| ~ 1e-15 to 1e-14, and near a crossing of two branches the level set
//! Phi = eps is a hyperbola (x y = eps, x along the branch, y across it) whose offset
//! y ~ eps / x, rate
//! y' ~ eps / x^2 and acceleration y'' ~ eps / x^3 grow as a stage comes nearer to t*
//! (A02, N = 200, rtol 1e-7: the couplers' ps'' at the stages, exactly 0 on the branch, are
//! 1e-7 to 2e-6 rad/s^2 between 1e-3 and 4e-4 s before t*). Measured against the absolute
//! tolerance of those coordinates (atol 1e-10), a straddle of size s with its nearest
//! stages 0.13 s from t* has an error from this noise of about s eps / (0.13 s)^3, which
//! falls as s grows: at s = 6e-3 s A02's error norm was 32, at the control's size (0.07 to
//! 0.2 s) it stays below 1. The prediction of t* was not the cause there (2e-6 s off).
//!
//! The watch predicts t* only once w < [`crate::simulation::singular::COARSE`], so a step
//! taken with no prediction can end just before t* (A02 grouped by kind: 2.8e-3 s before,
//! after a step of 0.106 s). The driver then retakes it ([`ends_too_near`], the step
//! counted as rejected) from its start with t* known, and [`steer`] ends it far enough
//! before t* for a straddle of at least h / (1 + c); again while the retaken step's own
//! prediction, made nearer to t*, says it still ends too near (a prediction from w near
//! [`crate::simulation::singular::COARSE`] can be late by most of the distance).
//!
//! A straddle placed by a prediction made far from t* can put t* on a node (A02 in angles:
//! predicted 0.013 to 0.018 s early, so at theta = 0.60 to 0.64 of a 0.1 s step, beside
//! DOP853's nodes 0.6 and 0.651) and is rejected. That rejection says nothing about the
//! size the smooth motion allows, so the first one of a passage leaves the control's size
//! as it was: the approach step ends before t*, predicts it from nearer, and the straddle
//! that follows has the size the control wanted. Shrinking it instead left straddles short
//! enough to fail on the noise alone, each shorter than the last, until the step size
//! collapsed or a step jumped onto the other branch (A02 N = 15 at rtol 1e-6: an energy
//! jump of 8.2 J).

/// The widest open interval of (0, 1) that holds none of `nodes` (each in [0, 1]).
pub(crate) fn widest_gap(nodes: &[f64]) -> (f64, f64) {
    let mut sorted: Vec<f64> = nodes.iter().copied().chain([0.0, 1.0]).collect();
    sorted.sort_by(f64::total_cmp);
    sorted
        .windows(2)
        .map(|w| (w[0], w[1]))
        .fold((0.0, 0.0), |best, (a, b)| {
            if b - a > best.1 - best.0 {
                (a, b)
            } else {
                best
            }
        })
}

/// The size of the next trial step from t when a singular position is predicted at
/// t + `d` (d > 0), the step control asking for `h` and the method's node-free interval
/// `gap` = (lo, hi), centre c = (lo + hi) / 2. Never more than `h`:
///
/// - d >= (1 + c) h: `h`, which ends at least c h before t*;
/// - d <= c h, unless a straddling trial of this step was rejected (`straddle_rejected`):
///   d / c, a step that straddles t* with t* at the centre of the gap;
/// - otherwise d / (1 + c): a step that ends c d / (1 + c) before t*, so that the next one
///   straddles t* with the same size.
///
/// No trial ends nearer to t* than c times the size of the step that then straddles it.
/// Where the tolerance cannot be met with the stages that far from t*, every straddle is
/// rejected and the steps before it shrink by c / (1 + c) (DOP853: 0.32): the step size
/// collapses and the run stops with the singular position named.
pub(crate) fn steer(h: f64, d: f64, gap: (f64, f64), straddle_rejected: bool) -> f64 {
    let c = 0.5 * (gap.0 + gap.1);
    if d >= (1.0 + c) * h {
        h
    } else if !straddle_rejected && d <= c * h {
        d / c
    } else {
        d / (1.0 + c)
    }
}

/// Whether a step of size `h` that ends `d` (> 0) before a singular position predicted only
/// after it was taken must be taken again, steered: when d < 0.75 c h (c the centre of
/// `gap`; the margin keeps a step that was steered to end c h before t* from being retaken
/// for a small change in its prediction), the step that would then straddle t* is smaller
/// than this one, d / c; its stages fall nearer to t* than this step's size allows for.
/// Retaken from its start with t* known, [`steer`] ends it c (d + h) / (1 + c) before t*,
/// and the straddle that follows has size (d + h) / (1 + c), at least h / (1 + c).
pub(crate) fn ends_too_near(h: f64, d: f64, gap: (f64, f64)) -> bool {
    let c = 0.5 * (gap.0 + gap.1);
    d > 0.0 && d < RETAKE_MARGIN * c * h
}

/// The fraction of c h (see [`ends_too_near`]) nearer than which a step's end is retaken.
pub(crate) const RETAKE_MARGIN: f64 = 0.75;

/// Whether a step of size `h` from t straddles a singular position at t + `d`.
pub(crate) fn straddles(h: f64, d: f64) -> bool {
    d > 0.0 && d < h
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOP853: [f64; 16] = [
        0.0,
        0.0526001519587677,
        0.0789002279381516,
        0.118350341907227,
        0.281649658092773,
        1.0 / 3.0,
        0.25,
        0.307692307692308,
        0.651282051282051,
        0.6,
        0.857142857142857,
        1.0,
        1.0,
        0.1,
        0.2,
        0.777777777777778,
    ];

    #[test]
    fn the_widest_gap_of_dop853_and_dopri5() {
        let (lo, hi) = widest_gap(&DOP853);
        assert_eq!((lo, hi), (1.0 / 3.0, 0.6));
        let dopri5 = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
        assert_eq!(widest_gap(&dopri5), (0.3, 0.8));
    }

    /// A steered step is at most `h`; one that straddles t* keeps every node at least half
    /// the gap's width times its size from t*; one that does not ends at least c times its
    /// size before t*; a straddle is never retried after its rejection.
    #[test]
    fn a_steered_step_keeps_its_nodes_away_from_the_singular_position() {
        let gap = widest_gap(&DOP853);
        let c = 0.5 * (gap.0 + gap.1);
        let half = 0.5 * (gap.1 - gap.0);
        for &h in &[1e-3, 1e-2, 0.1] {
            for k in 1..400 {
                let d = k as f64 * 1e-4;
                for rejected in [false, true] {
                    let s = steer(h, d, gap, rejected);
                    assert!(s > 0.0);
                    if straddles(s, d) {
                        assert!(!rejected, "h {h} d {d}");
                        let nearest = DOP853
                            .iter()
                            .map(|&ci| (ci * s - d).abs())
                            .fold(f64::INFINITY, f64::min);
                        assert!(
                            nearest >= half * s * (1.0 - 1e-12),
                            "h {h} d {d}: {nearest}"
                        );
                    } else {
                        assert!(d - s >= c * s * (1.0 - 1e-12), "h {h} d {d} s {s}");
                    }
                    assert!(s <= h * (1.0 + 1e-12), "h {h} d {d} s {s}");
                }
            }
        }
    }

    /// A step that ends d < 0.75 c h before t* is retaken; retaken from its start with t*
    /// known, its steered size ends c times the next step's size before t*, and that next
    /// step (the control still asking for h) straddles t* with at least h / (1 + c), where
    /// without the retake it would straddle with d / c, as small as the distance left. A
    /// step that ends farther before t*, or after it, is kept.
    #[test]
    fn a_step_ending_just_before_the_singular_position_is_retaken_to_straddle_it_wide() {
        let gap = widest_gap(&DOP853);
        let c = 0.5 * (gap.0 + gap.1);
        for &h in &[1e-3, 1e-2, 0.1] {
            for k in 1..400 {
                let d = k as f64 * 1e-3 * h;
                let retake = ends_too_near(h, d, gap);
                assert_eq!(retake, d < RETAKE_MARGIN * c * h, "h {h} d {d}");
                if !retake {
                    continue;
                }
                let from_start = d + h;
                let first = steer(h, from_start, gap, false);
                assert!(!straddles(first, from_start), "h {h} d {d}");
                let left = from_start - first;
                let second = steer(h, left, gap, false);
                assert!(straddles(second, left), "h {h} d {d}");
                assert!(left >= c * second * (1.0 - 1e-12), "h {h} d {d}");
                assert!(
                    second >= h / (1.0 + c) * (1.0 - 1e-12),
                    "h {h} d {d}: {second}"
                );
                assert!(second > d / c, "h {h} d {d}");
            }
            assert!(!ends_too_near(h, -1e-3 * h, gap));
            assert!(!ends_too_near(h, 0.0, gap));
        }
    }
}
