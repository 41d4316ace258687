//! The std route: the f64 methods of the platform's math library.

#[inline(always)]
pub(crate) fn sqrt(x: f64) -> f64 {
    x.sqrt()
}

#[inline(always)]
pub(crate) fn tan(x: f64) -> f64 {
    x.tan()
}

#[inline(always)]
pub(crate) fn exp(x: f64) -> f64 {
    x.exp()
}

#[inline(always)]
pub(crate) fn ln(x: f64) -> f64 {
    x.ln()
}

#[inline(always)]
pub(crate) fn atan2(y: f64, x: f64) -> f64 {
    y.atan2(x)
}

#[inline(always)]
pub(crate) fn powf(x: f64, y: f64) -> f64 {
    x.powf(y)
}

#[inline(always)]
pub(crate) fn powi(x: f64, k: i32) -> f64 {
    x.powi(k)
}

#[inline(always)]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    x.sin_cos()
}
