//! Difference-bound matrices: the symbolic representation of clock zones.
//!
//! A zone over clocks `x1..xn` is a conjunction of constraints
//! `xi - xj ≺ c` (with `x0 = 0` the reference clock, `≺` one of `<`, `≤`).
//! Entry `(i, j)` of the matrix is the tightest bound on `xi - xj`. A bound
//! is stored as one `i64`: `2c + 1` for `≤ c`, `2c` for `< c`, and
//! [`INF`] for no bound, so that comparing raw values compares bounds and
//! adding them is cheap.

use std::fmt;

/// A bound `≺ c` packed in an `i64`.
pub type Bound = i64;

/// No bound.
pub const INF: Bound = i64::MAX;

/// `≤ 0`.
pub const LE_ZERO: Bound = 1;

/// `≤ c`.
pub const fn le(c: i64) -> Bound {
    (c << 1) | 1
}

/// `< c`.
pub const fn lt(c: i64) -> Bound {
    c << 1
}

/// The constant of a finite bound.
pub const fn constant(b: Bound) -> i64 {
    b >> 1
}

/// Whether a finite bound is non-strict.
pub const fn is_weak(b: Bound) -> bool {
    b & 1 == 1
}

/// The sum of two bounds (`≤` only when both are `≤`).
pub fn add(a: Bound, b: Bound) -> Bound {
    if a == INF || b == INF {
        return INF;
    }
    let c = constant(a).saturating_add(constant(b));
    (c << 1) | (a & b & 1)
}

/// The bound `xj - xi ≺' -c` implied by the negation of `xi - xj ≺ c`
/// (used for complements): `¬(x ≤ c)` is `-x < -c`, `¬(x < c)` is `-x ≤ -c`.
pub fn negate(b: Bound) -> Bound {
    if b == INF {
        return INF;
    }
    let c = -constant(b);
    if is_weak(b) { lt(c) } else { le(c) }
}

/// A zone over `dim - 1` clocks (clock 0 is the constant zero).
#[derive(Clone, PartialEq, Eq, Hash)]
pub struct Dbm {
    dim: usize,
    m: Vec<Bound>,
}

impl Dbm {
    /// Bytes of the bound matrix on the heap.
    pub fn heap_bytes(&self) -> usize {
        self.m.capacity() * size_of::<Bound>()
    }

    /// The zone where every clock is 0.
    pub fn zero(clocks: usize) -> Dbm {
        let dim = clocks + 1;
        Dbm {
            dim,
            m: vec![LE_ZERO; dim * dim],
        }
    }

    /// Every non-negative valuation.
    pub fn universe(clocks: usize) -> Dbm {
        let dim = clocks + 1;
        let mut m = vec![INF; dim * dim];
        for i in 0..dim {
            m[i * dim + i] = LE_ZERO;
            m[i] = LE_ZERO;
        }
        Dbm { dim, m }
    }

    /// Number of clocks (without the reference clock).
    pub fn clocks(&self) -> usize {
        self.dim - 1
    }

    /// The bound on `xi - xj`.
    pub fn get(&self, i: usize, j: usize) -> Bound {
        self.m[i * self.dim + j]
    }

    fn set(&mut self, i: usize, j: usize, b: Bound) {
        self.m[i * self.dim + j] = b;
    }

    /// The raw matrix, row by row (for hashing and storage).
    pub fn raw(&self) -> &[Bound] {
        &self.m
    }

    /// Rebuilds a zone from its raw matrix.
    pub fn from_raw(dim: usize, m: Vec<Bound>) -> Dbm {
        Dbm { dim, m }
    }

    /// Closes the matrix under shortest paths (Floyd–Warshall); afterwards
    /// every entry is the tightest bound. Returns `false` when empty.
    pub fn canonicalize(&mut self) -> bool {
        let n = self.dim;
        for k in 0..n {
            for i in 0..n {
                let ik = self.get(i, k);
                if ik == INF {
                    continue;
                }
                for j in 0..n {
                    let via = add(ik, self.get(k, j));
                    if via < self.get(i, j) {
                        self.set(i, j, via);
                    }
                }
            }
            if self.get(k, k) < LE_ZERO {
                self.set(0, 0, lt(0));
                return false;
            }
        }
        !self.is_empty()
    }

    /// Whether the (canonical) zone is empty.
    pub fn is_empty(&self) -> bool {
        (0..self.dim).any(|i| self.get(i, i) < LE_ZERO)
    }

