//! Expressions and statements over the integer variables of a network:
//! constructors that fold constants, so that guards and updates stay small.

use crate::timed_automata::{ClockId, VarId};

/// A comparison operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum CmpOp {
    /// `==`
    Eq,
    /// `!=`
    Ne,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
}

impl CmpOp {
    /// The C spelling (both printers use it).
    pub fn symbol(self) -> &'static str {
        match self {
            CmpOp::Eq => "==",
            CmpOp::Ne => "!=",
            CmpOp::Lt => "<",
            CmpOp::Le => "<=",
            CmpOp::Gt => ">",
            CmpOp::Ge => ">=",
        }
    }

    /// The negated operator.
    pub fn negate(self) -> CmpOp {
        match self {
            CmpOp::Eq => CmpOp::Ne,
            CmpOp::Ne => CmpOp::Eq,
            CmpOp::Lt => CmpOp::Ge,
            CmpOp::Le => CmpOp::Gt,
            CmpOp::Gt => CmpOp::Le,
            CmpOp::Ge => CmpOp::Lt,
        }
    }

    pub(super) fn eval(self, a: i64, b: i64) -> bool {
        match self {
            CmpOp::Eq => a == b,
            CmpOp::Ne => a != b,
            CmpOp::Lt => a < b,
            CmpOp::Le => a <= b,
            CmpOp::Gt => a > b,
            CmpOp::Ge => a >= b,
        }
    }
}

/// An integer expression over the network's integer variables (booleans are
/// integers: 0 is false, anything else true). Built through the smart
/// constructors, which fold constants.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Expr {
    /// A constant.
    Const(i64),
    /// A scalar variable.
    Var(VarId),
    /// An element of an array variable.
    Elem(VarId, Box<Expr>),
    /// A local variable of the statement being executed.
    Local(String),
    /// A sum.
    Add(Vec<Expr>),
    /// A difference.
    Sub(Box<Expr>, Box<Expr>),
    /// A comparison (0 or 1).
    Cmp(CmpOp, Box<Expr>, Box<Expr>),
    /// Negation (0 or 1).
    Not(Box<Expr>),
    /// Conjunction (0 or 1).
    And(Vec<Expr>),
    /// Disjunction (0 or 1).
    Or(Vec<Expr>),
    /// `if c then a else b`.
    Ite(Box<Expr>, Box<Expr>, Box<Expr>),
}

impl Expr {
    /// True.
    pub const TRUE: Expr = Expr::Const(1);
    /// False.
    pub const FALSE: Expr = Expr::Const(0);

    /// A constant.
    pub fn int(v: i64) -> Expr {
        Expr::Const(v)
    }

    /// A scalar variable.
    pub fn var(v: VarId) -> Expr {
        Expr::Var(v)
    }

    /// An array element with a constant index.
    pub fn elem(v: VarId, i: i64) -> Expr {
        Expr::Elem(v, Box::new(Expr::Const(i)))
    }

    /// An array element with a computed index.
    pub fn elem_at(v: VarId, i: Expr) -> Expr {
        Expr::Elem(v, Box::new(i))
    }

    /// The constant value, if constant.
    pub fn as_const(&self) -> Option<i64> {
        match self {
            Expr::Const(c) => Some(*c),
            _ => None,
        }
    }

    /// Whether the expression is the constant true.
    pub fn is_true(&self) -> bool {
        self.as_const().is_some_and(|c| c != 0)
    }

    /// Whether the expression is the constant false.
    pub fn is_false(&self) -> bool {
        self.as_const() == Some(0)
    }

    /// Whether the expression's value is always 0 or 1.
    pub fn is_boolean(&self) -> bool {
        matches!(
            self,
            Expr::Cmp(..) | Expr::Not(_) | Expr::And(_) | Expr::Or(_) | Expr::Const(0 | 1)
        )
    }

    /// A comparison, folded when both sides are constants.
    pub fn cmp(op: CmpOp, a: Expr, b: Expr) -> Expr {
        match (a.as_const(), b.as_const()) {
            (Some(x), Some(y)) => Expr::bool(op.eval(x, y)),
            _ => Expr::Cmp(op, Box::new(a), Box::new(b)),
        }
    }

    /// `a == b`.
    pub fn eq(a: Expr, b: Expr) -> Expr {
        Expr::cmp(CmpOp::Eq, a, b)
    }

    /// `a != b`.
    pub fn ne(a: Expr, b: Expr) -> Expr {
        Expr::cmp(CmpOp::Ne, a, b)
    }

    /// A boolean constant.
    pub fn bool(b: bool) -> Expr {
        Expr::Const(i64::from(b))
    }

    /// Negation, folded.
    pub fn negation(e: Expr) -> Expr {
        match e {
            Expr::Const(c) => Expr::bool(c == 0),
            Expr::Not(inner) if inner.is_boolean() => *inner,
            Expr::Cmp(op, a, b) => Expr::Cmp(op.negate(), a, b),
            other => Expr::Not(Box::new(other)),
        }
    }

