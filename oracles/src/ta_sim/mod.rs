//! A small explicit-state interpreter of a [`Network`] for tests: it runs
//! the network's own expressions and statements (as the printers render
//! them) on explicit locations and integer variables, and the clocks
//! symbolically, as zones ([`zone`]: difference-bound matrices with the
//! maximal-constant extrapolation, each zone kept unless one already found
//! for the same locations and variables includes it), so that fine time
//! units (a 10 us `validate` against 20 ms periods) cost nothing. It checks
//! on the way what `tck-reach` and UPPAAL would refuse: a variable outside
//! its range, and an [`Network::urgency`] predicate that disagrees with
//! the urgent edges. What the GenoM3 networks do not use (arrays, `!=`
//! on a clock, a loop that does not end) is a problem too, and stops the
//! exploration.
//!
//! An oracle (it reads the network alone): `tests/differential` compares
//! the labels it reaches with those of the engines and of `tck-reach`.

pub(crate) mod zone;

use std::collections::{BTreeSet, HashMap, VecDeque};

use genom_model::timed_automata::{ClockConstraint, CmpOp, Edge, Expr, LValue, Network, Stmt};

use zone::Zone;

/// One symbolic state: locations, variables, and the clocks' zone.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
struct St {
    locs: Vec<u32>,
    vars: Vec<i64>,
    zone: Zone,
}

/// What the exploration found.
#[derive(Debug, Default)]
pub struct Reach {
    /// Every label of a location reached.
    pub labels: BTreeSet<String>,
    /// Symbolic states explored.
    pub states: usize,
    /// Whether every reachable symbolic state was explored.
    pub complete: bool,
    /// Problems found on the way (out-of-range values, urgency mismatch).
    pub problems: Vec<String>,
}

/// Whether `a op b` (also the Fiacre interpreter's comparisons).
pub(crate) fn cmp(op: CmpOp, a: i64, b: i64) -> bool {
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
    fn eval(&self, e: &Expr) -> Result<i64, String> {
        Ok(match e {
            Expr::Const(c) => *c,
            Expr::Var(v) => self.vars[v.0 as usize],
            Expr::Elem(..) => return Err("arrays are not used by the GenoM3 networks".into()),
            Expr::Local(n) => self
                .locals
                .iter()
                .rev()
                .find(|(m, _)| m == n)
                .map(|(_, v)| *v)
                .ok_or_else(|| format!("local `{n}` read before its declaration"))?,
            Expr::Add(items) => items
                .iter()
                .map(|x| self.eval(x))
                .sum::<Result<i64, String>>()?,
            Expr::Sub(a, b) => self.eval(a)? - self.eval(b)?,
            Expr::Cmp(op, a, b) => i64::from(cmp(*op, self.eval(a)?, self.eval(b)?)),
            Expr::Not(x) => i64::from(self.eval(x)? == 0),
            Expr::And(items) => {
                let mut all = true;
                for x in items {
                    all &= self.eval(x)? != 0;
                }
                i64::from(all)
            }
            Expr::Or(items) => {
                let mut any = false;
                for x in items {
                    any |= self.eval(x)? != 0;
                }
                i64::from(any)
            }
            Expr::Ite(c, a, b) => {
                if self.eval(c)? != 0 {
                    self.eval(a)?
                } else {
                    self.eval(b)?
                }
            }
        })
    }

    fn run(&mut self, list: &[Stmt], resets: &mut Vec<usize>) -> Result<(), String> {
        for s in list {
            match s {
                Stmt::Local(n, e) => {
                    let v = self.eval(e)?;
                    self.locals.push((n.clone(), v));
                }
                Stmt::Assign(lv, e) => {
                    let v = self.eval(e)?;
                    match lv {
                        LValue::Var(x) => self.vars[x.0 as usize] = v,
                        LValue::Elem(..) => return Err("arrays are not used".into()),
                        LValue::Local(n) => {
                            let slot = self.locals.iter_mut().rev().find(|(m, _)| m == n);
                            let slot = slot.ok_or_else(|| {
                                format!("local `{n}` assigned before its declaration")
                            })?;
                            slot.1 = v;
                        }
                    }
                }
                Stmt::If(c, a, b) => {
                    if self.eval(c)? != 0 {
                        self.run(a, resets)?;
                    } else {
                        self.run(b, resets)?;
                    }
                }
                Stmt::While(c, body) => {
                    let mut n = 0;
                    while self.eval(c)? != 0 {
                        self.run(body, resets)?;
                        n += 1;
                        if n >= 10_000 {
                            return Err("a while loop that does not end".into());
                        }
                    }
                }
                Stmt::Reset(c) => resets.push(c.0 as usize),
            }
        }
        Ok(())
    }
}

fn constrain(z: &mut Zone, cs: &[ClockConstraint]) -> Result<(), String> {
    for c in cs {
        z.constrain(c.clock.0 as usize, c.op, c.bound)?;
    }
    Ok(())
}

struct Sim<'a> {
    net: &'a Network,
    /// Per clock: the largest constant it is compared with.
    max: Vec<i64>,
}

