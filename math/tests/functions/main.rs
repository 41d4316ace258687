//! The math functions: the inline `sin_cos` against a double-double reference and the
//! platform's libm, `sin_cos_lanes` against `sin_cos`, and the no-std route against the std
//! one.

mod lanes;
mod routes;
mod sin_cos;
mod ulps;
