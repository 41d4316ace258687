//! Van Khang's matrix calculus ((dA/dx)[i, j n + k] = d a_ij / d x_k) on random symbolic matrices:
//! the layout (dA/dx)[i, j n + k] = d a_ij/dx_k, Theorem 1 dA/dt = (dA/dx)(I_p kron x'),
//! Theorem 2 d(AB)/dx = (dA/dx)(B kron I_n) + A (dB/dx), each against a brute-force
//! definition (entrywise differentiation, and num-dual derivatives of the random trees).
//!
//! Tolerance 1e-9 relative (absolute below 1), values above 1e4 skipped: as in diff_props,
//! the two sides are one function evaluated by different operation orders.

use crate::common::{Ast, ast, build, close, eval_ast};
use mechanism_codegen::error::AlgebraError;
use mechanism_codegen::{
    Arena, Differentiator, Error, Id, Matrix, SymbolId, SymbolKind, eval_matrix,
};
use num_dual::Dual64;
use proptest::prelude::*;

const TOL: f64 = 1e-9;
const BIG: f64 = 1e4;

/// An arena with coordinates x, y, z (positions, linked to their rates).
struct Xyz {
    a: Arena,
    q: [Id; 3],
    qd: [Id; 3],
    sq: [SymbolId; 3],
}

fn xyz() -> Xyz {
    let mut a = Arena::new();
    let c = ["x", "y", "z"].map(|n| a.coordinate(n));
    let q = c.map(|c| c[0]);
    let qd = c.map(|c| c[1]);
    let sq = q.map(|i| a.as_symbol(i).unwrap());
    Xyz { a, q, qd, sq }
}

fn matrix(t: &mut Xyz, rows: usize, cols: usize, entries: &[Ast]) -> Option<Matrix> {
    let data: Option<Vec<Id>> = entries.iter().map(|e| build(&mut t.a, e, &t.q)).collect();
    Some(Matrix::new(rows, cols, data?).unwrap())
}

/// Values of a matrix at q = p, q' = v.
fn values(t: &Xyz, m: &Matrix, p: &[f64; 3], v: &[f64; 3]) -> Option<Vec<f64>> {
    let table: Vec<(SymbolId, f64)> = (0..3)
        .flat_map(|k| [(t.sq[k], p[k]), (t.a.as_symbol(t.qd[k]).unwrap(), v[k])])
        .collect();
    let vals = eval_matrix(&t.a, m, &|s| table.iter().find(|e| e.0 == s).map(|e| e.1)).ok()?;
    vals.iter().all(|x| x.is_finite()).then_some(vals)
}

