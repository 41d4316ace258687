//! T, Pi and Phi of the benchmarked mechanisms written by hand as generic Rust over
//! [`DualNum`], the input of the AD baseline ([`crate::autodiff`]). Each mirrors the `.mech`
//! declaration of the same name (`mechanisms/` and `benches/mechanisms/`); the unit tests
//! check that the AD route reproduces the compiled equations.

use num_dual::DualNum;

use crate::autodiff::{AdModel, parameter};

/// The seed spatial crank-slider (`mechanisms/spatial_crank_slider.mech`),
/// q = [phi, beta, gamma, x_c].
pub struct SeedAd {
    h: f64,
    l1: f64,
    l2: f64,
    d: f64,
    alpha: f64,
    m1: f64,
    m2: f64,
    m3: f64,
    j1: f64,
    a1: f64,
    g: f64,
    tau0: f64,
    omega: f64,
}

impl AdModel<4, 3> for SeedAd {
    fn from_parameters(names: &[String], values: &[f64]) -> Self {
        let p = |s| parameter(names, values, s);
        Self {
            h: p("h"),
            l1: p("l1"),
            l2: p("l2"),
            d: p("d"),
            alpha: p("alpha"),
            m1: p("m1"),
            m2: p("m2"),
            m3: p("m3"),
            j1: p("J1"),
            a1: p("a1"),
            g: p("g"),
            tau0: p("tau0"),
            omega: p("Omega"),
        }
    }
    fn kinetic<D: DualNum<Primitive = f64> + Copy>(&self, _q: &[D; 4], qd: &[D; 4]) -> D {
        let (jp, mx) = (
            self.j1 + self.m2 / 2.0 * self.l1 * self.l1,
            self.m2 / 2.0 + self.m3,
        );
        qd[0] * qd[0] * (0.5 * jp) + qd[3] * qd[3] * (0.5 * mx)
    }
    fn potential<D: DualNum<Primitive = f64> + Copy>(&self, q: &[D; 4]) -> D {
        let c = q[0].cos();
        (c * self.a1 + self.h) * (self.m1 * self.g)
            + (c * self.l1 + self.h) * (self.m2 / 2.0 * self.g)
    }
    fn constraints<D: DualNum<Primitive = f64> + Copy>(&self, q: &[D; 4]) -> [D; 3] {
        let (sp, cp) = q[0].sin_cos();
        let (sb, cb) = q[1].sin_cos();
        let (sg, cg) = q[2].sin_cos();
        let (sa, ca) = self.alpha.sin_cos();
        [
            sp * (self.l1 * sa) + sg * cb * self.l2 - q[3],
            -sp * (self.l1 * ca) + sg * sb * self.l2 - self.d,
            cp * self.l1 - cg * self.l2 + self.h,
        ]
    }
    fn forces(&self, t: f64, _q: &[f64; 4], _qd: &[f64; 4]) -> [f64; 4] {
        [self.tau0 * (self.omega * t).sin(), 0.0, 0.0, 0.0]
    }
}

/// The planar four-bar (`mechanisms/planar_four_bar.mech`), q = [th1, th2, th3].
pub struct FourBarAd {
    l1: f64,
    l2: f64,
    l3: f64,
    dx: f64,
    m1: f64,
    m2: f64,
    m3: f64,
    g: f64,
}

impl AdModel<3, 2> for FourBarAd {
    fn from_parameters(names: &[String], values: &[f64]) -> Self {
        let p = |s| parameter(names, values, s);
        Self {
            l1: p("l1"),
            l2: p("l2"),
            l3: p("l3"),
            dx: p("Dx"),
            m1: p("m1"),
            m2: p("m2"),
            m3: p("m3"),
            g: p("g"),
        }
    }
    fn kinetic<D: DualNum<Primitive = f64> + Copy>(&self, q: &[D; 3], qd: &[D; 3]) -> D {
        let (l1, l2, l3) = (self.l1, self.l2, self.l3);
        let (s1, c1) = q[0].sin_cos();
        let (s2, c2) = q[1].sin_cos();
        let vx = -(s1 * qd[0] * l1 + s2 * qd[1] * (l2 / 2.0));
        let vy = c1 * qd[0] * l1 + c2 * qd[1] * (l2 / 2.0);
        let crank = 0.5 * self.m1 * (l1 * l1 / 4.0 + l1 * l1 / 12.0);
        let rocker = 0.5 * self.m3 * (l3 * l3 / 4.0 + l3 * l3 / 12.0);
        qd[0] * qd[0] * crank
            + (vx * vx + vy * vy) * (0.5 * self.m2)
            + qd[1] * qd[1] * (0.5 * self.m2 * l2 * l2 / 12.0)
            + qd[2] * qd[2] * rocker
    }
    fn potential<D: DualNum<Primitive = f64> + Copy>(&self, q: &[D; 3]) -> D {
        let (s1, s2, s3) = (q[0].sin(), q[1].sin(), q[2].sin());
        (s1 * (self.m1 * self.l1 / 2.0)
            + (s1 * self.l1 + s2 * (self.l2 / 2.0)) * self.m2
            + s3 * (self.m3 * self.l3 / 2.0))
            * self.g
    }
    fn constraints<D: DualNum<Primitive = f64> + Copy>(&self, q: &[D; 3]) -> [D; 2] {
        let (s1, c1) = q[0].sin_cos();
        let (s2, c2) = q[1].sin_cos();
        let (s3, c3) = q[2].sin_cos();
        [
            c1 * self.l1 + c2 * self.l2 - c3 * self.l3 - self.dx,
            s1 * self.l1 + s2 * self.l2 - s3 * self.l3,
        ]
    }
}

