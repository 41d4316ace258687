//! The math functions: the inline `sin_cos` against a double-double reference and the
//! platform's libm, and the no-std route against the std one.

mod routes;
mod sin_cos;
mod ulps;
