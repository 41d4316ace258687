//! Rolling without slipping of a thin (knife-edge) wheel on the ground plane z = 0: the
//! `rolling(B, a, r)` statement of `joints`.
//!
//! With c the centre of body B (its declared position), a its wheel axis in world
//! components and r the radius, the lowest point of the rim is the contact point
//!
//! ```text
//! p = c + r d,   d = -u / |u|,   u = e_z - (e_z . a) a / (a . a)
//! ```
//!
//! (u is e_z with its component along the axis removed, so d points from the centre to the
//! ground within the wheel plane). Rolling means:
//!
//! - the contact height is zero, p_z = c_z - r |u| = 0: one position row, holonomic;
//! - the material point of B at p does not slide, v_p = c' + w x (p - c) with zero x and y
//!   components: two velocity rows, linear in q' and not integrable (nonholonomic). w is
//!   B's angular velocity in world axes, R (J_w q' + w_t) from [`Orientation::angular_jacobian`].
//!
//! The contact is undefined for a vertical axis (u = 0, the wheel lying flat), which the
//! builder refuses at the initial guesses.

use crate::algebra::diff::Differentiator;
use crate::algebra::eval::eval;
use crate::algebra::expr::{Arena, Id, SymbolId, Vec3};
use crate::algebra::matrix::Matrix;
use crate::algebra::rotation::Orientation;
use crate::error::Result;
use crate::mechanics::bodies::dot;
use crate::mechanics::joints::cross;

/// The rows of one rolling wheel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct RollingRows {
    /// p_z = c_z - r |u| (position level).
    pub(crate) height: Id,
    /// The x and y components of the contact point's material velocity (linear in q').
    pub(crate) slip: [Id; 2],
    /// |u|^2 = 1 - a_z^2 / (a . a), zero for a vertical axis.
    pub(crate) tilt_squared: Id,
}

/// The body and ground data of one wheel.
pub(crate) struct Wheel<'a> {
    /// The centre c (world).
    pub(crate) centre: &'a Vec3,
    /// B's orientation (body to world).
    pub(crate) orientation: &'a Orientation,
    /// The axis a (world).
    pub(crate) axis: &'a Vec3,
    /// The radius r.
    pub(crate) radius: Id,
}

/// The rows of `wheel` (module docs), with q the coordinate symbols and `time` the time
/// symbol, if any.
///
/// # Errors
/// Differentiation and shape errors.
pub(crate) fn rolling_rows(
    arena: &mut Arena,
    wheel: &Wheel<'_>,
    q: &[SymbolId],
    time: Option<SymbolId>,
) -> Result<RollingRows> {
    let a = wheel.axis;
    let aa = dot(arena, a, a);
    let inv_aa = {
        let minus_one = arena.int(-1);
        arena.pow(aa, minus_one)?
    };
    let one = arena.int(1);
    // u = e_z - (a_z / a.a) a.
    let along = arena.mul2(a[2], inv_aa);
    let mut u = [0, 1, 2].map(|i| {
        let t = arena.mul2(along, a[i]);
        arena.neg(t)
    });
    u[2] = arena.add2(one, u[2]);
    let tilt_squared = {
        let az2 = arena.mul2(a[2], a[2]);
        let f = arena.mul2(az2, inv_aa);
        arena.sub(one, f)
    };
    let norm = arena.sqrt(tilt_squared)?;
    let r = wheel.radius;
    let rn = arena.mul2(r, norm);
    let height = arena.sub(wheel.centre[2], rn);
    // r d = -r u / |u|.
    let minus_one = arena.int(-1);
    let inv_norm = arena.pow(norm, minus_one)?;
    let scale = {
        let s = arena.mul2(r, inv_norm);
        arena.neg(s)
    };
    let rd = u.map(|ui| arena.mul2(scale, ui));
    // w (world) = R (J_w q' + w_t).
    let mut d = Differentiator::new();
    let (jw, wt) = wheel.orientation.angular_jacobian(arena, &mut d, q, time)?;
    let mut body_w = [arena.int(0); 3];
    for (i, w) in body_w.iter_mut().enumerate() {
        let mut terms = vec![wt[i]];
        for (k, &s) in q.iter().enumerate() {
            let Some(rate) = arena.symbol_info(s).derivative else {
                continue;
            };
            let rate = arena.symbol_node(rate);
            terms.push(arena.mul2(jw.get(i, k), rate));
        }
        *w = arena.add(&terms);
    }
    let rotation = wheel.orientation.matrix(arena)?;
    let w = rotation.mul(arena, &Matrix::column(body_w.to_vec()))?;
    let w = [w.data[0], w.data[1], w.data[2]];
    let spin = cross(arena, &w, &rd);
    let mut slip = [arena.int(0); 2];
    for (i, s) in slip.iter_mut().enumerate() {
        let vc = d.time_derivative(arena, wheel.centre[i])?;
        *s = arena.add2(vc, spin[i]);
    }
    Ok(RollingRows {
        height,
        slip,
        tilt_squared,
    })
}

/// |u|^2 of `rows` at the symbol values `values` (missing symbols make it `None`).
pub(crate) fn tilt_squared_at(
    arena: &Arena,
    rows: &RollingRows,
    values: &[(SymbolId, f64)],
) -> Option<f64> {
    let env = |s: SymbolId| values.iter().find(|k| k.0 == s).map(|k| k.1);
    eval(arena, rows.tilt_squared, &env).ok()
}
