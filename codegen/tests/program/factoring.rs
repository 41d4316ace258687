//! The factoring of sums at the scale where it matters: a closed chain's C q'.

use mechanism_codegen::fixtures::closed_chain_model;
use mechanism_codegen::{Program, derive};

/// Row i of the N-bar chain's C q' is sum_j qd_j^2 w_ij (sin th_i cos th_j - cos th_i sin th_j).
/// Multiplied out pair by pair it costs about 5 N^2 operations (288 at N = 8, 1216 at 16,
/// 4992 at 32 before the factoring); with sin th_i and cos th_i taken out of each row it is
/// two sums of N - 1 multiply-adds per row over products cos th_j qd_j^2 shared by every
/// row, about 3 N^2. The bound 4 N^2 separates the two.
#[test]
fn a_chain_coriolis_program_costs_under_four_n_squared() {
    for n in [8, 16] {
        let mut model = closed_chain_model(n);
        let eqs = derive(&mut model).expect("derived");
        let p = Program::new(&model.arena, &[&eqs.coriolis_forces]).expect("program");
        let ops = p.op_counts().total();
        assert!(ops < 4 * n * n, "N = {n}: {ops} operations");
    }
}
