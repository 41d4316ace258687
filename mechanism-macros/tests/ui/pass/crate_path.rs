//! `crate = path,` names the runtime crate through a re-export.
mod reexport {
    pub use mechanism;
}

reexport::mechanism::mechanism! {
    crate = crate::reexport::mechanism,
    pub struct Free;
    parameters { m = 1.0; }
    coordinates { x = 0.0; }
    independent { x = 0.0; der(x) = 1.0; }
    kinetic = 1/2*m*der(x)^2;
    potential = 0;
}

fn main() {
    use reexport::mechanism::Mechanism;
    let q = reexport::mechanism::nalgebra::SVector::<f64, 1>::new(0.0);
    assert_eq!(Free::default().mass_matrix(&q)[(0, 0)], 1.0);
}
