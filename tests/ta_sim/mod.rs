//! A small explicit-state interpreter of a [`Network`] for tests: it runs
//! the network's own expressions and statements (as the printers render
//! them), with time advancing in half units (a digitisation of the clock
//! values: every state it reaches is reachable, but it may miss states
//! that need other fractional parts; the GenoM3 networks' constraints are
//! met at integer or half-integer instants in the fixtures). It checks on
//! the way what `tck-reach` and UPPAAL would refuse: a variable outside its
//! range, and an [`Network::urgency`] predicate that disagrees with the
//! urgent edges.

#![allow(dead_code, clippy::expect_used, clippy::unwrap_used)]

use std::collections::{BTreeSet, HashSet, VecDeque};

use genom_model::timed_automata::{ClockConstraint, CmpOp, Edge, Expr, LValue, Network, Stmt};

/// One state: locations, variables, clocks (in half units, capped).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
struct St {
    locs: Vec<u32>,
    vars: Vec<i64>,
    clocks: Vec<i64>,
}

/// What the exploration found.
#[derive(Debug, Default)]
pub struct Reach {
    /// Every label of a location reached.
    pub labels: BTreeSet<String>,
    /// States explored.
    pub states: usize,
    /// Whether every reachable state (of the digitisation) was explored.
    pub complete: bool,
    /// Problems found on the way (out-of-range values, urgency mismatch).
    pub problems: Vec<String>,
}

fn cmp(op: CmpOp, a: i64, b: i64) -> bool {
    match op {
        CmpOp::Eq => a == b,
        CmpOp::Ne => a != b,
        CmpOp::Lt => a < b,
        CmpOp::Le => a <= b,
        CmpOp::Gt => a > b,
        CmpOp::Ge => a >= b,
    }
}

struct Env<'a> {
    vars: &'a mut Vec<i64>,
    locals: Vec<(String, i64)>,
}

impl Env<'_> {
    fn eval(&self, e: &Expr) -> i64 {
        match e {
            Expr::Const(c) => *c,
            Expr::Var(v) => self.vars[v.0 as usize],
            Expr::Elem(..) => panic!("arrays are not used by the GenoM3 networks"),
            Expr::Local(n) => self
                .locals
                .iter()
                .rev()
                .find(|(m, _)| m == n)
                .map(|(_, v)| *v)
                .expect("a declared local"),
            Expr::Add(items) => items.iter().map(|x| self.eval(x)).sum(),
            Expr::Sub(a, b) => self.eval(a) - self.eval(b),
            Expr::Cmp(op, a, b) => i64::from(cmp(*op, self.eval(a), self.eval(b))),
            Expr::Not(x) => i64::from(self.eval(x) == 0),
            Expr::And(items) => i64::from(items.iter().all(|x| self.eval(x) != 0)),
            Expr::Or(items) => i64::from(items.iter().any(|x| self.eval(x) != 0)),
            Expr::Ite(c, a, b) => {
                if self.eval(c) != 0 {
                    self.eval(a)
                } else {
                    self.eval(b)
                }
            }
        }
    }

    fn run(&mut self, list: &[Stmt], resets: &mut Vec<usize>) {
        for s in list {
            match s {
                Stmt::Local(n, e) => {
                    let v = self.eval(e);
                    self.locals.push((n.clone(), v));
                }
                Stmt::Assign(lv, e) => {
                    let v = self.eval(e);
                    match lv {
                        LValue::Var(x) => self.vars[x.0 as usize] = v,
                        LValue::Elem(..) => panic!("arrays are not used"),
                        LValue::Local(n) => {
                            let slot = self
                                .locals
                                .iter_mut()
                                .rev()
                                .find(|(m, _)| m == n)
                                .expect("a declared local");
                            slot.1 = v;
                        }
                    }
                }
                Stmt::If(c, a, b) => {
                    if self.eval(c) != 0 {
                        self.run(a, resets);
                    } else {
                        self.run(b, resets);
                    }
                }
                Stmt::While(c, body) => {
                    let mut n = 0;
                    while self.eval(c) != 0 {
                        self.run(body, resets);
                        n += 1;
                        assert!(n < 10_000, "a while loop that does not end");
                    }
                }
                Stmt::Reset(c) => resets.push(c.0 as usize),
            }
        }
    }
}

