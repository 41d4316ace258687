//! Axis ranges, tick labels, the decade axis, data thinning and legend placement.

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::SeriesLabelPosition;

use super::LOG_FLOOR;
use super::spec::{LEGEND_MARGIN, Panel};

/// Lines with more points than this are thinned (min/max per bucket, so peaks survive).
const MAX_POINTS: usize = 4000;

pub(super) fn superscript(n: i32) -> String {
    const SUP: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let digits = n
        .unsigned_abs()
        .to_string()
        .chars()
        .map(|c| SUP[c.to_digit(10).unwrap_or(0) as usize])
        .collect::<String>();
    if n < 0 {
        format!("⁻{digits}")
    } else {
        digits
    }
}

/// Differences below this fraction of a figure's scale are round-off: a series that varies
/// by no more is drawn as a constant (16 digits carry about 1e-16; a solve loses a few).
pub(super) const ROUND_OFF: f64 = 1e-12;

/// Range of the finite values in `ys`, padded by 5 %, never empty. `scale` is the magnitude
/// of the quantity across the whole mechanism (the largest |q| of the same unit, say): a
/// series whose spread is at most [`ROUND_OFF`] of it (or of its own magnitude) is drawn
/// constant, centred in a range of +-10 % of `scale` (at least +-1e-3), so the round-off of
/// a coordinate that stays at 0 is not magnified to full height.
pub(super) fn linear_range<'a>(ys: impl Iterator<Item = &'a f64>, scale: f64) -> (f64, f64) {
    let (lo, hi) = ys
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if lo > hi {
        return (-1.0, 1.0);
    }
    let span = hi - lo;
    let magnitude = lo.abs().max(hi.abs()).max(scale.abs());
    if span <= ROUND_OFF * magnitude || span == 0.0 {
        let mid = 0.5 * (lo + hi);
        let mid = if mid.abs() <= ROUND_OFF * magnitude {
            0.0
        } else {
            mid
        };
        let pad = (0.1 * mid.abs()).max(0.1 * scale.abs()).max(1e-3);
        return (mid - pad, mid + pad);
    }
    (lo - 0.05 * span, hi + 0.05 * span)
}

/// From the first to the last finite time, exactly (padded only when they coincide).
pub(super) fn time_range(t: &[f64]) -> (f64, f64) {
    let (lo, hi) = linear_range(std::iter::empty(), 0.0);
    let finite = || t.iter().copied().filter(|v| v.is_finite());
    match (finite().next(), finite().next_back()) {
        (Some(a), Some(b)) if b > a => (a, b),
        (Some(a), _) => (a - 0.5, a + 0.5),
        _ => (lo, hi),
    }
}

/// Whole decades around the finite log10 values in `ys`.
pub(super) fn decade_range<'a>(ys: impl Iterator<Item = &'a f64>) -> (f64, f64) {
    let (lo, hi) = ys
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if lo > hi {
        return (LOG_FLOOR.log10() - 1.0, LOG_FLOOR.log10() + 1.0);
    }
    let (lo, hi) = ((lo - 1e-9).floor(), (hi + 1e-9).ceil());
    (lo, hi.max(lo + 1.0))
}

/// Thins `(t, y)` to at most about [`MAX_POINTS`] points, keeping each bucket's min and max.
pub(super) fn thin(t: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    let n = t.len().min(y.len());
    let points = (0..n)
        .map(|i| (t[i], y[i]))
        .filter(|p| p.0.is_finite() && p.1.is_finite());
    if n <= MAX_POINTS {
        return points.collect();
    }
    let bucket = n.div_ceil(MAX_POINTS / 2);
    let all: Vec<_> = points.collect();
    let mut out = Vec::with_capacity(MAX_POINTS + 2);
    for chunk in all.chunks(bucket) {
        let lo = chunk
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.1.total_cmp(&b.1.1))
            .map_or(0, |p| p.0);
        let hi = chunk
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.1.total_cmp(&b.1.1))
            .map_or(0, |p| p.0);
        out.push(chunk[lo.min(hi)]);
        if lo != hi {
            out.push(chunk[lo.max(hi)]);
        }
    }
    out
}

/// Where the legend goes, and the y range that makes room for it: the corner whose box
/// (the legend's estimated size in pixels, plus its margin) holds the fewest data points, as
/// MATLAB's `'best'`; when every corner has data, the y range grows upward (by whole decades
/// on a log axis) until the upper-right box is empty. `plot` is the plot area in pixels.
pub(super) fn place_legend(
    panel: &Panel<'_>,
    x: (f64, f64),
    y: (f64, f64),
    plot: (f64, f64),
) -> (SeriesLabelPosition, (f64, f64)) {
    let chars = panel
        .lines
        .iter()
        .map(|l| l.label.chars().count())
        .max()
        .unwrap_or(0);
    let fw = ((36 + 12 + 2 * LEGEND_MARGIN + 11 * chars as i32) as f64 / plot.0).min(0.9);
    let fh = ((2 * LEGEND_MARGIN + 24 * panel.lines.len() as i32 + 8) as f64 / plot.1).min(0.6);
    let points = || {
        panel
            .lines
            .iter()
            .flat_map(|l| panel.t.iter().zip(&l.y))
            .filter(|p| p.1.is_finite())
    };
    let count = |right: bool, upper: bool| {
        points()
            .filter(|&(&t, &v)| {
                let (u, w) = ((t - x.0) / (x.1 - x.0), (v - y.0) / (y.1 - y.0));
                (if right { u > 1.0 - fw } else { u < fw })
                    && (if upper { w > 1.0 - fh } else { w < fh })
            })
            .count()
    };
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let (best, n) = corners
        .into_iter()
        .map(|(c, r, u)| (c, count(r, u)))
        .min_by_key(|p| p.1)
        .unwrap_or((SeriesLabelPosition::UpperRight, 0));
    if n == 0 {
        return (best, y);
    }
    let top = points()
        .filter(|&(&t, _)| (t - x.0) / (x.1 - x.0) > 1.0 - fw)
        .map(|p| *p.1)
        .fold(f64::NEG_INFINITY, f64::max);
    let top = top.max(y.0);
    // Room of height fh above `top`: (y1' - top) / (y1' - y0) >= fh.
    let mut hi = (top - fh * y.0) / (1.0 - fh) + 0.02 * (y.1 - y.0);
    if panel.log {
        hi = hi.ceil();
    }
    (SeriesLabelPosition::UpperRight, (y.0, hi.max(y.1)))
}

