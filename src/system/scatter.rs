//! Where the interpreter's evaluation puts each output of its tape: the structural nonzeros
//! of M and Phi_q ([`Sparsity`]) and every entry of the vectors, read straight from the
//! tape's register file into an [`Evaluation`]. The tape of a large mechanism has n^2 + m n
//! matrix outputs of which a few per row are nonzero (A02 with N = 80: 52,000 outputs,
//! about 1,100 nonzeros); this copies only those, and never touches the structural zeros.

use mechanism_codegen::EvaluationOutput;

use crate::system::Evaluation;
use crate::system::routine::Routine;
use crate::system::sparsity::Sparsity;

/// The register slots of an evaluation tape's outputs and their places in an
/// [`Evaluation`].
#[derive(Clone, Debug)]
pub(crate) struct EvaluationScatter {
    /// (register slot, column-major index) of each structural nonzero of M.
    mass: Vec<(usize, usize)>,
    /// The same for Phi_q.
    phi_q: Vec<(usize, usize)>,
    /// The register slots of C q', g, tau, Phi, Phi_t, gamma (each entry), T and Pi, in
    /// this order.
    vectors: Vec<usize>,
}

/// (register slot, column-major index) of each entry of `pattern` in the output matrix of
/// `rows` x `cols` that starts at output entry `base` of `routine`; `None` when the routine
/// has fewer outputs.
pub(crate) fn matrix_scatter(
    routine: &Routine,
    base: usize,
    (rows, cols): (usize, usize),
    pattern: &[(usize, usize)],
) -> Option<Vec<(usize, usize)>> {
    pattern
        .iter()
        .map(|&(i, j)| Some((routine.output_slot(base + i * cols + j)?, i + j * rows)))
        .collect()
}

/// Writes the entries `scatter` lists from `registers` into the column-major `out`.
pub(crate) fn write_matrix(scatter: &[(usize, usize)], registers: &[f64], out: &mut [f64]) {
    for &(slot, k) in scatter {
        out[k] = registers[slot];
    }
}

impl EvaluationScatter {
    /// The scatter of `routine`, the [`mechanism_codegen::Role::Evaluation`] tape of a
    /// system with n coordinates and m rows whose outputs have the pattern `sparsity`;
    /// `None` when the tape has fewer outputs than these sizes need.
    pub(crate) fn new(routine: &Routine, sparsity: &Sparsity) -> Option<Self> {
        let (n, m) = (sparsity.n, sparsity.m);
        let mut base = 0;
        let mut out = Self {
            mass: Vec::new(),
            phi_q: Vec::new(),
            vectors: Vec::new(),
        };
        for o in EvaluationOutput::ORDER {
            let (rows, cols) = o.shape(n, m);
            let slot = |k: usize| routine.output_slot(base + k);
            match o {
                EvaluationOutput::Mass => {
                    out.mass = matrix_scatter(routine, base, (rows, cols), &sparsity.mass)?;
                }
                EvaluationOutput::PhiQ => {
                    out.phi_q = matrix_scatter(routine, base, (rows, cols), &sparsity.jacobian)?;
                }
                _ => {
                    for k in 0..rows * cols {
                        out.vectors.push(slot(k)?);
                    }
                }
            }
            base += rows * cols;
        }
        Some(out)
    }

    /// Writes the outputs held in `registers` (after the tape ran) into `out`: M and Phi_q
    /// at their pattern only, every entry of the rest.
    pub(crate) fn write(&self, registers: &[f64], out: &mut Evaluation) {
        self.write_from(|slot| registers[slot], out);
    }

    /// The same places read from the lane register file of `routine`
    /// ([`Routine::lane_slot`]); `None` when a slot has no lane slot.
    pub(crate) fn for_lanes(&self, routine: &Routine) -> Option<Self> {
        let map = |v: &[(usize, usize)]| {
            v.iter()
                .map(|&(s, k)| Some((routine.lane_slot(s)?, k)))
                .collect::<Option<Vec<_>>>()
        };
        Some(Self {
            mass: map(&self.mass)?,
            phi_q: map(&self.phi_q)?,
            vectors: self
                .vectors
                .iter()
                .map(|&s| routine.lane_slot(s))
                .collect::<Option<_>>()?,
        })
    }

    /// [`EvaluationScatter::write`] from lane `lane` of a lane register file, through a
    /// scatter made by [`EvaluationScatter::for_lanes`]
    /// ([`crate::system::routine::Routine::execute_rows`]).
    pub(crate) fn write_lane<const L: usize>(
        &self,
        registers: &[[f64; L]],
        lane: usize,
        out: &mut Evaluation,
    ) {
        self.write_from(|slot| registers[slot][lane], out);
    }

    /// Writes the value `value(slot)` of each output's slot into its place in `out`.
    #[inline(always)]
    fn write_from(&self, value: impl Fn(usize) -> f64, out: &mut Evaluation) {
        let (mass, phi_q) = (out.mass.as_mut_slice(), out.phi_q.as_mut_slice());
        for &(slot, k) in &self.mass {
            mass[k] = value(slot);
        }
        for &(slot, k) in &self.phi_q {
            phi_q[k] = value(slot);
        }
        let mut slots = self.vectors.iter().map(|&s| value(s));
        for v in [
            &mut out.coriolis,
            &mut out.gravity,
            &mut out.forces,
            &mut out.phi,
            &mut out.phi_t,
            &mut out.gamma,
        ] {
            for (o, x) in v.iter_mut().zip(&mut slots) {
                *o = x;
            }
        }
        out.kinetic = slots.next().unwrap_or(f64::NAN);
        out.potential = slots.next().unwrap_or(f64::NAN);
    }
}
