//! The exploration of a parsed Fiacre model: its instances (the root
//! component's `par`), its shared variables, and the reachable symbolic
//! states, clocks as zones ([`crate::ta_sim`]'s difference-bound
//! matrices).
//!
//! Time, as Fiacre defines it (a transition's `wait [a,b]` counts from the
//! moment the transition became enabled; it may fire once `a` has passed
//! and must fire, or be disabled, before `b` passes; `wait [0,0]` makes it
//! urgent), read with **one clock per process instance**: the time since
//! the instance last moved. That clock is the transition's own exactly
//! when the transition is enabled as long as its instance stays in its
//! state, i.e. has no `on` condition; so a transition with an `on` may
//! only have `wait [0,0]` (urgent: no time passes while it is enabled) or
//! no `wait` at all (any time), and a model outside that subset is an
//! error rather than a different reading.

use std::collections::{BTreeSet, HashMap, VecDeque};

use genom_model::timed_automata::CmpOp;

use super::ast::{Arg, Expr, Interval, Program, Stmt};
use super::paths::{Path, Scope, paths};
use crate::ta_sim::zone::Zone;

/// A process instance of the root component.
struct Inst {
    /// The process's name (made unique among the instances).
    name: String,
    states: Vec<String>,
    init: usize,
    /// Per state, its `from` statement.
    froms: Vec<Option<Vec<Stmt>>>,
    /// Each name of the process: its variable among the network's.
    names: HashMap<String, usize, Fnv>,
}

impl Scope for Inst {
    fn slot(&self, name: &str) -> Result<usize, String> {
        self.names
            .get(name)
            .copied()
            .ok_or_else(|| format!("process `{}` has no variable `{name}`", self.name))
    }
}

/// The FNV-1a hash of a variable's name: names are looked up at every
/// statement, and they are short (SipHash's guarantees are not needed).
#[derive(Default, Clone, Copy)]
struct Fnv;

/// FNV-1a's state.
struct FnvHasher(u64);

impl std::hash::BuildHasher for Fnv {
    type Hasher = FnvHasher;
    fn build_hasher(&self) -> FnvHasher {
        FnvHasher(0xcbf2_9ce4_8422_2325)
    }
}

impl std::hash::Hasher for FnvHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    }
}

/// A Fiacre model ready to explore.
pub struct Net {
    insts: Vec<Inst>,
    init_vars: Vec<i64>,
    /// Per instance and state, the largest constant its clock is compared
    /// with there (its clock is reset when it leaves: elsewhere it is not
    /// read).
    max: Vec<Vec<i64>>,
}

/// What [`Net::explore`] found.
#[derive(Debug, Default)]
pub struct Reach {
    /// Every (instance, state) reached.
    pub reached: BTreeSet<(String, String)>,
    /// The *strict* (instance, state) pairs some run stays in for a
    /// positive time (see [`Net::explore`]).
    pub lingered: BTreeSet<(String, String)>,
    /// Symbolic states explored.
    pub states: usize,
    /// Whether every reachable symbolic state was explored.
    pub complete: bool,
}

#[derive(Clone, PartialEq, Eq, Hash)]
struct Key {
    locs: Vec<usize>,
    vars: Vec<i64>,
}

fn constant(e: &Expr) -> Result<i64, String> {
    match e {
        Expr::Int(v) => Ok(*v),
        Expr::Bool(b) => Ok(i64::from(*b)),
        Expr::Neg(a) => Ok(-constant(a)?),
        _ => Err("an initial value or argument must be a constant".to_owned()),
    }
}

