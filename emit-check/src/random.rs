//! The deterministic random-expression generator shared by `build.rs` (which emits the
//! expressions as Rust) and the tests (which rebuild the same arena to interpret them).
//!
//! Same seed, same calls, same order: the same canonical nodes with the same ids.

use mechanism_codegen::{Arena, Func, Id, Matrix, SymbolKind};

/// The generator's seed.
pub const SEED: u64 = 0x5EED_C0DE_2026;
/// Number of random scalar expressions.
pub const COUNT: usize = 300;
/// Rows and columns of each generated matrix function.
pub const ROWS: usize = 2;
/// Columns of each generated matrix function.
pub const COLS: usize = 3;
/// Symbol names; build.rs reads them as `q[0]`, `q[1]`, `self.k`, `t`.
pub const SYMBOLS: [&str; 4] = ["x0", "x1", "k", "t"];

/// splitmix64: a small, fixed-seed generator (no dependency in build.rs).
#[derive(Clone, Debug)]
pub struct Rng(pub u64);

impl Rng {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, n).
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n.max(1)
    }

    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The arena with the four symbols declared, and their nodes.
pub fn arena() -> (Arena, [Id; 4]) {
    let mut a = Arena::new();
    let syms = SYMBOLS.map(|n| a.symbol(n, SymbolKind::Free));
    (a, syms)
}

fn leaf(a: &mut Arena, s: &[Id; 4], r: &mut Rng) -> Id {
    match r.below(10) {
        0..=3 => s[r.below(4) as usize],
        4 | 5 => a.int(r.below(7) as i64 - 3),
        6 => a
            .rational(r.below(11) as i64 - 5, r.below(4) as i64 + 2)
            .unwrap_or(s[0]),
        7 | 8 => {
            let v = (r.uniform(-3.0, 3.0) * 1000.0).round() / 1000.0 + 1e-4;
            a.float(v).unwrap_or(s[1])
        }
        _ => a.pi(),
    }
}

/// 1/2 + u^2, positive everywhere.
fn positive(a: &mut Arena, u: Id) -> Id {
    let h = a.rational(1, 2).unwrap_or(u);
    let u2 = a.mul2(u, u);
    a.add2(h, u2)
}

/// A random expression of depth at most `depth` over the symbols, built with the canonical
/// constructors (a constructor's refusal, such as division by a constant 0, gives a symbol).
pub fn expression(a: &mut Arena, s: &[Id; 4], r: &mut Rng, depth: u32) -> Id {
    if depth == 0 || r.below(5) == 0 {
        return leaf(a, s, r);
    }
    let d = depth - 1;
    let kind = r.below(17);
    let u = expression(a, s, r, d);
    match kind {
        0..=2 => {
            let v = expression(a, s, r, d);
            a.add2(u, v)
        }
        3 | 4 => {
            let v = expression(a, s, r, d);
            a.sub(u, v)
        }
        5..=7 => {
            let v = expression(a, s, r, d);
            a.mul2(u, v)
        }
        8 => {
            let v = expression(a, s, r, d);
            a.div(u, v).unwrap_or(s[2])
        }
        9 => {
            let k = [-3, -2, -1, 2, 3, 4, 5, 6][r.below(8) as usize];
            a.powi(u, k).unwrap_or(s[3])
        }
        10 => a.sin(u),
        11 => a.cos(u),
        12 => {
            // sin and cos of one argument together, to exercise sin_cos
            let su = a.sin(u);
            let cu = a.cos(u);
            let v = expression(a, s, r, d);
            let p = a.mul2(su, v);
            a.add2(p, cu)
        }
        13 => {
            let p = positive(a, u);
            match r.below(3) {
                0 => a.sqrt(p).unwrap_or(s[0]),
                1 => a.func(Func::Ln, p).unwrap_or(s[0]),
                _ => {
                    let v = expression(a, s, r, d);
                    a.pow(p, v).unwrap_or(s[0])
                }
            }
        }
        14 => {
            let f = [Func::Exp, Func::Tan, Func::Abs][r.below(3) as usize];
            a.func(f, u).unwrap_or(s[1])
        }
        15 => {
            let v = expression(a, s, r, d);
            a.atan2(u, v)
        }
        _ => a.neg(u),
    }
}

/// The [`COUNT`] random expressions, in one arena.
pub fn generate() -> (Arena, Vec<Id>) {
    let (mut a, s) = arena();
    let mut r = Rng(SEED);
    let ids = (0..COUNT)
        .map(|_| expression(&mut a, &s, &mut r, 4))
        .collect();
    (a, ids)
}

/// Groups of [`ROWS`] x [`COLS`] expressions as matrices; every fourth entry is 0, so that
/// zero-skipping is exercised.
pub fn matrices(a: &mut Arena, ids: &[Id]) -> Vec<Matrix> {
    let n = ROWS * COLS;
    let zero = a.int(0);
    ids.chunks_exact(n)
        .enumerate()
        .map(|(k, c)| {
            Matrix::from_fn(ROWS, COLS, |i, j| {
                let entry = i * COLS + j;
                if (k + entry).is_multiple_of(4) {
                    zero
                } else {
                    c[entry]
                }
            })
        })
        .collect()
}
