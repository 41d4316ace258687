//! The null-space solve on slices (column-major, a[i + j rows] = A_ij), for the run-time
//! sizes of [`super::NullSpace`] (N = M = 0) and the static ones of
//! [`super::FixedNullSpace`] (N, M > 0: every trip count is then a constant, and the small
//! loops unroll into straight-line code without bounds checks).

/// The storage of one solve.
pub(super) struct Parts<'a> {
    /// P Phi_q^T = [L1; L2] U (n x m): L below the diagonal (unit diagonal implied), U on
    /// and above it; rows in pivot order.
    pub lu: &'a mut [f64],
    /// Row k of the factor is coordinate `cols[k]` (n; the first m are dependent).
    pub cols: &'a mut [usize],
    /// M in pivot order, P M P^T (n x n).
    pub pm: &'a mut [f64],
    /// X = -L1^-T L2^T (m x d, at least m d values).
    pub x: &'a mut [f64],
    /// W = M_dd X + M_di (m x d).
    pub w: &'a mut [f64],
    /// Z^T M Z (d x d), its L D L^T factors in the lower triangle (D on the diagonal).
    pub r: &'a mut [f64],
    /// n values in pivot order.
    pub u: &'a mut [f64],
    /// m values.
    pub v: &'a mut [f64],
    /// d values.
    pub z: &'a mut [f64],
    /// 1 / u_kk (m), then 1 / D_jj (d): the solves multiply instead of dividing.
    pub inv: &'a mut [f64],
}

/// The static size when specialised, else the run-time one.
#[inline(always)]
fn size<const K: usize>(k: usize) -> usize {
    if K > 0 { K } else { k }
}

/// Factors Phi_q^T (`phi_q` is m x n) with row pivoting, forms X, M in pivot order and
/// Z^T M Z, and factors it; returns the condition indicator (see the module docs of
/// [`super`]) or `None` (rank below m, Z^T M Z not positive definite, or m > n).
#[inline(always)]
pub(super) fn factor<const N: usize, const M: usize>(
    p: &mut Parts<'_>,
    n: usize,
    m: usize,
    mass: &[f64],
    phi_q: &[f64],
) -> Option<f64> {
    let (n, m) = (size::<N>(n), size::<M>(m));
    if m > n {
        return None;
    }
    let d = n - m;
    let kappa_b = if N > 0 && N * M <= LOCAL_MAX {
        eliminate_local::<N, M>(p, phi_q)?
    } else {
        eliminate(p, n, m, phi_q)?
    };
    let (lu, cols) = (&p.lu[..m * n], &p.cols[..n]);
    // M in pivot order.
    let (mass, pm) = (&mass[..n * n], &mut p.pm[..n * n]);
    for j in 0..n {
        let cj = cols[j] * n;
        for i in 0..n {
            pm[i + j * n] = mass[cols[i] + cj];
        }
    }
    // X = -L1^-T L2^T, and W = M_dd X + M_di.
    let (x, w) = (&mut p.x[..m * d], &mut p.w[..m * d]);
    for c in 0..d {
        let xc = &mut x[c * m..(c + 1) * m];
        for k in (0..m).rev() {
            let mut s = -lu[(m + c) + k * n];
            for i in k + 1..m {
                s -= lu[i + k * n] * xc[i];
            }
            xc[k] = s;
        }
        for i in 0..m {
            let mut s = pm[i + (m + c) * n];
            for k in 0..m {
                s += pm[i + k * n] * xc[k];
            }
            w[i + c * m] = s;
        }
    }
    // Z^T M Z = M_ii + M_id X + X^T W (lower triangle), and the largest |Z_j|^2.
    let r = &mut p.r[..d * d];
    let mut znorm = 1.0_f64;
    for b in 0..d {
        let xb = &x[b * m..(b + 1) * m];
        znorm = znorm.max(1.0 + xb.iter().map(|v| v * v).sum::<f64>());
        for a in b..d {
            let mut s = pm[(m + a) + (m + b) * n];
            for k in 0..m {
                s += pm[(m + a) + k * n] * xb[k] + x[k + a * m] * w[k + b * m];
            }
            r[a + b * d] = s;
        }
    }
    let scale = (0..n).fold(0.0_f64, |s, i| s.max(pm[i * (n + 1)].abs())) * znorm;
    let smallest = ldlt(r, d, &mut p.inv[m..n])?;
    let kappa_r = if d == 0 { 1.0 } else { scale / smallest };
    Some(kappa_b.max(kappa_r))
}

/// Largest N M whose elimination runs on a local copy (see [`eliminate_local`]).
const LOCAL_MAX: usize = 24;