    /// Lets time pass: removes upper bounds on every clock.
    pub fn up(&mut self) {
        for i in 1..self.dim {
            self.set(i, 0, INF);
        }
    }

    /// Lets time go back (the past of the zone): removes lower bounds.
    pub fn down(&mut self) {
        for j in 1..self.dim {
            self.set(0, j, LE_ZERO);
            for i in 1..self.dim {
                if self.get(i, j) < self.get(0, j) {
                    self.set(0, j, self.get(i, j));
                }
            }
        }
    }

    /// Resets clock `x` to 0 (canonical in, canonical out).
    pub fn reset(&mut self, x: usize) {
        for j in 0..self.dim {
            self.set(x, j, self.get(0, j));
            self.set(j, x, self.get(j, 0));
        }
        self.set(x, x, LE_ZERO);
    }

    /// Sets clock `x` to the value of clock `y` (canonical in and out).
    pub fn copy(&mut self, x: usize, y: usize) {
        if x == y {
            return;
        }
        for j in 0..self.dim {
            if j != x {
                self.set(x, j, self.get(y, j));
                self.set(j, x, self.get(j, y));
            }
        }
        self.set(x, y, LE_ZERO);
        self.set(y, x, LE_ZERO);
        self.set(x, x, LE_ZERO);
    }

    /// Frees clock `x` (any non-negative value), canonical in and out.
    pub fn free(&mut self, x: usize) {
        for j in 0..self.dim {
            if j != x {
                self.set(x, j, INF);
                self.set(j, x, self.get(j, 0));
            }
        }
        self.set(0, x, LE_ZERO);
    }

    /// Intersects with `xi - xj ≺ b`, keeping canonical form (incremental
    /// closure). Returns `false` when the result is empty.
    pub fn constrain(&mut self, i: usize, j: usize, b: Bound) -> bool {
        if b >= self.get(i, j) {
            return !self.is_empty();
        }
        if add(b, self.get(j, i)) < LE_ZERO {
            self.set(0, 0, lt(0));
            return false;
        }
        self.set(i, j, b);
        let n = self.dim;
        for a in 0..n {
            let ai = self.get(a, i);
            for c in 0..n {
                let via = add(add(ai, b), self.get(j, c));
                if via < self.get(a, c) {
                    self.set(a, c, via);
                }
            }
        }
        true
    }

    /// `x ≤ c`.
    pub fn upper(&mut self, x: usize, c: i64) -> bool {
        self.constrain(x, 0, le(c))
    }

    /// `x ≥ c`.
    pub fn lower(&mut self, x: usize, c: i64) -> bool {
        self.constrain(0, x, le(-c))
    }

    /// Whether `self ⊆ other` (both canonical, same clocks).
    pub fn included_in(&self, other: &Dbm) -> bool {
        self.m.iter().zip(&other.m).all(|(a, b)| a <= b)
    }

    /// Whether the zone intersects `xi - xj ≺ b`.
    pub fn intersects(&self, i: usize, j: usize, b: Bound) -> bool {
        add(b, self.get(j, i)) >= LE_ZERO
    }

    /// Extra⁺_LU extrapolation (Behrmann, Bouyer, Larsen, Pelánek 2006) with
    /// per-clock maximal lower (`l`) and upper (`u`) constants (`None`: the
    /// clock is never compared that way, i.e. −∞). Sound and complete for
    /// reachability with diagonal-free constraints; bounds the number of
    /// zones. Canonical in and out. With `c` the constant of a bound:
    ///
    /// - `∞` if `c_ij > L(xi)`, or `−c_0i > L(xi)`,
    /// - `∞` if `−c_0j > U(xj)` and `i ≠ 0`,
    /// - `< −U(xj)` if `−c_0j > U(xj)` and `i = 0`,
    /// - unchanged otherwise.
    pub fn extrapolate(&mut self, l: &[Option<i64>], u: &[Option<i64>]) {
        let n = self.dim;
        let bound_of = |k: &[Option<i64>], x: usize| {
            if x == 0 {
                Some(0)
            } else {
                k.get(x - 1).copied().flatten()
            }
        };
        let exceeds = |v: i64, k: Option<i64>| k.is_none_or(|k| v > k);
        // Row 0 (the lower bounds, read by every other row) is rewritten
        // last, so the matrix is changed in place.
        let mut changed = false;
        for i in (1..n).chain(std::iter::once(0)) {
            let li = bound_of(l, i);
            let low_i = -constant(self.get(0, i));
            for j in (0..n).filter(|&j| j != i) {
                let dij = self.get(i, j);
                let uj = bound_of(u, j);
                let low_j = -constant(self.get(0, j));
                let b = if (dij != INF && exceeds(constant(dij), li)) || exceeds(low_i, li) {
                    INF
                } else if exceeds(low_j, uj) {
                    if i == 0 {
                        uj.map_or(LE_ZERO, |k| lt(-k)).min(LE_ZERO)
                    } else {
                        INF
                    }
                } else {
                    dij
                };
                if b != dij {
                    self.set(i, j, b);
                    changed = true;
                }
            }
        }
        // An unchanged matrix is still canonical.
        if changed {
            self.canonicalize();
        }
    }

