//! Uses one compiled chain (feature `chain16` or `chain32`) or none, so that a timed build
//! shows the macro's cost: derivation inside the proc-macro plus rustc on the emitted code.
//! Every method of the `Mechanism` impl is called (through `black_box`), so that the emitted
//! code is not only type-checked but also code-generated, as in a real user's binary.

use std::hint::black_box;

use mechanism::Mechanism;
use mechanism::nalgebra::SVector;

#[cfg(feature = "chain16")]
mechanism::mechanism!(file = "../mechanisms/closed_chain_16.mech");
#[cfg(feature = "chain32")]
mechanism::mechanism!(file = "../mechanisms/closed_chain_32.mech");

/// Calls every generated method once.
#[allow(dead_code)]
fn touch<T: Mechanism<N, M>, const N: usize, const M: usize>(m: &T) -> f64 {
    let q = black_box(SVector::<f64, N>::from_element(0.1));
    let qd = black_box(SVector::<f64, N>::from_element(0.2));
    let t = black_box(0.3);
    let e = m.evaluate(t, &q, &qd);
    m.mass_matrix(&q).sum()
        + m.coriolis_matrix(&q, &qd).sum()
        + m.coriolis_forces(&q, &qd).sum()
        + m.gravity(&q).sum()
        + m.generalized_forces(t, &q, &qd).sum()
        + m.constraints(t, &q).sum()
        + m.constraint_jacobian(t, &q).sum()
        + m.constraint_time_derivative(t, &q).sum()
        + m.constraint_gamma(t, &q, &qd).sum()
        + m.kinetic_energy(&q, &qd)
        + m.potential_energy(&q)
        + e.mass.sum()
        + T::equations().len() as f64
}

fn main() {
    #[cfg(feature = "chain16")]
    println!("{}", touch(black_box(&ClosedChain16::default())));
    #[cfg(feature = "chain32")]
    println!("{}", touch(black_box(&ClosedChain32::default())));
    println!("{}", black_box(1));
}