/// P Phi_q^T = [L1; L2] U in `p.lu` with the pivot order in `p.cols` and 1 / u_kk in
/// `p.inv`; returns max_k |Phi_q,k|_inf / |u_kk| (at least 1), or `None` at a zero or
/// non-finite pivot.
#[inline(always)]
fn eliminate(p: &mut Parts<'_>, n: usize, m: usize, phi_q: &[f64]) -> Option<f64> {
    let (lu, cols) = (&mut p.lu[..m * n], &mut p.cols[..n]);
    let phi_q = &phi_q[..m * n];
    // Phi_q^T, and the largest entry of each row of Phi_q.
    let mut kappa_b = 1.0_f64;
    for k in 0..m {
        let mut big = 0.0_f64;
        for j in 0..n {
            let v = phi_q[k + j * m];
            lu[j + k * n] = v;
            big = big.max(v.abs());
        }
        // Reused below as the row's scale; the pivot of row k is compared with it.
        p.v[k] = big;
    }
    for (k, c) in cols.iter_mut().enumerate() {
        *c = k;
    }
    for k in 0..m {
        let (mut pi, mut best) = (k, 0.0_f64);
        for i in k..n {
            let v = lu[i + k * n].abs();
            if v > best {
                (pi, best) = (i, v);
            }
        }
        if best == 0.0 || !best.is_finite() {
            return None;
        }
        if pi != k {
            for j in 0..m {
                lu.swap(k + j * n, pi + j * n);
            }
            cols.swap(k, pi);
        }
        let inv = 1.0 / lu[k + k * n];
        p.inv[k] = inv;
        // |u_kk| against the size of constraint row k: its distance from the rows before
        // (|1 / u_kk| is at hand: no second division on the pivots' dependency chain).
        kappa_b = kappa_b.max(p.v[k] * inv.abs());
        for i in k + 1..n {
            lu[i + k * n] *= inv;
        }
        for j in k + 1..m {
            let akj = lu[k + j * n];
            for i in k + 1..n {
                lu[i + j * n] -= lu[i + k * n] * akj;
            }
        }
    }
    Some(kappa_b)
}

/// [`eliminate`] for small static sizes on a local array: with every index a constant after
/// unrolling and the row swaps written as selects, the values stay in registers, and the
/// factors are stored once at the end. Rows are never swapped in memory: a row written
/// and read back as a pair stalls on store forwarding.
#[inline(always)]
// Indices, not iterators: the point is that each becomes a constant once unrolled.
#[allow(clippy::needless_range_loop)]
fn eliminate_local<const N: usize, const M: usize>(
    p: &mut Parts<'_>,
    phi_q: &[f64],
) -> Option<f64> {
    let phi_q = &phi_q[..M * N];
    // a[k][i] = (Phi_q^T)_ik, and the largest entry of each row of Phi_q.
    let mut a = [[0.0_f64; N]; M];
    let mut row_max = [0.0_f64; M];
    for k in 0..M {
        for i in 0..N {
            let v = phi_q[k + i * M];
            a[k][i] = v;
            row_max[k] = row_max[k].max(v.abs());
        }
    }
    let mut cols: [usize; N] = core::array::from_fn(|i| i);
    let mut kappa_b = 1.0_f64;
    for k in 0..M {
        let (mut pi, mut best) = (k, 0.0_f64);
        for i in k..N {
            let v = a[k][i].abs();
            if v > best {
                (pi, best) = (i, v);
            }
        }
        if best == 0.0 || !best.is_finite() {
            return None;
        }
        for i in k + 1..N {
            let swap = i == pi;
            for col in a.iter_mut() {
                let (x, y) = (col[k], col[i]);
                col[k] = if swap { y } else { x };
                col[i] = if swap { x } else { y };
            }
            let (x, y) = (cols[k], cols[i]);
            cols[k] = if swap { y } else { x };
            cols[i] = if swap { x } else { y };
        }
        let inv = 1.0 / a[k][k];
        p.inv[k] = inv;
        kappa_b = kappa_b.max(row_max[k] * inv.abs());
        for i in k + 1..N {
            a[k][i] *= inv;
        }
        for j in k + 1..M {
            let akj = a[j][k];
            for i in k + 1..N {
                a[j][i] -= a[k][i] * akj;
            }
        }
    }
    for k in 0..M {
        p.lu[k * N..(k + 1) * N].copy_from_slice(&a[k]);
    }
    p.cols[..N].copy_from_slice(&cols);
    Some(kappa_b)
}

