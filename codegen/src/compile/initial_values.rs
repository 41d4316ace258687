//! The outputs of [`Role::InitialValues`](crate::Role::InitialValues): the declared initial
//! values as expressions in the parameters, so that both back ends evaluate them at the
//! parameter values of the moment rather than at the defaults.

use crate::algebra::matrix::Matrix;
use crate::mechanics::model::Model;

/// Two columns: the initial guesses of the n coordinates, then the position and the rate of
/// each independent coordinate in turn (a rate not declared is 0).
pub(crate) fn outputs(model: &mut Model) -> [Matrix; 2] {
    let guesses = model.coordinates.iter().map(|c| c.guess_expr).collect();
    let zero = model.arena.int(0);
    let independent = model
        .independent
        .iter()
        .flat_map(|i| [i.position_expr, i.velocity_expr.unwrap_or(zero)])
        .collect();
    [Matrix::column(guesses), Matrix::column(independent)]
}
