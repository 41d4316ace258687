//! A crate that forbids unsafe code can still declare a mechanism: the emitted call into
//! the AVX2 copy of `evaluate_into` (an `unsafe` block, in x86-64 builds without AVX2) comes
//! from the macro, which the `unsafe_code` lint does not hold against the user's crate.
#![forbid(unsafe_code)]
use mechanism::prelude::*;

mechanism!(file = "../../../../mechanisms/planar_four_bar.mech");

fn main() {
    let m = PlanarFourBar::default();
    let q = SVector::<f64, 3>::new(0.4, 1.1, 2.0);
    let qd = SVector::<f64, 3>::new(1.0, -0.5, 0.25);
    let mut out = StaticEvaluation::<3, 2>::zeros();
    m.evaluate_into(0.0, &q, &qd, &mut out);
    let mass = m.mass_matrix(&q);
    // Two programs (the combined one and the mass matrix's own) of the same expressions:
    // equal up to rounding.
    assert!((out.mass - mass).abs().max() <= 1e-12 * mass.abs().max());
}
