//! Whether an undetermined motion is a singularity of the coordinates rather than a body
//! without inertia: a disc or a bicycle frame that falls flat, where the yaw and the spin
//! of `rot_z(psi) * rot_x(phi) * rot_y(th)` turn about one axis and their rates part only
//! in a direction that moves nothing.
//!
//! With Z a basis of the motions the constraints allow at q (the null space of Phi_q,
//! velocity rows included), the reduced mass Z^T M Z has a null direction there
//! ([`crate::Error::UndeterminedMotion`]). Its relative size, rho(q) = lambda_min /
//! lambda_max of Z^T M Z, tells the two causes apart: a body or coordinate without mass
//! has rho = 0 everywhere, while a coordinate singularity has it only at the singular
//! values, so a step of one coordinate away from q (+-0.05, in rad or m) restores it. The
//! coordinate whose step restores rho most, by a factor 100 at least and to 1e-6 at least,
//! is the one at its singular value (phi at +-pi/2 above). Where that coordinate and the
//! ones the null direction moves are angles of one body's declared rotation sequence
//! ([`crate::SystemInfo::orientations`]), the singularity is that sequence's: the axes of
//! the moving angles line up ([`crate::Error::CoordinateSingularity`]).
//!
//! Runs once, after a run stopped, so it allocates freely.

use nalgebra::{DMatrix, SymmetricEigen};

use crate::error::{Error, OrientationSingularity};
use crate::system::{BodyOrientation, Evaluation, System};

/// The step of each coordinate away from the stopping point.
const STEP: f64 = 0.05;
/// The factor by which a step must restore rho, and the least rho it must reach.
const RESTORED_BY: f64 = 100.0;
const RESTORED_TO: f64 = 1e-6;
/// Singular values of Phi_q at most this fraction of the largest count as zero.
const RANK: f64 = 1e-10;
/// A coordinate moves in the null direction when its share is at least this fraction of
/// the largest.
const SHARE: f64 = 0.1;

/// `e`, or [`Error::CoordinateSingularity`] when it is an undetermined motion that a
/// singularity of the coordinates causes (module docs).
pub(crate) fn explain(system: &dyn System, e: Error) -> Error {
    let Error::UndeterminedMotion { t, q, .. } = &e else {
        return e;
    };
    match find(system, *t, q) {
        Some(found) => found,
        None => e,
    }
}

/// The reduced mass at (t, q): rho (module docs) and the null direction in q, or `None`
/// where it cannot be formed (a non-finite entry, no allowed motion, no mass at all).
fn reduced(system: &dyn System, t: f64, q: &[f64]) -> Option<(f64, Vec<f64>)> {
    let info = system.info();
    let (n, m) = (info.n(), info.m());
    let mut e = Evaluation::zeros(n, m);
    system.evaluate(t, q, &vec![0.0; n], &mut e);
    if !e.mass.iter().chain(e.phi_q.iter()).all(|x| x.is_finite()) {
        return None;
    }
    // The left singular vectors of [Phi_q^T 0] (n x max(n, m)): all n of them, those of the
    // zero singular values spanning the null space of Phi_q.
    let mut a = DMatrix::zeros(n, n.max(m));
    a.view_mut((0, 0), (n, m)).copy_from(&e.phi_q.transpose());
    let svd = a.svd(true, false);
    let u = svd.u?;
    let largest = svd.singular_values.max();
    let free: Vec<usize> = (0..n)
        .filter(|&k| svd.singular_values[k] <= RANK * largest)
        .collect();
    if free.is_empty() {
        return None;
    }
    let z = DMatrix::from_fn(n, free.len(), |i, j| u[(i, free[j])]);
    let reduced = z.transpose() * &e.mass * &z;
    let eigen = SymmetricEigen::new((&reduced + reduced.transpose()) * 0.5);
    let top = eigen.eigenvalues.max();
    if top <= 0.0 {
        return None;
    }
    let low = eigen.eigenvalues.imin();
    let direction = &z * eigen.eigenvectors.column(low);
    Some((
        eigen.eigenvalues[low] / top,
        direction.iter().copied().collect(),
    ))
}

/// [`Error::CoordinateSingularity`] at (t, q) when one coordinate's step restores the
/// reduced mass (module docs).
fn find(system: &dyn System, t: f64, q: &[f64]) -> Option<Error> {
    let info = system.info();
    let (rho, direction) = reduced(system, t, q)?;
    if rho >= RESTORED_TO {
        return None;
    }
    let mut best: Option<(usize, f64)> = None;
    let mut shifted = q.to_vec();
    for k in 0..info.n() {
        for step in [STEP, -STEP] {
            shifted[k] = q[k] + step;
            if let Some((there, _)) = reduced(system, t, &shifted)
                && best.is_none_or(|(_, b)| there > b)
            {
                best = Some((k, there));
            }
        }
        shifted[k] = q[k];
    }
    let (k, restored) = best?;
    if restored < RESTORED_TO || restored < RESTORED_BY * rho.max(0.0) {
        return None;
    }
    let largest = direction.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let moving: Vec<usize> = (0..info.n())
        .filter(|&j| direction[j].abs() >= SHARE * largest)
        .collect();
    let orientation = info
        .orientations
        .iter()
        .filter_map(|b| sequence_singularity(b, k, &moving, &info.coordinates))
        // The body that explains most of the motion, and among those one whose first and
        // last factors are the two in line (its axis along the world's can be named).
        .min_by_key(|(unexplained, found)| (*unexplained, found.along.is_none()))
        .map(|(_, found)| Box::new(found));
    Some(Error::CoordinateSingularity {
        t,
        coordinate: info.coordinates[k].clone(),
        value: q[k],
        moving: moving
            .iter()
            .map(|&j| info.coordinates[j].clone())
            .collect(),
        orientation,
    })
}

/// The singularity of `body`'s sequence when coordinate `k` and at least one of the
/// `moving` coordinates are angles of it, with the count of moving coordinates it leaves
/// unexplained (the body that explains most is named).
fn sequence_singularity(
    body: &BodyOrientation,
    k: usize,
    moving: &[usize],
    names: &[String],
) -> Option<(usize, OrientationSingularity)> {
    let angle_of = |c: usize| body.factors.iter().position(|f| f.coordinate == Some(c));
    angle_of(k)?;
    let turning: Vec<usize> = moving.iter().filter_map(|&c| angle_of(c)).collect();
    let (&first, &last) = (turning.iter().min()?, turning.iter().max()?);
    if first == last {
        return None; // one angle alone: nothing in line with it
    }
    let axis = |f: usize| body.factors[f].axis.map_or("?", |a| ["x", "y", "z"][a]);
    let angle = |f: usize| {
        body.factors[f]
            .coordinate
            .map_or("..", |c| names[c].as_str())
    };
    let sequence: Vec<String> = (0..body.factors.len())
        .map(|f| match body.factors[f].axis {
            Some(_) => format!("rot_{}({})", axis(f), angle(f)),
            None => "R".to_string(),
        })
        .collect();
    // The first factor turns about a world axis and the last about a body axis: when the
    // two in line are those, the body's axis lies along the world's.
    let along = (first == 0 && last == body.factors.len() - 1).then(|| {
        format!(
            "its {} axis lies along the world {} axis",
            axis(last),
            axis(first)
        )
    });
    let found = OrientationSingularity {
        body: body.body.clone(),
        sequence: sequence.join(" "),
        in_line: [angle(first).to_string(), angle(last).to_string()],
        along,
    };
    Some((moving.len() - turning.len(), found))
}
