//! Bounds on an expression's degree as a polynomial in the rates q', read off the graph in
//! one pass: the cheap proof that a kinetic energy is the quadratic form 1/2 q'^T M(q) q'.
//!
//! A node's bounds [lo, hi] hold every monomial of its expansion in the rates:
//! - a rate is [1, 1]; a constant, a coordinate, a parameter or time is [0, 0];
//! - a product adds its factors' bounds, a sum takes the smallest lo and the largest hi;
//! - a power with a constant non-negative integer exponent k multiplies them by k;
//! - a function, an atan2 or any other power of something free of the rates is [0, 0].
//!
//! Cancellation only removes monomials, so the true degrees lie within the bounds. Anything
//! else that involves a rate (sin q', |q'|, 1/q', q'^(1/2)) is not a polynomial in the
//! rates and has no bounds.

use crate::algebra::expr::{Arena, Id, Node};

/// The degree bounds of one node, or `None` for a non-polynomial in the rates.
type Bounds = Option<(u32, u32)>;

/// True when every monomial of `root` in the rates has degree exactly 2 (bounds [2, 2]):
/// `root` is then a homogeneous quadratic in q', 1/2 q'^T H q' with H its Hessian (free of
/// q'), and it and its gradient vanish at q' = 0. False says only that the bounds do not
/// prove it (a q'-free part that cancels, for one); `is_rate[s]` marks the rates by
/// symbol index. The pass reads each node up to `root` once (children precede parents).
pub(crate) fn is_homogeneous_quadratic(arena: &Arena, root: Id, is_rate: &[bool]) -> bool {
    let mut bounds: Vec<Bounds> = Vec::with_capacity(root.index() + 1);
    for node in &arena.nodes()[..=root.index()] {
        let of = |c: &Id| bounds[c.index()];
        let b = match node {
            Node::Num(_) | Node::Pi => Some((0, 0)),
            Node::Sym(s) => {
                let d = u32::from(is_rate.get(s.index()).copied().unwrap_or(false));
                Some((d, d))
            }
            Node::Mul(fs) => fs.iter().map(of).try_fold((0u32, 0u32), |acc, f| {
                let (lo, hi) = f?;
                Some((acc.0.saturating_add(lo), acc.1.saturating_add(hi)))
            }),
            Node::Add(ts) => ts.iter().map(of).try_fold((u32::MAX, 0u32), |acc, t| {
                let (lo, hi) = t?;
                Some((acc.0.min(lo), acc.1.max(hi)))
            }),
            Node::Pow(base, exponent) => match (of(base), of(exponent)) {
                (Some((0, 0)), Some((0, 0))) => Some((0, 0)),
                (Some((lo, hi)), _) => arena
                    .as_number(*exponent)
                    .and_then(|k| k.as_integer())
                    .and_then(|k| u32::try_from(k).ok())
                    .map(|k| (lo.saturating_mul(k), hi.saturating_mul(k))),
                (None, _) => None,
            },
            Node::Func(_, a) => of(a).filter(|&d| d == (0, 0)),
            Node::Named(a) => of(a),
            Node::Atan2(y, x) => match (of(y), of(x)) {
                (Some((0, 0)), Some((0, 0))) => Some((0, 0)),
                _ => None,
            },
        };
        bounds.push(b);
    }
    bounds[root.index()] == Some((2, 2))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An arena with a coordinate q, its rate and a second rate; the rate marks.
    fn setup() -> (Arena, Id, Id, Id, Vec<bool>) {
        let mut a = Arena::new();
        let [q, v, _] = a.coordinate("q");
        let [_, w, _] = a.coordinate("r");
        let mut is_rate = vec![false; a.symbols().len()];
        for id in [v, w] {
            is_rate[a.as_symbol(id).unwrap().index()] = true;
        }
        (a, q, v, w, is_rate)
    }

    /// Quadratic forms with coefficients in q are proven; a constant, a linear or a
    /// cubic term, a rate inside a function, a negative or a fractional power are not.
    #[test]
    fn proves_exactly_the_homogeneous_quadratics() {
        let (mut a, q, v, w, is_rate) = setup();
        let c = a.cos(q);
        let two = a.int(2);
        let vv = a.pow(v, two).unwrap();
        let cvw = a.mul(&[c, v, w]);
        let form = a.add(&[vv, cvw]);
        let sum = a.add2(v, w);
        let square = a.pow(sum, two).unwrap();
        let scaled = a.mul(&[c, square]);
        let proven = [form, scaled];
        let one = a.int(1);
        let three = a.int(3);
        let half = a.rational(1, 2).unwrap();
        let minus_two = a.int(-2);
        let with_constant = a.add2(form, one);
        let with_linear = a.add2(form, v);
        let cubic = a.pow(v, three).unwrap();
        let with_cubic = a.add2(form, cubic);
        let sin_v = a.sin(v);
        let in_function = a.mul(&[sin_v, v]);
        let root = a.pow(vv, half).unwrap();
        let inverse = a.pow(v, minus_two).unwrap();
        let negative = a.mul(&[inverse, w, w, w, w]);
        let free = a.pow(c, two).unwrap();
        for id in proven {
            assert!(is_homogeneous_quadratic(&a, id, &is_rate), "{id:?}");
        }
        let refused = [
            with_constant,
            with_linear,
            with_cubic,
            in_function,
            root,
            negative,
            free,
        ];
        for id in refused {
            assert!(!is_homogeneous_quadratic(&a, id, &is_rate), "{id:?}");
        }
    }
}