/// The spatial four-bar RSSR (`mechanisms/spatial_four_bar.mech`), q = [phi, beta, gamma, psi].
pub struct RssrAd {
    l1: f64,
    l2: f64,
    l3: f64,
    m1: f64,
    m2: f64,
    m3: f64,
    dx: f64,
    dy: f64,
    dz: f64,
    g: f64,
}

impl AdModel<4, 3> for RssrAd {
    fn from_parameters(names: &[String], values: &[f64]) -> Self {
        let p = |s| parameter(names, values, s);
        Self {
            l1: p("l1"),
            l2: p("l2"),
            l3: p("l3"),
            m1: p("m1"),
            m2: p("m2"),
            m3: p("m3"),
            dx: p("Dx"),
            dy: p("Dy"),
            dz: p("Dz"),
            g: p("g"),
        }
    }
    fn kinetic<D: DualNum<Primitive = f64> + Copy>(&self, q: &[D; 4], qd: &[D; 4]) -> D {
        let (l1, l2, l3) = (self.l1, self.l2, self.l3);
        let (sp, cp) = q[0].sin_cos();
        let (sb, cb) = q[1].sin_cos();
        let (sg, cg) = q[2].sin_cos();
        let (dp, db, dg, dpsi) = (qd[0], qd[1], qd[2], qd[3]);
        let vx = -(sp * dp * l1) + (cg * cb * dg - sg * sb * db) * (l2 / 2.0);
        let vy = cp * dp * l1 + (cg * sb * dg + sg * cb * db) * (l2 / 2.0);
        let vz = sg * dg * (l2 / 2.0);
        dp * dp * (0.5 * self.m1 * l1 * l1 / 3.0)
            + (vx * vx + vy * vy + vz * vz) * (0.5 * self.m2)
            + (dg * dg + sg * sg * db * db) * (0.5 * self.m2 * l2 * l2 / 12.0)
            + dpsi * dpsi * (0.5 * self.m3 * l3 * l3 / 3.0)
    }
    fn potential<D: DualNum<Primitive = f64> + Copy>(&self, q: &[D; 4]) -> D {
        q[2].cos() * (self.m2 * self.g * self.l2 / 2.0)
            + (q[3].sin() * (self.l3 / 2.0) + self.dz) * (self.m3 * self.g)
    }
    fn constraints<D: DualNum<Primitive = f64> + Copy>(&self, q: &[D; 4]) -> [D; 3] {
        let (sp, cp) = q[0].sin_cos();
        let (sb, cb) = q[1].sin_cos();
        let (sg, cg) = q[2].sin_cos();
        let (ss, cs) = q[3].sin_cos();
        let (l1, l2, l3) = (self.l1, self.l2, self.l3);
        [
            cp * l1 + sg * cb * l2 - self.dx,
            sp * l1 + sg * sb * l2 - cs * l3 - self.dy,
            cg * l2 - ss * l3 - self.dz,
        ]
    }
}

/// The closed planar chain of N rods (`closed_chain_source(N)`), q = [th1 .. thN]: the
/// midpoint velocities by running sums, O(N) per evaluation of T.
pub struct ChainAd<const N: usize> {
    g: f64,
}

impl<const N: usize> AdModel<N, 2> for ChainAd<N> {
    fn from_parameters(names: &[String], values: &[f64]) -> Self {
        Self {
            g: parameter(names, values, "g"),
        }
    }
    fn kinetic<D: DualNum<Primitive = f64> + Copy>(&self, q: &[D; N], qd: &[D; N]) -> D {
        let zero = D::from(0.0);
        let (mut ax, mut ay, mut t) = (zero, zero, zero);
        for i in 0..N {
            let (s, c) = q[i].sin_cos();
            let (dx, dy) = (-(s * qd[i]), c * qd[i]);
            let (vx, vy) = (ax + dx * 0.5, ay + dy * 0.5);
            t += (vx * vx + vy * vy) * 0.5 + qd[i] * qd[i] * (1.0 / 24.0);
            ax += dx;
            ay += dy;
        }
        t
    }
    fn potential<D: DualNum<Primitive = f64> + Copy>(&self, q: &[D; N]) -> D {
        let zero = D::from(0.0);
        let (mut a, mut p) = (zero, zero);
        for x in q {
            let s = x.sin();
            p += a + s * 0.5;
            a += s;
        }
        p * self.g
    }
    fn constraints<D: DualNum<Primitive = f64> + Copy>(&self, q: &[D; N]) -> [D; 2] {
        let zero = D::from(0.0);
        let (mut x, mut y) = (zero, zero);
        for v in q {
            let (s, c) = v.sin_cos();
            x += c;
            y += s;
        }
        [x - N as f64 / 2.0, y]
    }
}