    /// The same zone with every constant multiplied by `k`.
    pub fn scaled(&self, k: i64) -> Dbm {
        let m = self
            .m
            .iter()
            .map(|&b| {
                if b == INF {
                    INF
                } else {
                    (constant(b).saturating_mul(k) << 1) | (b & 1)
                }
            })
            .collect();
        Dbm { dim: self.dim, m }
    }

    /// Some valuation of the zone, as integers in units of `1/scale` of the
    /// zone's unit, chosen clock by clock as low as possible: an integer
    /// point (`scale` 1) whenever the zone has one, else a point on the
    /// grid of `1/(2 * dim)`, which leaves room for strict bounds. `None`
    /// when empty.
    pub fn pick(&self) -> Option<(Vec<i64>, i64)> {
        if let Some(values) = self.pick_integer() {
            return Some((values, 1));
        }
        let scale = 2 * i64::try_from(self.dim).unwrap_or(i64::MAX / 4);
        self.scaled(scale).lowest().map(|v| (v, scale))
    }

    /// The lowest integer valuation of the zone (clock by clock), if it has
    /// one: on integers `x - y < c` is `x - y ≤ c - 1`, and a canonical
    /// zone whose bounds are all non-strict integers has integer vertices.
    pub fn pick_integer(&self) -> Option<Vec<i64>> {
        let m = self
            .m
            .iter()
            .map(|&b| {
                if b == INF || is_weak(b) {
                    b
                } else {
                    le(constant(b).saturating_sub(1))
                }
            })
            .collect();
        Dbm { dim: self.dim, m }.lowest()
    }

    /// The valuation chosen clock by clock as low as possible, when every
    /// bound is an integer one (the lowest value of a clock is then a
    /// constant of the canonical zone, or one more for a strict bound).
    fn lowest(&self) -> Option<Vec<i64>> {
        let mut z = self.clone();
        if !z.canonicalize() {
            return None;
        }
        let mut out = Vec::with_capacity(self.dim - 1);
        for x in 1..self.dim {
            let low = z.get(0, x);
            let v = if is_weak(low) {
                -constant(low)
            } else {
                -constant(low) + 1
            };
            let v = v.max(0);
            if !(z.constrain(x, 0, le(v)) && z.constrain(0, x, le(-v))) {
                return None;
            }
            out.push(v);
        }
        Some(out)
    }

    /// Whether a valuation (integers in units of `1/scale`) satisfies every
    /// constraint of the zone.
    pub fn contains(&self, values: &[i64], scale: i64) -> bool {
        let val = |x: usize| {
            if x == 0 {
                0
            } else {
                values.get(x - 1).copied().unwrap_or(0)
            }
        };
        (0..self.dim).all(|i| {
            (0..self.dim).all(|j| {
                let b = self.get(i, j);
                if b == INF {
                    return true;
                }
                let diff = val(i) - val(j);
                let c = constant(b).saturating_mul(scale);
                if is_weak(b) { diff <= c } else { diff < c }
            })
        })
    }
}

impl fmt::Debug for Dbm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let show = |b: Bound| {
            if b == INF {
                "∞".to_owned()
            } else {
                format!("{}{}", if is_weak(b) { "≤" } else { "<" }, constant(b))
            }
        };
        for i in 0..self.dim {
            let row: Vec<String> = (0..self.dim).map(|j| show(self.get(i, j))).collect();
            writeln!(f, "[{}]", row.join(" "))?;
        }
        Ok(())
    }
}