/// L D L^T of the d x d lower triangle of `r` in place (L unit lower triangular below the
/// diagonal, D on it; no square root on the path of every solve); `inv_diag` receives
/// 1 / D_jj. Returns the smallest pivot D_jj, or `None` when one is not positive and finite
/// (infinite for d = 0).
#[inline(always)]
fn ldlt(r: &mut [f64], d: usize, inv_diag: &mut [f64]) -> Option<f64> {
    let mut smallest = f64::INFINITY;
    for j in 0..d {
        // Below the diagonal r[i + k d] holds L_ik, on it D_kk.
        let mut p = r[j + j * d];
        for k in 0..j {
            let ljk = r[j + k * d];
            p -= ljk * ljk * r[k + k * d];
        }
        if !(p > 0.0 && p.is_finite()) {
            return None;
        }
        smallest = smallest.min(p);
        r[j + j * d] = p;
        let inv = 1.0 / p;
        inv_diag[j] = inv;
        for i in j + 1..d {
            let mut s = r[i + j * d];
            for k in 0..j {
                s -= r[i + k * d] * r[j + k * d] * r[k + k * d];
            }
            r[i + j * d] = s * inv;
        }
    }
    Some(smallest)
}

/// Solves in place: `sol` holds [Q; gamma] and receives [q''; lambda] (see the module docs
/// of [`super`]), from the factors of [`factor`]. Without `multipliers` the last m values
/// are left as they were (gamma): the multipliers' n m + m^2 operations are skipped.
#[inline(always)]
pub(super) fn solve<const N: usize, const M: usize>(
    p: &mut Parts<'_>,
    n: usize,
    m: usize,
    sol: &mut [f64],
    multipliers: bool,
) {
    let (n, m) = (size::<N>(n), size::<M>(m));
    let d = n - m;
    let sol = &mut sol[..n + m];
    let (lu, cols, pm) = (&p.lu[..m * n], &p.cols[..n], &p.pm[..n * n]);
    let (x, r) = (&p.x[..m * d], &p.r[..d * d]);
    let (u, v, z) = (&mut p.u[..n], &mut p.v[..m], &mut p.z[..d]);
    let (inv_u, inv_r) = p.inv[..n].split_at(m);
    // Particular solution: B v = gamma with B = U^T L1^T (the dependent columns of Phi_q).
    v.copy_from_slice(&sol[n..]);
    for k in 0..m {
        let mut s = v[k];
        for i in 0..k {
            s -= lu[i + k * n] * v[i];
        }
        v[k] = s * inv_u[k];
    }
    for k in (0..m).rev() {
        let mut s = v[k];
        for i in k + 1..m {
            s -= lu[i + k * n] * v[i];
        }
        v[k] = s;
    }
    // u = P Q - (M in pivot order) [v; 0]; the reduced right-hand side X^T u_dep + u_ind.
    for k in 0..n {
        u[k] = sol[cols[k]];
    }
    for i in 0..m {
        let vi = v[i];
        for k in 0..n {
            u[k] -= pm[k + i * n] * vi;
        }
    }
    for c in 0..d {
        let mut s = u[m + c];
        for k in 0..m {
            s += x[k + c * m] * u[k];
        }
        z[c] = s;
    }
    ldlt_solve(r, d, inv_r, z);
    // q'' in pivot order: [v + X z; z].
    for i in 0..m {
        let mut s = v[i];
        for c in 0..d {
            s += x[i + c * m] * z[c];
        }
        u[i] = s;
    }
    u[m..].copy_from_slice(z);
    if !multipliers {
        for k in 0..n {
            sol[cols[k]] = u[k];
        }
        return;
    }
    // Multipliers: B^T lambda = L1 U lambda = (P Q - M q'')_dep.
    for i in 0..m {
        let mut s = sol[cols[i]];
        for k in 0..n {
            s -= pm[i + k * n] * u[k];
        }
        v[i] = s;
    }
    for k in 0..m {
        let mut s = v[k];
        for i in 0..k {
            s -= lu[k + i * n] * v[i];
        }
        v[k] = s;
    }
    for k in (0..m).rev() {
        let mut s = v[k];
        for j in k + 1..m {
            s -= lu[k + j * n] * v[j];
        }
        v[k] = s * inv_u[k];
    }
    for k in 0..n {
        sol[cols[k]] = u[k];
    }
    sol[n..].copy_from_slice(v);
}

/// b = (L D L^T)^-1 b, L the unit lower triangle below the diagonal of the d x d `l`, `inv`
/// the reciprocal of D.
#[inline(always)]
fn ldlt_solve(l: &[f64], d: usize, inv: &[f64], b: &mut [f64]) {
    for j in 0..d {
        let bj = b[j];
        for i in j + 1..d {
            b[i] -= l[i + j * d] * bj;
        }
    }
    for j in 0..d {
        b[j] *= inv[j];
    }
    for j in (0..d).rev() {
        let mut s = b[j];
        for i in j + 1..d {
            s -= l[i + j * d] * b[i];
        }
        b[j] = s;
    }
}