/// Tick label with up to 6 decimals (`60`, `6.2`, `0.125`), and exponent form for very
/// small or large magnitudes: [`tick_label_spanning`] for an axis of span 1.
pub(super) fn tick_label(v: &f64) -> String {
    tick_label_spanning(*v, 1.0)
}

/// Tick label on an axis of span `span` with at most 8 labels, so at least `span / 8`
/// apart: with d = 1 - floor(log10(span / 8)) decimals (at least 6, at most 15) neighbouring
/// labels differ (`0.0999995` and `0.1` on a span of 4e-6, where 6 decimals print both as
/// `0.1`); trailing zeros dropped; exponent form for very small or large magnitudes.
pub(super) fn tick_label_spanning(v: f64, span: f64) -> String {
    let step = span / 8.0;
    let decimals = if step > 0.0 && step.is_finite() {
        (1.0 - step.log10().floor()).clamp(6.0, 15.0) as usize
    } else {
        6
    };
    let a = v.abs();
    if a < 1e-12 {
        return "0".to_string();
    }
    if !(1e-3..1e5).contains(&a) {
        let s = format!("{v:.2e}");
        let (mantissa, exp) = s.split_once('e').unwrap_or((&s, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        return format!("{mantissa}e{exp}").replace('-', "−");
    }
    let s = format!("{v:.decimals$}");
    s.trim_end_matches('0')
        .trim_end_matches('.')
        .replace('-', "−")
}

pub(super) fn decade_label(v: &f64) -> String {
    let k = v.round() as i32;
    if k == 0 {
        "1".to_string()
    } else {
        format!("10{}", superscript(k))
    }
}

/// A y axis holding log10 of the data: bold lines and labels at whole decades (every
/// k-th decade when there are too many), light lines at 2..9 times each decade.
#[derive(Clone, Debug)]
pub(super) struct Decades {
    pub(super) lo: f64,
    pub(super) hi: f64,
}

impl Ranged for Decades {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        RangedCoordf64::from(self.lo..self.hi).map(value, limit)
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        let (lo, hi) = (self.lo.ceil() as i32, self.hi.floor() as i32);
        let count = (hi - lo + 1).max(1) as usize;
        let step = count.div_ceil(hint.max_num_points().max(1)).max(1);
        let bold = (lo..=hi).step_by(step).map(f64::from);
        if !hint.weight().allow_light_points() {
            return bold.collect();
        }
        if step > 1 {
            return (lo..=hi).map(f64::from).collect();
        }
        let minor = move |d: f64| (2..10).map(move |k| d + f64::from(k).log10());
        bold.flat_map(minor).filter(|&v| v < self.hi).collect()
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.lo..self.hi
    }
}

#[cfg(test)]
mod tests {
    use super::{linear_range, tick_label, tick_label_spanning};

    #[test]
    fn neighbouring_ticks_of_a_narrow_axis_read_differently() {
        // The rolling disc's centre height: 0.0999967 to 0.100001 m, ticks 5e-7 apart.
        let span = 0.100_001 - 0.099_996_7;
        let ticks = [
            0.099_997,
            0.099_997_5,
            0.099_998,
            0.099_998_5,
            0.099_999,
            0.1,
        ];
        let labels: Vec<String> = ticks
            .iter()
            .map(|&v| tick_label_spanning(v, span))
            .collect();
        assert_eq!(
            labels,
            [
                "0.099997",
                "0.0999975",
                "0.099998",
                "0.0999985",
                "0.099999",
                "0.1"
            ]
        );
        // A span of metres keeps the short labels.
        assert_eq!(tick_label(&0.125), "0.125");
        assert_eq!(tick_label_spanning(2.5, 10.0), "2.5");
    }

    #[test]
    fn round_off_around_a_constant_is_drawn_constant() {
        // Bricard's az1: 0 +- 1e-15 in a mechanism of metre size.
        let noise = [1e-15, -2e-15, 0.0, 1.5e-15];
        let (lo, hi) = linear_range(noise.iter(), 1.0);
        assert_eq!((lo, hi), (-0.1, 0.1));
        // Without a scale to compare with, the same values are the data: drawn at full height.
        let (lo, hi) = linear_range(noise.iter(), 0.0);
        assert!(hi - lo < 1e-14);
        // A constant away from zero keeps its value in the middle.
        let (lo, hi) = linear_range([2.0, 2.0 + 1e-13].iter(), 1.0);
        assert!((0.5 * (lo + hi) - 2.0).abs() < 1e-12 && hi - lo >= 0.4);
    }

    #[test]
    fn a_real_motion_fills_the_axis() {
        // 1e-9 m of motion is far above round-off at metre scale: drawn at full height.
        let ys = [0.0, 1e-9];
        let (lo, hi) = linear_range(ys.iter(), 1.0);
        assert!((hi - lo - 1.1e-9).abs() < 1e-18, "{lo} {hi}");
    }
}