    /// Conjunction, flattened and folded.
    pub fn and(items: impl IntoIterator<Item = Expr>) -> Expr {
        let mut out = Vec::new();
        for e in items {
            match e {
                Expr::And(inner) => out.extend(inner),
                e if e.is_true() => {}
                e if e.is_false() => return Expr::FALSE,
                e => out.push(e),
            }
        }
        dedup_keep_order(&mut out);
        match out.len() {
            0 => Expr::TRUE,
            1 => out.pop().unwrap_or(Expr::TRUE),
            _ => Expr::And(out),
        }
    }

    /// Disjunction, flattened and folded.
    pub fn or(items: impl IntoIterator<Item = Expr>) -> Expr {
        let mut out = Vec::new();
        for e in items {
            match e {
                Expr::Or(inner) => out.extend(inner),
                e if e.is_false() => {}
                e if e.is_true() => return Expr::TRUE,
                e => out.push(e),
            }
        }
        dedup_keep_order(&mut out);
        match out.len() {
            0 => Expr::FALSE,
            1 => out.pop().unwrap_or(Expr::FALSE),
            _ => Expr::Or(out),
        }
    }

    /// A sum, folded.
    pub fn add(items: impl IntoIterator<Item = Expr>) -> Expr {
        let mut constant = 0;
        let mut out = Vec::new();
        for e in items {
            match e {
                Expr::Const(c) => constant += c,
                Expr::Add(inner) => out.extend(inner),
                e => out.push(e),
            }
        }
        if constant != 0 || out.is_empty() {
            out.push(Expr::Const(constant));
        }
        if out.len() == 1 {
            out.pop().unwrap_or(Expr::Const(0))
        } else {
            Expr::Add(out)
        }
    }

    /// A difference.
    pub fn minus(a: Expr, b: Expr) -> Expr {
        match (a.as_const(), b.as_const()) {
            (Some(x), Some(y)) => Expr::Const(x - y),
            (_, Some(0)) => a,
            _ => Expr::Sub(Box::new(a), Box::new(b)),
        }
    }

    /// `if c then a else b`, folded.
    pub fn ite(c: Expr, a: Expr, b: Expr) -> Expr {
        if c.is_true() {
            a
        } else if c.is_false() || a == b {
            b
        } else if a == Expr::Const(1) && b == Expr::Const(0) && c.is_boolean() {
            c
        } else {
            Expr::Ite(Box::new(c), Box::new(a), Box::new(b))
        }
    }

    /// `lo <= e <= hi` (false when the interval is empty).
    pub fn within(e: &Expr, lo: i64, hi: i64) -> Expr {
        if lo > hi {
            Expr::FALSE
        } else if lo == hi {
            Expr::eq(e.clone(), Expr::Const(lo))
        } else {
            Expr::and([
                Expr::cmp(CmpOp::Ge, e.clone(), Expr::Const(lo)),
                Expr::cmp(CmpOp::Le, e.clone(), Expr::Const(hi)),
            ])
        }
    }
}

fn dedup_keep_order(v: &mut Vec<Expr>) {
    let mut seen: Vec<Expr> = Vec::new();
    v.retain(|e| {
        if seen.contains(e) {
            false
        } else {
            seen.push(e.clone());
            true
        }
    });
}

/// What a statement assigns.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum LValue {
    /// A scalar variable.
    Var(VarId),
    /// An array element.
    Elem(VarId, Expr),
    /// A local variable.
    Local(String),
}

/// A statement of an edge. Local variables are declared once per edge
/// statement, with names unique in it and distinct from every global name.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Stmt {
    /// Declares a local integer variable with its initial value.
    Local(String, Expr),
    /// An integer assignment.
    Assign(LValue, Expr),
    /// `if c then ... else ... end`.
    If(Expr, Vec<Stmt>, Vec<Stmt>),
    /// `while c do ... end`.
    While(Expr, Vec<Stmt>),
    /// Resets a clock to 0.
    Reset(ClockId),
}

impl Stmt {
    /// `v = e`.
    pub fn set(v: VarId, e: Expr) -> Stmt {
        Stmt::Assign(LValue::Var(v), e)
    }

    /// `v[i] = e`.
    pub fn set_elem(v: VarId, i: i64, e: Expr) -> Stmt {
        Stmt::Assign(LValue::Elem(v, Expr::Const(i)), e)
    }

    /// `if c then a else b end`, folded; pushed onto `out`.
    pub fn push_if(out: &mut Vec<Stmt>, c: Expr, a: Vec<Stmt>, b: Vec<Stmt>) {
        if c.is_true() {
            out.extend(a);
        } else if c.is_false() {
            out.extend(b);
        } else if !(a.is_empty() && b.is_empty()) {
            out.push(Stmt::If(c, a, b));
        }
    }
}
