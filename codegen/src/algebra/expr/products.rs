//! Products and powers of the arena: the canonical product (flat, like powers collected,
//! a numeric factor distributed over a single sum), quotients, powers and square roots.

use smallvec::SmallVec;

use crate::algebra::expr::{Arena, Id, Node, Operands, Short};
use crate::error::AlgebraError;
use crate::error::{Error, Result};
use crate::number::Number;

impl Arena {
    /// Splits a factor into base and exponent (`x` is `x^1`).
    fn split_power(&mut self, id: Id) -> (Id, Id) {
        match *self.node(id) {
            Node::Pow(b, e) => (b, e),
            _ => (id, self.int(1)),
        }
    }

    /// The canonical product of `factors`.
    pub fn mul(&mut self, factors: &[Id]) -> Id {
        let mut flat: Short<Id> = SmallVec::with_capacity(factors.len());
        for &f in factors {
            match self.node(f) {
                Node::Mul(fs) => flat.extend_from_slice(fs),
                _ => flat.push(f),
            }
        }
        let mut coef = Number::int(1);
        let mut pairs: Short<(Id, Id)> = SmallVec::with_capacity(flat.len());
        for &f in flat.iter() {
            match self.node(f) {
                Node::Num(n) => {
                    let n = *n;
                    coef = self.fold_mul(coef, n);
                    if coef.is_zero() {
                        return self.int(0);
                    }
                }
                _ => pairs.push(self.split_power(f)),
            }
        }
        pairs.sort_by_key(|p| p.0);
        let mut rest: Short<Id> = SmallVec::with_capacity(pairs.len());
        let mut redo = false;
        let mut i = 0;
        while i < pairs.len() {
            let base = pairs[i].0;
            let mut j = i + 1;
            while j < pairs.len() && pairs[j].0 == base {
                j += 1;
            }
            let exp = if j == i + 1 {
                pairs[i].1
            } else {
                let es: Short<Id> = pairs[i..j].iter().map(|p| p.1).collect();
                self.add(&es)
            };
            // pow of a canonical base with collected exponent; a 0^negative cannot arise from a
            // product of existing factors unless one of them already was undefined.
            let p = match self.pow(base, exp) {
                Ok(p) => p,
                Err(_) => self.intern(Node::Pow(base, exp)),
            };
            match self.node(p) {
                Node::Num(n) => {
                    let n = *n;
                    coef = self.fold_mul(coef, n);
                    if coef.is_zero() {
                        return self.int(0);
                    }
                }
                Node::Mul(_) => {
                    redo = true;
                    rest.push(p);
                }
                _ => rest.push(p),
            }
            i = j;
        }
        if redo {
            let c = self.number(coef);
            rest.push(c);
            return self.mul(&rest);
        }
        rest.sort();
        match rest.len() {
            0 => self.number(coef),
            1 => self.scale(coef, rest[0]),
            _ => {
                let body = self.intern(Node::Mul(Operands::from(rest)));
                self.scale(coef, body)
            }
        }
    }

    /// a * b.
    pub fn mul2(&mut self, a: Id, b: Id) -> Id {
        self.mul(&[a, b])
    }

    /// a / b; an error when b is the constant 0.
    pub fn div(&mut self, a: Id, b: Id) -> Result<Id> {
        let m1 = self.int(-1);
        let inv = self.pow(b, m1)?;
        Ok(self.mul2(a, inv))
    }

    /// base ^ exponent, canonical; 0 to a negative constant power is
    /// [`crate::error::AlgebraError::DivisionByZero`].
    pub fn pow(&mut self, base: Id, exp: Id) -> Result<Id> {
        let e = self.as_number(exp);
        if let Some(en) = e {
            if en.is_zero() {
                return Ok(self.int(1));
            }
            if en.is_one() {
                return Ok(base);
            }
        }
        if let Some(b) = self.as_number(base) {
            if b.is_zero() {
                return match e {
                    Some(en) if en.is_negative() => {
                        Err(Error::Algebra(AlgebraError::DivisionByZero {
                            operation: format!("0^{en}"),
                        }))
                    }
                    Some(_) => Ok(self.int(0)),
                    None => Ok(self.intern(Node::Pow(base, exp))),
                };
            }
            if b.is_one() {
                return Ok(base);
            }
            if let Some(en) = e {
                if let Some(k) = en.as_integer() {
                    if let Some(r) = b.powi(k) {
                        return Ok(self.number(r));
                    }
                } else if (b.is_float() || en.is_float())
                    && let Some(r) = Number::float(b.to_f64().powf(en.to_f64()))
                {
                    return Ok(self.number(r));
                }
            }
        }
        let int_exp = e.and_then(Number::as_integer);
        match self.node(base).clone() {
            Node::Pow(b, e1) if int_exp.is_some() => {
                let ne = self.mul2(e1, exp);
                return self.pow(b, ne);
            }
            Node::Mul(fs) if int_exp.is_some() => {
                let mut parts = Vec::with_capacity(fs.len());
                for f in fs.iter() {
                    parts.push(self.pow(*f, exp)?);
                }
                return Ok(self.mul(&parts));
            }
            _ => {}
        }
        Ok(self.intern(Node::Pow(base, exp)))
    }

    /// base ^ n for an integer n.
    pub fn powi(&mut self, base: Id, n: i64) -> Result<Id> {
        let e = self.int(n);
        self.pow(base, e)
    }

    /// sqrt(x) = x^(1/2).
    pub fn sqrt(&mut self, x: Id) -> Result<Id> {
        let h = self.rational(1, 2)?;
        self.pow(x, h)
    }
}
