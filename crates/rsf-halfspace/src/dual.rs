//! Forward-mode derivatives of closed forms: a number with its three partial derivatives
//! ([`Dual3`]), and the few operations the triangular dislocation's displacement needs, so
//! that its stress is the exact derivative of its displacement (docs/halfspace.md §6,
//! "Stress by forward differentiation").
//!
//! Why not a crate: num-dual 0.15 needs Rust 1.89, above the libraries' 1.85, and the
//! displacement needs only `+ − × ÷`, `√`, `ln` and two arc tangents; written here for
//! `f64` and [`Dual3`] alike through [`Real`].

use std::ops::{Add, Div, Mul, Neg, Sub};

/// The arithmetic the closed forms are written in: `f64` (values) or [`Dual3`] (values
/// and the three partial derivatives by the observation point's coordinates).
pub(crate) trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
{
    /// A constant.
    fn cst(v: f64) -> Self;
    /// The value.
    fn value(self) -> f64;
    /// `√self`.
    fn sqrt(self) -> Self;
    /// `ln self`.
    fn ln(self) -> Self;
    /// `atan2(self, x)`: the angle of `(x, self)` in `(−π, π]`.
    fn atan2(self, x: Self) -> Self;
    /// `atan(self/d)` in `(−π/2, π/2)` (`±π/2` for `d = 0`), its derivative
    /// `(d self' − self d')/(self² + d²)` finite where `d` vanishes.
    fn atan_ratio(self, d: Self) -> Self;
    /// `1/self`.
    fn recip(self) -> Self {
        Self::cst(1.0) / self
    }
}

impl Real for f64 {
    fn cst(v: f64) -> Self {
        v
    }
    fn value(self) -> f64 {
        self
    }
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    fn ln(self) -> Self {
        f64::ln(self)
    }
    fn atan2(self, x: Self) -> Self {
        f64::atan2(self, x)
    }
    fn atan_ratio(self, d: Self) -> Self {
        (self / d).atan()
    }
}

/// A value with its partial derivatives by three variables.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Dual3 {
    /// The value.
    pub v: f64,
    /// `∂/∂x_j`.
    pub d: [f64; 3],
}

impl Dual3 {
    /// The variable `j` at the value `v` (`∂/∂x_j = 1`).
    pub fn variable(v: f64, j: usize) -> Self {
        let mut d = [0.0; 3];
        d[j] = 1.0;
        Self { v, d }
    }

    /// `f(v)` with `f'(v) = slope`.
    fn chain(self, value: f64, slope: f64) -> Self {
        Self {
            v: value,
            d: self.d.map(|x| slope * x),
        }
    }
}

impl Add for Dual3 {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            v: self.v + o.v,
            d: [0, 1, 2].map(|j| self.d[j] + o.d[j]),
        }
    }
}

impl Sub for Dual3 {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self {
            v: self.v - o.v,
            d: [0, 1, 2].map(|j| self.d[j] - o.d[j]),
        }
    }
}

impl Mul for Dual3 {
    type Output = Self;
    #[expect(clippy::suspicious_arithmetic_impl, reason = "the product rule")]
    fn mul(self, o: Self) -> Self {
        Self {
            v: self.v * o.v,
            d: [0, 1, 2].map(|j| self.d[j] * o.v + self.v * o.d[j]),
        }
    }
}

impl Div for Dual3 {
    type Output = Self;
    #[expect(clippy::suspicious_arithmetic_impl, reason = "the quotient rule")]
    fn div(self, o: Self) -> Self {
        let q = self.v / o.v;
        Self {
            v: q,
            d: [0, 1, 2].map(|j| (self.d[j] - q * o.d[j]) / o.v),
        }
    }
}

impl Neg for Dual3 {
    type Output = Self;
    fn neg(self) -> Self {
        Self {
            v: -self.v,
            d: self.d.map(|x| -x),
        }
    }
}

impl Add<f64> for Dual3 {
    type Output = Self;
    fn add(self, o: f64) -> Self {
        Self {
            v: self.v + o,
            d: self.d,
        }
    }
}

impl Sub<f64> for Dual3 {
    type Output = Self;
    fn sub(self, o: f64) -> Self {
        Self {
            v: self.v - o,
            d: self.d,
        }
    }
}

impl Mul<f64> for Dual3 {
    type Output = Self;
    fn mul(self, o: f64) -> Self {
        Self {
            v: self.v * o,
            d: self.d.map(|x| x * o),
        }
    }
}

impl Div<f64> for Dual3 {
    type Output = Self;
    fn div(self, o: f64) -> Self {
        Self {
            v: self.v / o,
            d: self.d.map(|x| x / o),
        }
    }
}

impl Real for Dual3 {
    fn cst(v: f64) -> Self {
        Self { v, d: [0.0; 3] }
    }
    fn value(self) -> f64 {
        self.v
    }
    fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        self.chain(s, 0.5 / s)
    }
    fn ln(self) -> Self {
        self.chain(self.v.ln(), 1.0 / self.v)
    }
    fn atan2(self, x: Self) -> Self {
        let r2 = self.v * self.v + x.v * x.v;
        Self {
            v: self.v.atan2(x.v),
            d: [0, 1, 2].map(|j| (x.v * self.d[j] - self.v * x.d[j]) / r2),
        }
    }
    fn atan_ratio(self, d: Self) -> Self {
        let r2 = self.v * self.v + d.v * d.v;
        Self {
            v: (self.v / d.v).atan(),
            d: [0, 1, 2].map(|j| (d.v * self.d[j] - self.v * d.d[j]) / r2),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each operation's derivative against a central difference of its value.
    #[test]
    fn derivatives_match_central_differences() {
        fn f<T: Real>(x: T, y: T, z: T) -> T {
            let r = (x * x + y * y + z * z).sqrt();
            (r - z).ln() * x / (r + 2.0) - y.atan2(x - 0.3) * 3.0
                + (y * 2.0).atan_ratio(z - r)
                + (x * y - z).recip()
        }
        let p = [0.7, -0.4, 1.3];
        let d = f(
            Dual3::variable(p[0], 0),
            Dual3::variable(p[1], 1),
            Dual3::variable(p[2], 2),
        );
        assert_eq!(d.v, f(p[0], p[1], p[2]));
        let h = 1e-6;
        for j in 0..3 {
            let mut a = p;
            let mut b = p;
            a[j] += h;
            b[j] -= h;
            let fd = (f(a[0], a[1], a[2]) - f(b[0], b[1], b[2])) / (2.0 * h);
            assert!(
                (fd - d.d[j]).abs() < 1e-8 * (1.0 + fd.abs()),
                "{j}: {fd} {:?}",
                d.d
            );
        }
        // atan(n/d) at d = 0: the value ±π/2, the derivative finite.
        let n = Dual3::variable(1.0, 0);
        let z = Dual3::variable(0.0, 1);
        let a = n.atan_ratio(z);
        assert_eq!(a.d, [0.0, -1.0, 0.0]);
    }
}
