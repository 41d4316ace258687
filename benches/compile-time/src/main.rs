//! Uses one compiled chain (feature `chain16` or `chain32`) or none, so that a timed build
//! shows the macro's cost: derivation inside the proc-macro plus rustc on the emitted code.

use std::hint::black_box;

#[cfg(feature = "chain16")]
mechanism::mechanism!(file = "../mechanisms/closed_chain_16.mech");
#[cfg(feature = "chain32")]
mechanism::mechanism!(file = "../mechanisms/closed_chain_32.mech");

fn main() {
    #[cfg(feature = "chain16")]
    {
        let s = mechanism::Compiled::new(ClosedChain16::default());
        println!("{}", mechanism::System::info(black_box(&s)).n());
    }
    #[cfg(feature = "chain32")]
    {
        let s = mechanism::Compiled::new(ClosedChain32::default());
        println!("{}", mechanism::System::info(black_box(&s)).n());
    }
    println!("{}", black_box(1));
}
