//! Each thread's evaluation buffers and dynamics workspace, shared by the one-state
//! methods (`methods.rs`) and the batch rows (`rows.rs`).

use std::cell::RefCell;

use mechanism::{Dynamics, Evaluation, Kinematic};

use crate::model::Model;

thread_local! {
    /// Per thread: the evaluation buffers and the dynamics workspace of the model last used
    /// (by its id), reused from state to state of a batch. A system writes M and Phi_q at
    /// its own pattern only, so the buffers are never shared between models.
    static SCRATCH: RefCell<Option<(u64, Evaluation, Dynamics)>> = const { RefCell::new(None) };
}

/// Runs `f` with this thread's evaluation buffers and dynamics workspace for `model`.
pub(crate) fn with_scratch<R>(
    model: &Model,
    f: impl FnOnce(&mut Evaluation, &mut Dynamics) -> R,
) -> R {
    SCRATCH.with(|cell| {
        let mut slot = cell.borrow_mut();
        let info = model.system.info();
        if slot.as_ref().is_none_or(|(id, _, _)| *id != model.id) {
            *slot = Some((
                model.id,
                Evaluation::zeros(info.n(), info.m()),
                Dynamics::new(info),
            ));
        }
        let (_, e, d) = slot.as_mut().expect("filled above");
        f(e, d)
    })
}