fn holds(cs: &[ClockConstraint], clocks: &[i64]) -> bool {
    cs.iter()
        .all(|c| cmp(c.op, clocks[c.clock.0 as usize], 2 * c.bound))
}

struct Sim<'a> {
    net: &'a Network,
    cap: i64,
}

impl Sim<'_> {
    fn guard(&self, e: &Edge, s: &St) -> bool {
        let mut vars = s.vars.clone();
        let env = Env {
            vars: &mut vars,
            locals: Vec::new(),
        };
        env.eval(&e.guard) != 0 && holds(&e.clock_guard, &s.clocks)
    }

    fn invariants(&self, s: &St) -> bool {
        self.net
            .processes
            .iter()
            .zip(&s.locs)
            .all(|(p, &l)| holds(&p.locations[l as usize].invariant, &s.clocks))
    }

    fn committed(&self, s: &St) -> bool {
        self.net
            .processes
            .iter()
            .zip(&s.locs)
            .any(|(p, &l)| p.locations[l as usize].committed)
    }

    fn successors(&self, s: &St, out: &mut Vec<St>, problems: &mut Vec<String>) {
        let committed = self.committed(s);
        let mut urgent = false;
        for (k, p) in self.net.processes.iter().enumerate() {
            let here = s.locs[k];
            if committed && !p.locations[here as usize].committed {
                continue;
            }
            for e in p.edges.iter().filter(|e| e.from.0 == here) {
                if !self.guard(e, s) {
                    continue;
                }
                urgent |= e.urgent;
                let mut n = s.clone();
                let mut resets = Vec::new();
                let mut env = Env {
                    vars: &mut n.vars,
                    locals: Vec::new(),
                };
                env.run(&e.statements, &mut resets);
                for c in resets {
                    n.clocks[c] = 0;
                }
                n.locs[k] = e.to.0;
                for (v, x) in self.net.vars.iter().zip(&n.vars) {
                    if *x < v.min || *x > v.max {
                        problems.push(format!(
                            "{} = {x} out of [{}, {}] after `{}`",
                            v.name, v.min, v.max, e.description
                        ));
                    }
                }
                if self.invariants(&n) {
                    out.push(n);
                }
            }
        }
        let mut vars = s.vars.clone();
        let env = Env {
            vars: &mut vars,
            locals: Vec::new(),
        };
        let predicate = env.eval(&self.net.urgency) != 0;
        if predicate != urgent && !committed {
            problems.push(format!(
                "urgency predicate {predicate}, urgent edges enabled {urgent}"
            ));
        }
        if committed || urgent {
            return;
        }
        let mut d = s.clone();
        for c in &mut d.clocks {
            *c = (*c + 1).min(self.cap);
        }
        if self.invariants(&d) && d != *s {
            out.push(d);
        }
    }
}

/// Explores the network (at most `limit` states).
pub fn explore(net: &Network, limit: usize) -> Reach {
    let sim = Sim {
        net,
        cap: 2 * net.horizon + 1,
    };
    let init = St {
        locs: net
            .processes
            .iter()
            .map(|p| {
                let i = p
                    .locations
                    .iter()
                    .position(|l| l.initial)
                    .expect("an initial location");
                u32::try_from(i).unwrap()
            })
            .collect(),
        vars: net.vars.iter().map(|v| v.init).collect(),
        clocks: vec![0; net.clocks.len()],
    };
    let mut seen = HashSet::new();
    let mut queue = VecDeque::new();
    let mut reach = Reach::default();
    seen.insert(init.clone());
    queue.push_back(init);
    let mut next = Vec::new();
    while let Some(s) = queue.pop_front() {
        reach.states += 1;
        for (p, &l) in net.processes.iter().zip(&s.locs) {
            reach
                .labels
                .extend(p.locations[l as usize].labels.iter().cloned());
        }
        if reach.states >= limit {
            return reach;
        }
        next.clear();
        sim.successors(&s, &mut next, &mut reach.problems);
        if reach.problems.len() > 10 {
            return reach;
        }
        for n in next.drain(..) {
            if seen.insert(n.clone()) {
                queue.push_back(n);
            }
        }
    }
    reach.complete = true;
    reach
}