impl Sim<'_> {
    fn int_guard(&self, e: &Edge, vars: &[i64]) -> Result<bool, String> {
        let mut vars = vars.to_vec();
        let env = Env {
            vars: &mut vars,
            locals: Vec::new(),
        };
        Ok(env.eval(&e.guard)? != 0)
    }

    /// Intersects `z` with the invariants of `locs`.
    fn invariants(&self, locs: &[u32], z: &mut Zone) -> Result<(), String> {
        for (p, &l) in self.net.processes.iter().zip(locs) {
            constrain(z, &p.locations[l as usize].invariant)?;
        }
        Ok(())
    }

    fn committed(&self, locs: &[u32]) -> bool {
        self.net
            .processes
            .iter()
            .zip(locs)
            .any(|(p, &l)| p.locations[l as usize].committed)
    }

    /// The edges whose integer guards hold in locations `locs` with
    /// variables `vars` (only committed processes' in a committed state),
    /// with their processes.
    fn edges<'n>(&'n self, locs: &[u32], vars: &[i64]) -> Result<Vec<(usize, &'n Edge)>, String> {
        let committed = self.committed(locs);
        let mut out = Vec::new();
        for (k, p) in self.net.processes.iter().enumerate() {
            let here = locs[k];
            if committed && !p.locations[here as usize].committed {
                continue;
            }
            for e in p.edges.iter().filter(|e| e.from.0 == here) {
                if self.int_guard(e, vars)? {
                    out.push((k, e));
                }
            }
        }
        Ok(out)
    }

    /// Whether time may pass in locations `locs` with variables `vars`.
    fn may_delay(&self, locs: &[u32], vars: &[i64]) -> Result<bool, String> {
        let urgent = self.edges(locs, vars)?.iter().any(|(_, e)| e.urgent);
        Ok(!self.committed(locs) && !urgent)
    }

    /// Time passes (when it may), under the invariants; extrapolated.
    fn delay(&self, s: &mut St) -> Result<(), String> {
        if self.may_delay(&s.locs, &s.vars)? {
            s.zone.up();
        }
        self.invariants(&s.locs, &mut s.zone)?;
        if !s.zone.is_empty() {
            s.zone.extrapolate(&self.max);
        }
        Ok(())
    }

    /// The successors of `s` into `out`; the problems of range and urgency
    /// into `problems`; Err for what the interpreter cannot run.
    fn successors(
        &self,
        s: &St,
        out: &mut Vec<St>,
        problems: &mut Vec<String>,
    ) -> Result<(), String> {
        let edges = self.edges(&s.locs, &s.vars)?;
        let urgent = edges.iter().any(|(_, e)| e.urgent);
        for (k, e) in edges {
            let mut zone = s.zone.clone();
            constrain(&mut zone, &e.clock_guard)?;
            if zone.is_empty() {
                continue;
            }
            let mut n = s.clone();
            let mut resets = Vec::new();
            let mut env = Env {
                vars: &mut n.vars,
                locals: Vec::new(),
            };
            env.run(&e.statements, &mut resets)?;
            for c in resets {
                zone.reset(c);
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
            self.invariants(&n.locs, &mut zone)?;
            if zone.is_empty() {
                continue;
            }
            n.zone = zone;
            self.delay(&mut n)?;
            if !n.zone.is_empty() {
                out.push(n);
            }
        }
        let mut vars = s.vars.clone();
        let env = Env {
            vars: &mut vars,
            locals: Vec::new(),
        };
        let predicate = env.eval(&self.net.urgency)? != 0;
        if predicate != urgent && !self.committed(&s.locs) {
            problems.push(format!(
                "urgency predicate {predicate}, urgent edges enabled {urgent}"
            ));
        }
        Ok(())
    }
}

/// The largest constant each clock is compared with (0 for none).
fn max_constants(net: &Network) -> Vec<i64> {
    let mut max = vec![0; net.clocks.len()];
    let mut see = |cs: &[ClockConstraint]| {
        for c in cs {
            let m = &mut max[c.clock.0 as usize];
            *m = (*m).max(c.bound.abs());
        }
    };
    for p in &net.processes {
        for l in &p.locations {
            see(&l.invariant);
        }
        for e in &p.edges {
            see(&e.clock_guard);
        }
    }
    max
}

/// The initial location of every process.
fn initial_locations(net: &Network) -> Result<Vec<u32>, String> {
    net.processes
        .iter()
        .map(|p| {
            let i = p.locations.iter().position(|l| l.initial);
            let i = i.ok_or_else(|| format!("process `{}` has no initial location", p.name))?;
            u32::try_from(i).map_err(|e| e.to_string())
        })
        .collect()
}

/// Explores the network (at most `limit` symbolic states). What the
/// interpreter cannot run ends the exploration, incomplete, with a
/// problem saying so.
pub fn explore(net: &Network, limit: usize) -> Reach {
    let mut reach = Reach::default();
    if let Err(e) = explore_into(net, limit, &mut reach) {
        reach.complete = false;
        reach.problems.push(e);
    }
    reach
}

fn explore_into(net: &Network, limit: usize, reach: &mut Reach) -> Result<(), String> {
    let sim = Sim {
        net,
        max: max_constants(net),
    };
    let mut init = St {
        locs: initial_locations(net)?,
        vars: net.vars.iter().map(|v| v.init).collect(),
        zone: Zone::zero(net.clocks.len()),
    };
    sim.delay(&mut init)?;
    if init.zone.is_empty() {
        reach.complete = true;
        return Ok(());
    }
    // Per locations and variables: the zones found (none includes another
    // found before it).
    let mut seen: HashMap<(Vec<u32>, Vec<i64>), Vec<Zone>> = HashMap::new();
    let mut queue = VecDeque::new();
    seen.insert(
        (init.locs.clone(), init.vars.clone()),
        vec![init.zone.clone()],
    );
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
            return Ok(());
        }
        next.clear();
        sim.successors(&s, &mut next, &mut reach.problems)?;
        if reach.problems.len() > 10 {
            return Ok(());
        }
        for n in next.drain(..) {
            let zones = seen.entry((n.locs.clone(), n.vars.clone())).or_default();
            if zones.iter().any(|z| n.zone.within(z)) {
                continue;
            }
            zones.retain(|z| !z.within(&n.zone));
            zones.push(n.zone.clone());
            queue.push_back(n);
        }
    }
    reach.complete = true;
    Ok(())
}