impl Net {
    /// The root component of `prog` (its `root` line, else its last
    /// component), instantiated.
    pub fn new(prog: &Program) -> Result<Net, String> {
        let root = match &prog.root {
            Some(r) => prog.components.iter().find(|c| &c.name == r),
            None => prog.components.last(),
        }
        .ok_or("no root component")?;
        let mut vars: HashMap<String, usize> = HashMap::new();
        let mut init_vars = Vec::new();
        for (name, _, init) in &root.vars {
            vars.insert(name.clone(), init_vars.len());
            init_vars.push(init.as_ref().map_or(Ok(0), constant)?);
        }
        let mut insts: Vec<Inst> = Vec::new();
        for inst in &root.par {
            let proc_ = prog
                .processes
                .iter()
                .find(|p| p.name == inst.name)
                .ok_or_else(|| format!("`{}` is not a process", inst.name))?;
            if proc_.params.len() != inst.args.len() {
                return Err(format!("`{}`: wrong number of arguments", inst.name));
            }
            let mut names = HashMap::with_hasher(Fnv);
            for (p, a) in proc_.params.iter().zip(&inst.args) {
                let slot = match (p.by_ref, a) {
                    (true, Arg::Ref(v)) => {
                        *vars.get(v).ok_or_else(|| format!("no variable `{v}`"))?
                    }
                    (false, Arg::Value(e)) => {
                        init_vars.push(constant(e)?);
                        init_vars.len() - 1
                    }
                    _ => {
                        return Err(format!(
                            "`{}`: argument `{}` passed the wrong way",
                            inst.name, p.name
                        ));
                    }
                };
                names.insert(p.name.clone(), slot);
            }
            for (v, init) in &proc_.vars {
                names.insert(v.clone(), init_vars.len());
                init_vars.push(init.as_ref().map_or(Ok(0), constant)?);
            }
            let state = |s: &str| proc_.states.iter().position(|x| x == s);
            let init = match &proc_.init {
                Some(s) => state(s).ok_or_else(|| format!("no state `{s}`"))?,
                None => 0,
            };
            let mut froms = vec![None; proc_.states.len()];
            for (s, body) in &proc_.froms {
                let k = state(s).ok_or_else(|| format!("`{}`: no state `{s}`", proc_.name))?;
                if froms[k].is_some() {
                    return Err(format!("`{}`: two `from {s}`", proc_.name));
                }
                froms[k] = Some(body.clone());
            }
            let mut name = proc_.name.clone();
            let mut n = 2;
            while insts.iter().any(|i| i.name == name) {
                name = format!("{}_{n}", proc_.name);
                n += 1;
            }
            insts.push(Inst {
                name,
                states: proc_.states.clone(),
                init,
                froms,
                names,
            });
        }
        let max = insts.iter().map(max_constant).collect();
        Ok(Net {
            insts,
            init_vars,
            max,
        })
    }

    /// The enabled transitions of instance `p` in `key`, checked against
    /// the subset (see the module doc).
    fn enabled(&self, p: usize, key: &Key) -> Result<Vec<Path>, String> {
        let inst = &self.insts[p];
        let here = &inst.states[key.locs[p]];
        let Some(body) = &inst.froms[key.locs[p]] else {
            return Ok(Vec::new());
        };
        let out = paths(inst, here, body, &key.vars)?;
        for path in &out {
            if path.guarded && path.interval.is_some_and(|i| !urgent(i)) {
                return Err(format!(
                    "`{}` from `{here}`: a `wait` other than [0,0] under an `on` condition is outside the interpreted subset",
                    inst.name
                ));
            }
            if !inst.states.contains(&path.target) {
                return Err(format!("`{}`: no state `{}`", inst.name, path.target));
            }
        }
        Ok(out)
    }

    /// Lets time pass in `key` from `zone`, as far as the enabled
    /// transitions allow; `None` when an urgent one is enabled.
    fn delay(&self, key: &Key, zone: &mut Zone, all: &[Vec<Path>]) -> Result<(), String> {
        if all
            .iter()
            .flatten()
            .any(|p| p.guarded && p.interval.is_some_and(urgent))
        {
            return Ok(());
        }
        zone.up();
        for (p, list) in all.iter().enumerate() {
            for path in list {
                if let Some(Interval {
                    hi: Some(hi),
                    hi_open,
                    ..
                }) = path.interval
                {
                    let op = if hi_open { CmpOp::Lt } else { CmpOp::Le };
                    zone.constrain(p, op, hi)?;
                }
            }
        }
        let _ = key;
        Ok(())
    }