fn dims() -> impl Strategy<Value = (usize, usize, usize, Vec<Ast>, Vec<Ast>)> {
    (1usize..=3, 1usize..=3, 1usize..=2).prop_flat_map(|(m, p, r)| {
        (
            Just(m),
            Just(p),
            Just(r),
            prop::collection::vec(ast(), m * p),
            prop::collection::vec(ast(), p * r),
        )
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    /// Theorem 1: (dA/dx)(I_p kron x') is, entry by entry, the total time derivative of a_ij
    /// (the same canonical node), and equals the num-dual derivative along x(t) = p + v t.
    #[test]
    fn theorem_1((m, p, _r, ea, _eb) in dims(), pt in prop::array::uniform3(-1.5f64..1.5), v in prop::array::uniform3(-1.5f64..1.5)) {
        let mut t = xyz();
        let Some(a) = matrix(&mut t, m, p, &ea) else { return Ok(()) };
        let mut d = Differentiator::new();
        let da = a.time_derivative(&mut t.a, &mut d, &t.sq).unwrap();
        prop_assert_eq!((da.rows(), da.cols()), (m, p));
        for (k, &e) in a.data().iter().enumerate() {
            let td = d.time_derivative(&mut t.a, e).unwrap();
            prop_assert_eq!(da.data()[k], td, "entry {}", k);
        }
        let oracle: Vec<Dual64> = ea.iter().map(|e| eval_ast(e, &[0, 1, 2].map(|k| Dual64::new(pt[k], v[k])))).collect();
        prop_assume!(oracle.iter().all(|o| o.re.is_finite() && o.eps.is_finite() && o.eps.abs() < BIG && o.re.abs() < BIG));
        let ours = values(&t, &da, &pt, &v).expect("finite where the oracle is");
        for (x, o) in ours.iter().zip(&oracle) {
            prop_assert!(close(*x, o.eps, TOL), "{x} vs {}", o.eps);
        }
    }

    /// Theorem 2: d(AB)/dx = (dA/dx)(B kron I_n) + A (dB/dx), and both equal the brute-force
    /// matrix derivative (num-dual d/dx_k of sum_l a_il b_lj placed at column j n + k).
    #[test]
    fn theorem_2((m, p, r, ea, eb) in dims(), pt in prop::array::uniform3(-1.5f64..1.5)) {
        let mut t = xyz();
        let (Some(a), Some(b)) = (matrix(&mut t, m, p, &ea), matrix(&mut t, p, r, &eb)) else { return Ok(()) };
        let mut d = Differentiator::new();
        let n = 3;
        let ab = a.mul(&mut t.a, &b).unwrap();
        let lhs = ab.khang_derivative(&mut t.a, &mut d, &t.sq).unwrap();
        let da = a.khang_derivative(&mut t.a, &mut d, &t.sq).unwrap();
        let db = b.khang_derivative(&mut t.a, &mut d, &t.sq).unwrap();
        let id = Matrix::identity(&mut t.a, n);
        let b_kron_i = b.kron(&mut t.a, &id).unwrap();
        let first = da.mul(&mut t.a, &b_kron_i).unwrap();
        let second = a.mul(&mut t.a, &db).unwrap();
        let rhs = first.add(&mut t.a, &second).unwrap();
        prop_assert_eq!((lhs.rows(), lhs.cols()), (m, r * n));
        prop_assert_eq!((rhs.rows(), rhs.cols()), (m, r * n));
        // brute force
        let mut brute = vec![0.0; m * r * n];
        for i in 0..m {
            for j in 0..r {
                for k in 0..n {
                    let mut x = pt.map(Dual64::from_re);
                    x[k].eps = 1.0;
                    let s: Dual64 = (0..p).map(|l| eval_ast(&ea[i * p + l], &x) * eval_ast(&eb[l * r + j], &x)).sum();
                    prop_assume!(s.re.is_finite() && s.eps.is_finite() && s.eps.abs() < BIG && s.re.abs() < BIG);
                    brute[i * r * n + j * n + k] = s.eps;
                }
            }
        }
        let zero = [0.0; 3];
        let l = values(&t, &lhs, &pt, &zero).expect("finite");
        let rv = values(&t, &rhs, &pt, &zero).expect("finite");
        for k in 0..brute.len() {
            prop_assert!(close(l[k], brute[k], TOL), "d(AB)/dx[{k}] {} vs {}", l[k], brute[k]);
            prop_assert!(close(rv[k], brute[k], TOL), "Theorem 2 rhs[{k}] {} vs {}", rv[k], brute[k]);
        }
    }

    /// The mixed-product property (A kron B)(C kron D) = (AC) kron (BD), numerically.
    #[test]
    fn kron_mixed_product(ea in prop::collection::vec(ast(), 4), eb in prop::collection::vec(ast(), 2), ec in prop::collection::vec(ast(), 2), ed in prop::collection::vec(ast(), 2), pt in prop::array::uniform3(-1.5f64..1.5)) {
        let mut t = xyz();
        // A 2x2, B 1x2, C 2x1, D 2x1
        let (Some(a), Some(b), Some(c), Some(dm)) = (matrix(&mut t, 2, 2, &ea), matrix(&mut t, 1, 2, &eb), matrix(&mut t, 2, 1, &ec), matrix(&mut t, 2, 1, &ed)) else { return Ok(()) };
        let ab = a.kron(&mut t.a, &b).unwrap();
        let cd = c.kron(&mut t.a, &dm).unwrap();
        prop_assert_eq!((ab.rows(), ab.cols(), cd.rows(), cd.cols()), (2, 4, 4, 1));
        let lhs = ab.mul(&mut t.a, &cd).unwrap();
        let ac = a.mul(&mut t.a, &c).unwrap();
        let bd = b.mul(&mut t.a, &dm).unwrap();
        let rhs = ac.kron(&mut t.a, &bd).unwrap();
        let zero = [0.0; 3];
        let (Some(l), Some(r)) = (values(&t, &lhs, &pt, &zero), values(&t, &rhs, &pt, &zero)) else { return Ok(()) };
        prop_assume!(l.iter().chain(&r).all(|x| x.abs() < BIG));
        for k in 0..l.len() {
            prop_assert!(close(l[k], r[k], TOL), "{} vs {}", l[k], r[k]);
        }
        // Transposition distributes over kron entry by entry (same canonical products).
        prop_assert_eq!(ab.transpose().unwrap(), a.transpose().unwrap().kron(&mut t.a, &b.transpose().unwrap()).unwrap());
    }
}

/// The layout, pinned: A = [[x y, sin x], [y^2, 1]] over (x, y, z) gives
/// dA/dx = [[y, x, 0, cos x, 0, 0], [0, 2 y, 0, 0, 0, 0]].
#[test]
fn layout_is_pinned() {
    let mut t = xyz();
    let [x, y, _] = t.q;
    let a = &mut t.a;
    let xy = a.mul2(x, y);
    let sx = a.sin(x);
    let y2 = a.powi(y, 2).unwrap();
    let one = a.int(1);
    let m = Matrix::new(2, 2, vec![xy, sx, y2, one]).unwrap();
    let dm = m
        .khang_derivative(a, &mut Differentiator::new(), &t.sq)
        .unwrap();
    let (zero, two) = (a.int(0), a.int(2));
    let cx = a.cos(x);
    let two_y = a.mul2(two, y);
    assert_eq!((dm.rows(), dm.cols()), (2, 6));
    assert_eq!(
        dm.data(),
        vec![
            y, x, zero, cx, zero, zero, zero, two_y, zero, zero, zero, zero
        ]
    );
    // (I_2 kron x') places x' in block column j: rows j n + k, column j.
    let qd = Matrix::column(t.qd.to_vec());
    let k = Matrix::identity(a, 2).kron(a, &qd).unwrap();
    assert_eq!((k.rows(), k.cols()), (6, 2));
    for row in 0..6 {
        for col in 0..2 {
            let want = if row / 3 == col { t.qd[row % 3] } else { zero };
            assert_eq!(k.get(row, col), want);
        }
    }
}

/// Theorem 1 with an explicit time dependence: d/dt [t x] = x + t x'.
#[test]
fn theorem_1_adds_the_explicit_time_derivative() {
    let mut t = xyz();
    let time = t.a.symbol("t", SymbolKind::Time);
    let tx = t.a.mul2(time, t.q[0]);
    let m = Matrix::column(vec![tx]);
    let dm = m
        .time_derivative(&mut t.a, &mut Differentiator::new(), &t.sq)
        .unwrap();
    let txd = t.a.mul2(time, t.qd[0]);
    assert_eq!(dm.data(), vec![t.a.add2(t.q[0], txd)]);
}

#[test]
fn shape_errors_are_typed() {
    let mut t = xyz();
    let a = &mut t.a;
    let m23 = Matrix::zeros(a, 2, 3);
    let m22 = Matrix::zeros(a, 2, 2);
    assert!(matches!(
        m23.mul(a, &m22),
        Err(Error::Algebra(AlgebraError::Shape {
            operation: "mul",
            ..
        }))
    ));
    assert!(matches!(
        m23.add(a, &m22),
        Err(Error::Algebra(AlgebraError::Shape {
            operation: "add",
            ..
        }))
    ));
    assert!(matches!(
        m23.sub(a, &m22),
        Err(Error::Algebra(AlgebraError::Shape { .. }))
    ));
    // A matrix whose entries do not fill rows x cols cannot be built.
    assert!(matches!(
        Matrix::new(3, 3, vec![t.q[0]]),
        Err(Error::Algebra(AlgebraError::MalformedMatrix { .. }))
    ));
    let foreign = Matrix::new(1, 1, vec![Id::new(1 << 30)]).unwrap();
    assert!(matches!(
        foreign.add(a, &foreign),
        Err(Error::Algebra(AlgebraError::InvalidId { .. }))
    ));
    assert!(foreign.scale(a, t.q[0]).is_err());
    let qd = Matrix::column(vec![t.qd[0]]);
    // q' has a rate q'' but q'' has none: Theorem 1 over x = (q'') is an error, not a panic.
    let qdd = a
        .as_symbol(a.lookup("der2(x)").map(|s| a.symbol_node(s)).unwrap())
        .unwrap();
    assert!(
        qd.time_derivative(a, &mut Differentiator::new(), &[qdd])
            .is_err()
    );
}
