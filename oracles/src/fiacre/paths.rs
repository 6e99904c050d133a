//! The transitions of a process instance in a state: Fiacre compiles a
//! `from` clause into one transition per way through its statement (each
//! `select` alternative, the taken branch of each `if`), enabled when its
//! `on` conditions hold; a transition carries at most one `wait`
//! interval (none: `[0,...[`, any time). [`paths`] runs the statement on
//! the current values of the variables and returns every enabled
//! transition with its effect.

use super::ast::{BinOp, Expr, Interval, Stmt};

/// Where a process instance's names live: the index of each variable it
/// reads or writes among the network's variables.
pub trait Scope {
    /// The variable `name` of the instance.
    fn slot(&self, name: &str) -> Result<usize, String>;
}

/// An enabled transition.
#[derive(Debug, Clone)]
pub struct Path {
    /// Its `wait` interval, if any.
    pub interval: Option<Interval>,
    /// Whether an `on` condition enables it (besides being in the state).
    pub guarded: bool,
    /// Its target state, by name (`loop`: the current one).
    pub target: String,
    /// The variables after it.
    pub vars: Vec<i64>,
}

/// The bound on `while` iterations in one transition.
const MAX_ITERATIONS: usize = 100_000;

struct Run<'a> {
    scope: &'a dyn Scope,
    here: &'a str,
    out: Vec<Path>,
    steps: usize,
}

/// Every enabled transition of the statement `body` from state `here`.
pub fn paths(
    scope: &dyn Scope,
    here: &str,
    body: &[Stmt],
    vars: &[i64],
) -> Result<Vec<Path>, String> {
    let mut run = Run {
        scope,
        here,
        out: Vec::new(),
        steps: 0,
    };
    let start = Path {
        interval: None,
        guarded: false,
        target: String::new(),
        vars: vars.to_vec(),
    };
    run.exec(body, &Cont::Done, start)?;
    Ok(run.out)
}

/// What is left to run after the current statements: a list of
/// statements, then what follows them (kept on the stack, so that
/// running a transition allocates nothing but its paths).
enum Cont<'a> {
    /// Nothing: the transition must have ended (`to` or `loop`).
    Done,
    /// These statements, then the rest.
    Then(&'a [Stmt], &'a Cont<'a>),
}

impl Run<'_> {
    /// Runs the statements `first`, then `rest`, on `p`.
    fn exec(&mut self, first: &[Stmt], rest: &Cont<'_>, mut p: Path) -> Result<(), String> {
        let Some((s, more)) = first.split_first() else {
            return match rest {
                Cont::Done => Err(format!(
                    "a transition from `{}` ends without `to` or `loop`",
                    self.here
                )),
                Cont::Then(next, after) => self.exec(next, after, p),
            };
        };
        self.steps += 1;
        if self.steps > MAX_ITERATIONS {
            return Err(format!("a transition from `{}` does not end", self.here));
        }
        let next = Cont::Then(more, rest);
        match s {
            Stmt::Null => self.exec(more, rest, p),
            Stmt::Assign(lhs, rhs) => {
                let values: Vec<i64> = rhs
                    .iter()
                    .map(|e| self.eval(e, &p.vars))
                    .collect::<Result<_, _>>()?;
                for (x, v) in lhs.iter().zip(values) {
                    let i = self.scope.slot(x)?;
                    p.vars[i] = v;
                }
                self.exec(more, rest, p)
            }
            Stmt::On(e) => {
                if self.eval(e, &p.vars)? == 0 {
                    return Ok(());
                }
                p.guarded = true;
                self.exec(more, rest, p)
            }
            Stmt::Wait(i) => {
                if p.interval.is_some() {
                    return Err(format!("two `wait` in one transition from `{}`", self.here));
                }
                p.interval = Some(*i);
                self.exec(more, rest, p)
            }
            Stmt::To(s) => {
                p.target.clone_from(s);
                self.out.push(p);
                Ok(())
            }
            Stmt::Loop => {
                p.target = self.here.to_owned();
                self.out.push(p);
                Ok(())
            }
            Stmt::Select(alts) => {
                for a in alts {
                    self.exec(a, &next, p.clone())?;
                }
                Ok(())
            }
            Stmt::If(arms, other) => {
                let mut body: &[Stmt] = other;
                for (c, b) in arms {
                    if self.eval(c, &p.vars)? != 0 {
                        body = b;
                        break;
                    }
                }
                self.exec(body, &next, p)
            }
            Stmt::While(c, b) => {
                if self.eval(c, &p.vars)? == 0 {
                    return self.exec(more, rest, p);
                }
                let again = Cont::Then(std::slice::from_ref(s), &next);
                self.exec(b, &again, p)
            }
        }
    }

    fn eval(&self, e: &Expr, vars: &[i64]) -> Result<i64, String> {
        Ok(match e {
            Expr::Int(v) => *v,
            Expr::Bool(b) => i64::from(*b),
            Expr::Var(x) => vars[self.scope.slot(x)?],
            Expr::Not(a) => i64::from(self.eval(a, vars)? == 0),
            Expr::Neg(a) => -self.eval(a, vars)?,
            Expr::Bin(op, a, b) => {
                let (x, y) = (self.eval(a, vars)?, self.eval(b, vars)?);
                binary(*op, x, y)?
            }
        })
    }
}

fn binary(op: BinOp, x: i64, y: i64) -> Result<i64, String> {
    Ok(match op {
        BinOp::Or => i64::from(x != 0 || y != 0),
        BinOp::And => i64::from(x != 0 && y != 0),
        BinOp::Cmp(c) => i64::from(crate::ta_sim::cmp(c, x, y)),
        BinOp::Add => x + y,
        BinOp::Sub => x - y,
        BinOp::Mul => x * y,
        BinOp::Div | BinOp::Mod if y == 0 => return Err("division by zero".to_owned()),
        BinOp::Div => x / y,
        BinOp::Mod => x % y,
    })
}
