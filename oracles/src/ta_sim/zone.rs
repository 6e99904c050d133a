//! Zones for the interpreter: difference-bound matrices over the network's
//! clocks (index 0 is the reference clock, clock `c` of the network is
//! index `c + 1`), kept canonical (shortest paths) after every operation,
//! with the classic maximal-constant extrapolation (every constraint of
//! the networks compares a clock with a constant, no clock differences).
//!
//! A bound is encoded as one integer: `2c + 1` for `≤ c`, `2c` for `< c`,
//! so that the integer order is the order of the bounds.

use genom_model::timed_automata::CmpOp;

/// No bound.
const INF: i64 = i64::MAX / 4;

fn le(c: i64) -> i64 {
    2 * c + 1
}

fn lt(c: i64) -> i64 {
    2 * c
}

/// The sum of two bounds (strict when either is).
fn add(a: i64, b: i64) -> i64 {
    if a >= INF || b >= INF {
        INF
    } else {
        ((a >> 1) + (b >> 1)) * 2 + (a & b & 1)
    }
}

/// A zone: `d[i * n + j]` bounds `x_i - x_j`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Zone {
    n: usize,
    d: Vec<i64>,
}

impl Zone {
    /// Every clock at 0.
    pub fn zero(clocks: usize) -> Zone {
        let n = clocks + 1;
        Zone {
            n,
            d: vec![le(0); n * n],
        }
    }

    fn at(&self, i: usize, j: usize) -> i64 {
        self.d[i * self.n + j]
    }

    fn set(&mut self, i: usize, j: usize, b: i64) {
        self.d[i * self.n + j] = b;
    }

    /// No valuation.
    pub fn is_empty(&self) -> bool {
        (0..self.n).any(|i| self.at(i, i) < le(0))
    }

    /// Shortest paths (Floyd-Warshall); stops early when empty.
    fn close(&mut self) {
        let n = self.n;
        for k in 0..n {
            for i in 0..n {
                let ik = self.at(i, k);
                if ik >= INF {
                    continue;
                }
                for j in 0..n {
                    let via = add(ik, self.at(k, j));
                    if via < self.at(i, j) {
                        self.set(i, j, via);
                    }
                }
            }
            if self.at(k, k) < le(0) {
                return;
            }
        }
    }

    /// Lets time pass: no upper bound on any clock.
    pub fn up(&mut self) {
        for i in 1..self.n {
            self.set(i, 0, INF);
        }
    }

    /// Intersects with `x op c` (network clock `x`); `!=` is no zone.
    pub fn constrain(&mut self, x: usize, op: CmpOp, c: i64) -> Result<(), String> {
        let x = x + 1;
        match op {
            CmpOp::Le => self.tighten(x, 0, le(c)),
            CmpOp::Lt => self.tighten(x, 0, lt(c)),
            CmpOp::Ge => self.tighten(0, x, le(-c)),
            CmpOp::Gt => self.tighten(0, x, lt(-c)),
            CmpOp::Eq => {
                self.tighten(x, 0, le(c));
                self.tighten(0, x, le(-c));
            }
            CmpOp::Ne => return Err("`!=` on a clock is not a zone".into()),
        }
        Ok(())
    }

    /// Intersects the canonical zone with `x_i - x_j` bounded by `b`, and
    /// keeps it canonical: a path through the new edge is the only one
    /// that can be shorter, so one pass over the pairs suffices (O(n²)
    /// instead of a whole Floyd-Warshall).
    fn tighten(&mut self, i: usize, j: usize, b: i64) {
        if b >= self.at(i, j) || self.is_empty() {
            return;
        }
        if add(self.at(j, i), b) < le(0) {
            // A negative cycle: no valuation.
            self.set(0, 0, lt(0));
            return;
        }
        let n = self.n;
        let to_i: Vec<i64> = (0..n).map(|k| self.at(k, i)).collect();
        let from_j: Vec<i64> = (0..n).map(|l| self.at(j, l)).collect();
        for (k, &ki) in to_i.iter().enumerate() {
            if ki >= INF {
                continue;
            }
            let kib = add(ki, b);
            for (l, &jl) in from_j.iter().enumerate() {
                let via = add(kib, jl);
                if via < self.at(k, l) {
                    self.set(k, l, via);
                }
            }
        }
    }

    /// Sets network clock `x` to 0.
    pub fn reset(&mut self, x: usize) {
        let x = x + 1;
        for j in 0..self.n {
            let (to, from) = (self.at(0, j), self.at(j, 0));
            self.set(x, j, to);
            self.set(j, x, from);
        }
        self.set(x, x, le(0));
    }

    /// Forgets what no constraint can tell apart: `max[c]` is the largest
    /// constant network clock `c` is compared with.
    pub fn extrapolate(&mut self, max: &[i64]) {
        let m = |i: usize| if i == 0 { 0 } else { max[i - 1] };
        for i in 0..self.n {
            for j in 0..self.n {
                if i == j {
                    continue;
                }
                let b = self.at(i, j);
                if i > 0 && b < INF && b > le(m(i)) {
                    self.set(i, j, INF);
                } else if j > 0 && b < lt(-m(j)) {
                    self.set(i, j, lt(-m(j)));
                }
            }
        }
        self.close();
    }

    /// Whether every valuation of `self` is one of `o` (both canonical).
    pub fn within(&self, o: &Zone) -> bool {
        self.d.iter().zip(&o.d).all(|(a, b)| a <= b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_add_and_order() {
        assert_eq!(add(le(2), le(3)), le(5));
        assert_eq!(add(le(2), lt(3)), lt(5));
        assert_eq!(add(lt(-2), le(-3)), lt(-5));
        assert!(lt(3) < le(3) && le(3) < lt(4));
    }

    #[test]
    fn a_zone_delays_constrains_and_resets() {
        let mut z = Zone::zero(2);
        z.up();
        z.constrain(0, CmpOp::Le, 5).unwrap();
        z.constrain(0, CmpOp::Ge, 5).unwrap();
        assert!(!z.is_empty());
        // Both clocks moved together: the second is 5 too.
        let mut w = z.clone();
        w.constrain(1, CmpOp::Lt, 5).unwrap();
        assert!(w.is_empty());
        z.reset(0);
        z.up();
        z.constrain(1, CmpOp::Le, 7).unwrap();
        let mut y = z.clone();
        y.constrain(0, CmpOp::Gt, 2).unwrap();
        assert!(y.is_empty());
        let mut small = Zone::zero(2);
        small.up();
        small.constrain(0, CmpOp::Le, 1).unwrap();
        let mut big = Zone::zero(2);
        big.up();
        assert!(small.within(&big) && !big.within(&small));
    }
}
