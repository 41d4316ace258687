//! The LU kernels behind [`super::Lu`], on column-major slices (a[i + j n] = A_ij).
//!
//! Each kernel takes a const `K`: with K > 0 the order is the constant K and the compiler
//! unrolls the loops and drops the bounds checks (the KKT systems of real mechanisms are
//! 2 x 2 to 20 x 20 and are solved once per right-hand side, so the loop overhead of a
//! run-time order is most of the cost); K = 0 means "use the run-time order n". One
//! algorithm, monomorphised per size by [`dispatch!`].

/// Calls `$f::<K>(args)` with K = the order when it is one of the specialised sizes, else
/// `$f::<0>(args)`.
macro_rules! dispatch {
    ($n:expr, $f:ident($($arg:expr),*)) => {
        match $n {
            1 => $f::<1>($($arg),*), 2 => $f::<2>($($arg),*), 3 => $f::<3>($($arg),*),
            4 => $f::<4>($($arg),*), 5 => $f::<5>($($arg),*), 6 => $f::<6>($($arg),*),
            7 => $f::<7>($($arg),*), 8 => $f::<8>($($arg),*), 9 => $f::<9>($($arg),*),
            10 => $f::<10>($($arg),*), 11 => $f::<11>($($arg),*), 12 => $f::<12>($($arg),*),
            _ => $f::<0>($($arg),*),
        }
    };
}
pub(super) use dispatch;

/// `for $k in 0..$n` (`up`) or `(0..$n).rev()` (`down`); when the order is a specialised
/// constant (K > 0) the loop is written out for k = 0..=11, so that with n and k both
/// constants every inner loop has a constant trip count and the kernel becomes
/// straight-line code (2.7x fewer instructions for a 7 x 7 factorisation).
macro_rules! each {
    (up $unroll:expr, $n:expr, |$k:ident| $body:block) => {
        if $unroll {
            each!(@lits $n, $k, $body, 0 1 2 3 4 5 6 7 8 9 10 11);
        } else {
            for $k in 0..$n $body
        }
    };
    (down $unroll:expr, $n:expr, |$k:ident| $body:block) => {
        if $unroll {
            each!(@lits $n, $k, $body, 11 10 9 8 7 6 5 4 3 2 1 0);
        } else {
            for $k in (0..$n).rev() $body
        }
    };
    (@lits $n:expr, $k:ident, $body:block, $($lit:literal)*) => {$(
        {
            let $k: usize = $lit;
            if $k < $n $body
        }
    )*};
}

/// The order: K when specialised, else the run-time n.
#[inline(always)]
fn order<const K: usize>(n: usize) -> usize {
    // `each!` writes loops out for k <= 11 only.
    const {
        assert!(
            K <= 12,
            "`dispatch!` and `each!` specialise orders up to 12"
        )
    };
    if K > 0 { K } else { n }
}

/// P A = L U in place with row pivoting (Golub & Van Loan alg. 3.4.1), |L_ij| <= 1.
/// Returns ||A||_1 (max column sum, for the condition estimate), or `None` when a pivot is
/// exactly zero or not finite.
pub(super) fn factor<const K: usize>(a: &mut [f64], n: usize, piv: &mut [usize]) -> Option<f64> {
    let n = order::<K>(n);
    let (a, piv) = (&mut a[..n * n], &mut piv[..n]);
    let anorm = a
        .chunks_exact(n.max(1))
        .map(|c| c.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, super::max_nan);
    each!(up K > 0, n, |k| {
        if !eliminate(a, n, piv, k) {
            return None;
        }
    });
    Some(anorm)
}

/// Elimination step k: pivot search in column k, row swap, multipliers, rank-1 update of the
/// trailing block. False when the pivot is zero or not finite.
#[inline(always)]
fn eliminate(a: &mut [f64], n: usize, piv: &mut [usize], k: usize) -> bool {
    let (mut p, mut best) = (k, a[k * n + k].abs());
    for (i, v) in a[k * n + k + 1..(k + 1) * n].iter().enumerate() {
        if v.abs() > best {
            p = k + 1 + i;
            best = v.abs();
        }
    }
    piv[k] = p;
    if best == 0.0 || !best.is_finite() {
        return false;
    }
    if p != k {
        for col in a.chunks_exact_mut(n) {
            col.swap(k, p);
        }
    }
    let (left, right) = a.split_at_mut((k + 1) * n);
    let col_k = &mut left[k * n..];
    let inv = 1.0 / col_k[k];
    let l = &mut col_k[k + 1..];
    l.iter_mut().for_each(|v| *v *= inv);
    for col in right.chunks_exact_mut(n) {
        let akj = col[k];
        for (x, lik) in col[k + 1..].iter_mut().zip(l.iter()) {
            *x -= lik * akj;
        }
    }
    true
}

/// x = A^-1 b in place from the factors: P b, then L y = P b (unit diagonal), then U x = y.
pub(super) fn solve<const K: usize>(a: &[f64], n: usize, piv: &[usize], b: &mut [f64]) {
    let n = order::<K>(n);
    let (a, piv, b) = (&a[..n * n], &piv[..n], &mut b[..n]);
    for (k, &p) in piv.iter().enumerate() {
        b.swap(k, p);
    }
    each!(up K > 0, n, |j| {
        let bj = b[j];
        let col = &a[j * n..(j + 1) * n];
        for (bi, l) in b[j + 1..].iter_mut().zip(&col[j + 1..]) {
            *bi -= l * bj;
        }
    });
    each!(down K > 0, n, |j| {
        let col = &a[j * n..(j + 1) * n];
        b[j] /= col[j];
        let bj = b[j];
        for (bi, u) in b[..j].iter_mut().zip(&col[..j]) {
            *bi -= u * bj;
        }
    });
}

/// x = A^-T b in place: U^T z = b, L^T w = z, x = P^T w.
pub(super) fn solve_transpose<const K: usize>(a: &[f64], n: usize, piv: &[usize], b: &mut [f64]) {
    let n = order::<K>(n);
    let (a, piv, b) = (&a[..n * n], &piv[..n], &mut b[..n]);
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(u, v)| u * v).sum::<f64>();
    each!(up K > 0, n, |j| {
        let col = &a[j * n..(j + 1) * n];
        b[j] = (b[j] - dot(&col[..j], &b[..j])) / col[j];
    });
    each!(down K > 0, n, |j| {
        let col = &a[j * n..(j + 1) * n];
        b[j] -= dot(&col[j + 1..], &b[j + 1..]);
    });
    for (k, &p) in piv.iter().enumerate().rev() {
        b.swap(k, p);
    }
}