    /// Explores every reachable symbolic state (at most `max_states`).
    /// `strict` lists (instance, state) pairs: a run ends as soon as time
    /// passes while an instance is in such a state (that it could is
    /// recorded in [`Reach::lingered`]); so the exploration reads the
    /// model's runs up to the first time one of them is occupied for a
    /// positive time.
    pub fn explore(&self, strict: &[(String, String)], max_states: usize) -> Result<Reach, String> {
        let strict: Vec<(usize, usize)> = strict
            .iter()
            .filter_map(|(i, s)| {
                let p = self.insts.iter().position(|x| &x.name == i)?;
                Some((p, self.insts[p].states.iter().position(|x| x == s)?))
            })
            .collect();
        let mut reach = Reach {
            complete: true,
            ..Reach::default()
        };
        let key = Key {
            locs: self.insts.iter().map(|i| i.init).collect(),
            vars: self.init_vars.clone(),
        };
        let mut seen: HashMap<Key, Vec<Zone>> = HashMap::new();
        let mut queue = VecDeque::new();
        self.note(&key, &mut reach);
        if let Some(z) = self.settle(&key, Zone::zero(self.insts.len()), &strict, &mut reach)? {
            seen.entry(key.clone()).or_default().push(z.clone());
            queue.push_back((key, z));
        }
        while let Some((key, zone)) = queue.pop_front() {
            reach.states += 1;
            if reach.states > max_states {
                reach.complete = false;
                break;
            }
            let all: Vec<Vec<Path>> = (0..self.insts.len())
                .map(|p| self.enabled(p, &key))
                .collect::<Result<_, _>>()?;
            for (p, list) in all.iter().enumerate() {
                for path in list {
                    let Some((next, z)) = self.fire(&key, &zone, p, path)? else {
                        continue;
                    };
                    self.note(&next, &mut reach);
                    let Some(z) = self.settle(&next, z, &strict, &mut reach)? else {
                        continue;
                    };
                    let stored = seen.entry(next.clone()).or_default();
                    if stored.iter().any(|s| z.within(s)) {
                        continue;
                    }
                    stored.retain(|s| !s.within(&z));
                    stored.push(z.clone());
                    queue.push_back((next, z));
                }
            }
        }
        Ok(reach)
    }

    /// The state after instance `p` takes `path` from `key` in `zone`.
    fn fire(
        &self,
        key: &Key,
        zone: &Zone,
        p: usize,
        path: &Path,
    ) -> Result<Option<(Key, Zone)>, String> {
        let mut z = zone.clone();
        if let (false, Some(i)) = (path.guarded, path.interval) {
            z.constrain(p, if i.lo_open { CmpOp::Gt } else { CmpOp::Ge }, i.lo)?;
            if let Some(hi) = i.hi {
                z.constrain(p, if i.hi_open { CmpOp::Lt } else { CmpOp::Le }, hi)?;
            }
        }
        if z.is_empty() {
            return Ok(None);
        }
        z.reset(p);
        let mut next = key.clone();
        next.vars.clone_from(&path.vars);
        next.locs[p] = self.insts[p]
            .states
            .iter()
            .position(|s| s == &path.target)
            .ok_or_else(|| format!("no state `{}`", path.target))?;
        Ok(Some((next, z)))
    }

    /// Time passes in a new state; the strict states cut it; the zone is
    /// extrapolated. `None` when nothing is left.
    fn settle(
        &self,
        key: &Key,
        mut z: Zone,
        strict: &[(usize, usize)],
        reach: &mut Reach,
    ) -> Result<Option<Zone>, String> {
        let all: Vec<Vec<Path>> = (0..self.insts.len())
            .map(|p| self.enabled(p, key))
            .collect::<Result<_, _>>()?;
        self.delay(key, &mut z, &all)?;
        for &(p, s) in strict {
            if key.locs[p] != s {
                continue;
            }
            let mut later = z.clone();
            later.constrain(p, CmpOp::Gt, 0)?;
            if !later.is_empty() {
                reach
                    .lingered
                    .insert((self.insts[p].name.clone(), self.insts[p].states[s].clone()));
            }
            z.constrain(p, CmpOp::Le, 0)?;
        }
        if z.is_empty() {
            return Ok(None);
        }
        let max: Vec<i64> = key
            .locs
            .iter()
            .enumerate()
            .map(|(p, &s)| self.max[p][s])
            .collect();
        z.extrapolate(&max);
        Ok(Some(z))
    }

    fn note(&self, key: &Key, reach: &mut Reach) {
        for (p, &s) in key.locs.iter().enumerate() {
            let i = &self.insts[p];
            reach.reached.insert((i.name.clone(), i.states[s].clone()));
        }
    }
}

fn urgent(i: Interval) -> bool {
    i.lo == 0 && !i.lo_open && i.hi == Some(0)
}

