//! The no-std route: [`libm`] for the transcendental functions, and `powi` written out as the
//! square-and-multiply loop that std's `powi` runs (LLVM's `__powidf2`), so both give the
//! same bits.

/// sqrt x (libm; correctly rounded, as std's).
#[inline(always)]
pub fn sqrt(x: f64) -> f64 {
    libm::sqrt(x)
}

/// tan x (libm).
#[inline(always)]
pub fn tan(x: f64) -> f64 {
    libm::tan(x)
}

/// e^x (libm).
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    libm::exp(x)
}

/// ln x (libm).
#[inline(always)]
pub fn ln(x: f64) -> f64 {
    libm::log(x)
}

/// atan2(y, x) (libm).
#[inline(always)]
pub fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}

/// x^y (libm).
#[inline(always)]
pub fn powf(x: f64, y: f64) -> f64 {
    libm::pow(x, y)
}

/// (sin x, cos x) (libm's `sincos`).
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    libm::sincos(x)
}

/// x^k: r = prod of x^(2^i) over the set bits i of |k|, squaring as it goes; 1/r for k < 0.
#[inline(always)]
pub fn powi(x: f64, k: i32) -> f64 {
    let mut n = k.unsigned_abs();
    let (mut base, mut r) = (x, 1.0);
    loop {
        if n & 1 == 1 {
            r *= base;
        }
        n >>= 1;
        if n == 0 {
            break;
        }
        base *= base;
    }
    if k < 0 { 1.0 / r } else { r }
}