/// Per state, the largest constant of the `wait`s of its `from` clause
/// (the process's clock is compared with nothing larger there).
fn max_constant(i: &Inst) -> Vec<i64> {
    fn walk(s: &[Stmt], m: &mut i64) {
        for st in s {
            match st {
                Stmt::Wait(iv) => *m = (*m).max(iv.lo).max(iv.hi.unwrap_or(0)),
                Stmt::Select(alts) => alts.iter().for_each(|a| walk(a, m)),
                Stmt::If(arms, other) => {
                    arms.iter().for_each(|(_, b)| walk(b, m));
                    walk(other, m);
                }
                Stmt::While(_, b) => walk(b, m),
                _ => {}
            }
        }
    }
    i.froms
        .iter()
        .map(|body| {
            let mut m = 0;
            if let Some(b) = body {
                walk(b, &mut m);
            }
            m
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fiacre::parse;

    /// A worker that takes [2,work] twice against a clock at 10: the watcher
    /// can stay `late` for a positive time only when the two together can
    /// exceed 10.
    fn late(work: i64) -> bool {
        let text = format!(
            "process clock (&t : bool) is states a, b from a wait [10,10]; t := true; to b\n\
             process worker (&t : bool, &done : bool) is states s1, s2, fin\n\
               from s1 wait [2,{work}]; to s2\n\
               from s2 wait [2,{work}]; done := true; to fin\n\
             process watch (&t : bool, &done : bool) is states w, late\n\
               from w wait [0,0]; on t and not done; to late\n\
               from late wait [0,0]; on done; to w\n\
             component c is var t : bool := false, done : bool := false\n\
               par * in clock (&t) || worker (&t, &done) || watch (&t, &done) end\n\
             c\n"
        );
        let net = Net::new(&parse(&text).expect("parses")).expect("instantiates");
        let reach = net
            .explore(&[("watch".to_owned(), "late".to_owned())], 10_000)
            .expect("runs");
        assert!(reach.complete);
        reach
            .lingered
            .contains(&("watch".to_owned(), "late".to_owned()))
    }

    #[test]
    fn deadlines_and_urgency_follow_the_intervals() {
        assert!(!late(4), "4 + 4 ends before the clock at 10");
        assert!(
            !late(5),
            "5 + 5 may end at 10, and must: the work is done first"
        );
        assert!(late(6), "6 + 6 may end after 10");
    }

    /// A worker whose only transition waits `[lo,...[`, observed by a
    /// clock at 3 and at 100: whether it can be done before 3, and
    /// whether it can still be waiting at 100.
    fn unbounded(lo: i64) -> (bool, bool) {
        let text = format!(
            "process clock (&t3 : bool, &t100 : bool) is states a, b, c\n\
               from a wait [3,3]; t3 := true; to b\n\
               from b wait [97,97]; t100 := true; to c\n\
             process worker (&done : bool) is states s, fin\n\
               from s wait [{lo},...[; done := true; to fin\n\
             process obs (&t3 : bool, &t100 : bool, &done : bool) is states w, early, slow\n\
               from w select wait [0,0]; on done and not t3; to early\n\
               [] wait [0,0]; on t100 and not done; to slow end\n\
             component c is var t3 : bool := false, t100 : bool := false, done : bool := false\n\
               par * in clock (&t3, &t100) || worker (&done) || obs (&t3, &t100, &done) end\n\
             c\n"
        );
        let net = Net::new(&parse(&text).expect("parses")).expect("instantiates");
        let reach = net.explore(&[], 10_000).expect("runs");
        assert!(reach.complete);
        let at = |s: &str| reach.reached.contains(&("obs".to_owned(), s.to_owned()));
        (at("early"), at("slow"))
    }

    #[test]
    fn an_interval_without_upper_bound_is_a_lower_bound_only() {
        assert_eq!(unbounded(2), (true, true), "done at 2, or after 100");
        assert_eq!(unbounded(4), (false, true), "never before 4");
    }

    #[test]
    fn an_on_condition_with_a_delay_is_outside_the_subset() {
        let text = "process p (&x : bool) is states a from a on x; wait [1,2]; to a\n\
                    component c is var x : bool := true par * in p (&x) end c\n";
        let net = Net::new(&parse(text).expect("parses")).expect("instantiates");
        assert!(net.explore(&[], 100).is_err());
    }
}
