//! The GenoM3 component as the network needs it, read from the resolved
//! [`Component`] and its [`Genom3Info`] (`docs/genom3-semantics.md`): the
//! tasks, the *slots* (one instance each: one per activity, two for an
//! activity that interrupts itself, 3.4, and one per task with permanent
//! codels), the codel state machines, the control services
//! (functions, attributes, the built-in `kill` and `abort_activity`) with
//! their control codels, and GenoM3's exclusion lists (8.1-8.2), computed
//! here from the codels' parameters.

use std::collections::BTreeMap;

use genom_model::component::genom3::{FsmCodel, Genom3Info, ParamSource};
use genom_model::component::{CodelId, Component, ServiceId, ThreadId};
use genom_model::kinds::CodelKind;
use genom_model::span::Span;

/// Where a yield leads: a state (`Some`) or `ether` (`None`), and whether
/// it is a `pause::` yield.
pub type Yield = (Option<usize>, bool);

/// One state of a codel state machine.
#[derive(Debug, Clone)]
pub struct State {
    /// The state's name.
    pub name: String,
    /// The model codel standing for it (activities only).
    pub codel: Option<CodelId>,
    /// Its yields, in the written order.
    pub yields: Vec<Yield>,
    /// `async`: no upper bound, the WCET is a lower bound.
    pub is_async: bool,
    /// Its WCET in nanoseconds (0 without one).
    pub wcet_ns: u64,
    /// Its key in [`Read::keys`].
    pub key: usize,
    /// The FSM codel.
    pub span: Span,
}

/// A codel state machine.
#[derive(Debug, Clone, Default)]
pub struct Fsm {
    pub states: Vec<State>,
    pub start: Option<usize>,
    pub stop: Option<usize>,
}

/// An instance slot: one instance of an activity, or a task's permanent
/// activity.
#[derive(Debug, Clone)]
pub struct Slot {
    /// An identifier part (`move`, `move_2`, `task_t`).
    pub name: String,
    /// Its task (index into [`Read::tasks`]).
    pub task: usize,
    /// The activity's service (`None`: permanent activity).
    pub service: Option<ServiceId>,
    /// Its state machine.
    pub fsm: Fsm,
    /// The slots it interrupts when accepted (every slot of each target
    /// activity).
    pub interrupts: Vec<usize>,
    /// For an activity's second slot: its first one, whose codels (keys)
    /// it shares.
    pub second_of: Option<usize>,
}

/// A task.
#[derive(Debug, Clone)]
pub struct Task {
    pub id: ThreadId,
    pub name: String,
    pub period_ns: Option<u64>,
    pub delay_ns: u64,
    /// Its slots: the permanent one first, then its activities.
    pub slots: Vec<usize>,
    /// Its permanent slot, if it has permanent codels.
    pub perm: Option<usize>,
    pub span: Span,
}

/// What a control service does besides its codels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CtlKind {
    Plain,
    Kill,
    Abort,
}

/// A control codel (`validate`, a function's codel, or an attribute's ids
/// copy).
#[derive(Debug, Clone)]
pub struct CtlCodel {
    pub name: String,
    pub wcet_ns: u64,
    pub key: usize,
    /// An attribute's ids copy (6.1 step 4): no time, no exception.
    pub copy: bool,
}

/// A function or attribute.
#[derive(Debug, Clone)]
pub struct Control {
    pub service: ServiceId,
    pub kind: CtlKind,
    /// The slots it interrupts after its codels succeeded.
    pub interrupts: Vec<usize>,
}

/// Who owns a key: a slot's state or a service's control codel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KeyOwner {
    Slot(usize, usize),
    Ctl(ServiceId, usize),
}

/// One codel as the locks see it.
#[derive(Debug, Clone)]
pub struct Key {
    pub owner: KeyOwner,
    /// Its task (`None`: the control thread).
    pub task: Option<usize>,
    pub is_async: bool,
    pub access: Vec<Access>,
    /// The keys it waits for while they run.
    pub excl: Vec<usize>,
}

/// A data access, as GenoM3's `param_mutex` compares them (8.1).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Access {
    /// `ids`, or `port NAME` / `remote NAME`.
    pub base: String,
    /// The member path below the base.
    pub path: Vec<String>,
    pub write: bool,
}

impl Access {
    /// An attribute's ids copy: it writes its inputs' ids members and reads
    /// its outputs'.
    fn of_attribute(s: &genom_model::component::Service) -> Vec<Access> {
        let member = |p: &genom_model::component::Param, write: bool| {
            // The member as the attribute's parameter names it.
            p.data.as_ref().map(|d| Access {
                base: "ids".to_owned(),
                path: d
                    .text
                    .split(['.', '[', ']'])
                    .map(str::trim)
                    .filter(|x| !x.is_empty() && *x != "::ids")
                    .map(str::to_owned)
                    .collect(),
                write,
            })
        };
        let written = s.inputs.iter().filter_map(|p| member(p, true));
        written
            .chain(s.outputs.iter().filter_map(|p| member(p, false)))
            .collect()
    }
}

impl Access {
    fn of(fsm: &FsmCodel) -> Vec<Access> {
        let mut out = Vec::new();
        for p in &fsm.params {
            let mut segs: Vec<String> = p
                .path
                .split(['.', '[', ']'])
                .map(str::trim)
                .filter(|x| !x.is_empty() && *x != "::ids")
                .map(str::to_owned)
                .collect();
            let base = match p.source {
                ParamSource::Ids => "ids".to_owned(),
                ParamSource::Port if !segs.is_empty() => format!("port {}", segs.remove(0)),
                ParamSource::Remote if !segs.is_empty() => format!("remote {}", segs.remove(0)),
                _ => continue,
            };
            out.push(Access {
                base,
                path: segs,
                write: p.dir != "in",
            });
        }
        out
    }

    /// Ports and remotes conflict whatever the directions; ids paths when
    /// one writes and they agree on their common prefix.
    fn conflicts(&self, o: &Access) -> bool {
        if self.base != o.base {
            return false;
        }
        if self.base != "ids" {
            return true;
        }
        (self.write || o.write) && self.path.iter().zip(&o.path).all(|(a, b)| a == b)
    }
}

/// Everything read from the component.
#[derive(Debug, Clone, Default)]
pub struct Read {
    pub tasks: Vec<Task>,
    pub slots: Vec<Slot>,
    pub controls: Vec<Control>,
    /// Per service: its control codels, in order (all of them).
    pub ctl_codels: BTreeMap<ServiceId, Vec<CtlCodel>>,
    pub keys: Vec<Key>,
    /// Per service: `after` and `before` services.
    pub after: BTreeMap<ServiceId, Vec<ServiceId>>,
    pub before: BTreeMap<ServiceId, Vec<ServiceId>>,
    /// Per activity service: its slots (two when it interrupts itself:
    /// a client restarts it by requesting it again while an instance
    /// lives, 3.4 and 15.8).
    pub slot_of: BTreeMap<ServiceId, Vec<usize>>,
}

impl Read {
    /// Per service, its control codels (indices into its `ctl_codels`)
    /// with a lock some task's codel contends, even those that take no
    /// time (waiting, their ticket delays those behind it, 15.5); the
    /// others are instantaneous and take no ticket.
    pub fn contended_control_codels(&self) -> BTreeMap<ServiceId, Vec<usize>> {
        let mut out = BTreeMap::new();
        for (&sid, list) in &self.ctl_codels {
            let kept: Vec<usize> = (0..list.len())
                .filter(|&i| {
                    let k = list[i].key;
                    !self.keys[k].excl.is_empty() || self.keys.iter().any(|j| j.excl.contains(&k))
                })
                .collect();
            if !kept.is_empty() {
                out.insert(sid, kept);
            }
        }
        out
    }

    /// The unit of time, in nanoseconds: the greatest common divisor of
    /// the periods, delays and WCETs (task and control codels), 1 at least.
    pub fn unit_ns(&self) -> u64 {
        fn gcd(a: u64, b: u64) -> u64 {
            if b == 0 { a } else { gcd(b, a % b) }
        }
        let mut unit = 0;
        for t in &self.tasks {
            unit = gcd(gcd(unit, t.period_ns.unwrap_or(0)), t.delay_ns);
        }
        for s in self.slots.iter().flat_map(|s| s.fsm.states.iter()) {
            unit = gcd(unit, s.wcet_ns);
        }
        for k in self.ctl_codels.values().flatten() {
            unit = gcd(unit, k.wcet_ns);
        }
        unit.max(1)
    }
}

/// Reads a GenoM3 component.
pub fn read(c: &Component, g: &Genom3Info) -> Read {
    let mut r = Read::default();
    let mut task_of = BTreeMap::new();
    for (tid, t) in c.threads.iter() {
        let info = g.tasks.iter().find(|k| k.thread == tid);
        task_of.insert(tid, r.tasks.len());
        r.tasks.push(Task {
            id: tid,
            name: t.name.name.clone(),
            period_ns: t.period.map(|p| p.ns),
            delay_ns: info.and_then(|k| k.delay).map_or(0, |d| d.ns),
            slots: Vec::new(),
            perm: None,
            span: t.name.span,
        });
    }
    // Permanent slots first: they come first in their task's sweep (1.7).
    for t in 0..r.tasks.len() {
        let tid = r.tasks[t].id;
        let codels: Vec<&FsmCodel> = g
            .tasks
            .iter()
            .filter(|k| k.thread == tid)
            .flat_map(|k| k.codels.iter())
            .collect();
        if codels.is_empty() {
            continue;
        }
        let fsm = fsm_of(&codels, |_| None, |_| None);
        let slot = r.slots.len();
        r.slots.push(Slot {
            name: format!("task_{}", r.tasks[t].name),
            task: t,
            service: None,
            fsm,
            interrupts: Vec::new(),
            second_of: None,
        });
        r.tasks[t].perm = Some(slot);
        r.tasks[t].slots.push(slot);
    }
    for (sid, s) in c.services.iter() {
        let Some(&t) = s.thread.as_ref().and_then(|x| task_of.get(&x.id)) else {
            continue;
        };
        let first = Slot {
            name: s.name.name.clone(),
            task: t,
            service: Some(sid),
            fsm: activity_fsm(c, g, sid),
            interrupts: Vec::new(),
            second_of: None,
        };
        let mut slots = vec![first];
        if s.stops.iter().any(|x| x.id == sid) {
            // One instance, plus the request restarting it (3.4, 15.8).
            let second = Slot {
                name: format!("{}_2", s.name.name),
                second_of: Some(r.slots.len()),
                ..slots[0].clone()
            };
            slots.push(second);
        }
        for slot in slots {
            r.tasks[t].slots.push(r.slots.len());
            r.slot_of.entry(sid).or_default().push(r.slots.len());
            r.slots.push(slot);
        }
    }
    read_controls(c, g, &mut r);
    for i in 0..r.slots.len() {
        if let Some(sid) = r.slots[i].service {
            r.slots[i].interrupts = targets(c, &r.slot_of, sid);
        }
    }
    for info in &g.services {
        r.after
            .insert(info.service, info.after.iter().map(|x| x.id).collect());
        r.before
            .insert(info.service, info.before.iter().map(|x| x.id).collect());
    }
    number_keys(c, g, &mut r);
    r
}

fn read_controls(c: &Component, g: &Genom3Info, r: &mut Read) {
    for (sid, s) in c.services.iter() {
        if r.slot_of.contains_key(&sid) {
            continue;
        }
        let genom = g
            .services
            .iter()
            .any(|i| i.service == sid && i.interface.as_deref() == Some("genom"));
        let kind = match s.name.name.as_str() {
            "kill" if genom => CtlKind::Kill,
            "abort_activity" if genom => CtlKind::Abort,
            _ => CtlKind::Plain,
        };
        let interrupts = if kind == CtlKind::Kill {
            r.slot_of.values().flatten().copied().collect()
        } else {
            targets(c, &r.slot_of, sid)
        };
        r.controls.push(Control {
            service: sid,
            kind,
            interrupts,
        });
    }
}

/// The activity slots a service interrupts (sorted).
fn targets(c: &Component, slot_of: &BTreeMap<ServiceId, Vec<usize>>, sid: ServiceId) -> Vec<usize> {
    let mut out: Vec<usize> = c.services[sid]
        .stops
        .iter()
        .filter_map(|x| slot_of.get(&x.id))
        .flatten()
        .copied()
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// The state machine of FSM codels (states in first-seen order).
fn fsm_of(
    codels: &[&FsmCodel],
    codel_of: impl Fn(&str) -> Option<CodelId>,
    wcet_of: impl Fn(Option<CodelId>) -> Option<u64>,
) -> Fsm {
    let mut index: BTreeMap<String, usize> = BTreeMap::new();
    let mut states: Vec<State> = Vec::new();
    let mut owner: Vec<usize> = Vec::new();
    for (k, f) in codels.iter().enumerate() {
        for s in &f.states {
            if index.contains_key(&s.name) {
                continue;
            }
            index.insert(s.name.clone(), states.len());
            let codel = codel_of(&s.name);
            owner.push(k);
            states.push(State {
                name: s.name.clone(),
                codel,
                yields: Vec::new(),
                is_async: f.is_async,
                wcet_ns: wcet_of(codel).or(f.wcet.map(|w| w.ns)).unwrap_or(0),
                key: 0,
                span: f.span,
            });
        }
    }
    for (i, st) in states.iter_mut().enumerate() {
        let f = codels[owner[i]];
        st.yields = f
            .yields
            .iter()
            .filter_map(|y| match index.get(&y.state.name) {
                Some(&s) => Some((Some(s), y.pause)),
                None => (y.state.name == "ether").then_some((None, y.pause)),
            })
            .collect();
    }
    Fsm {
        start: index.get("start").copied(),
        stop: index.get("stop").copied(),
        states,
    }
}

fn activity_fsm(c: &Component, g: &Genom3Info, sid: ServiceId) -> Fsm {
    let s = &c.services[sid];
    let infos: Vec<_> = g
        .codels
        .iter()
        .filter(|i| s.codels.contains(&i.codel) && c.codels[i.codel].kind != CodelKind::Control)
        .collect();
    let mut seen: Vec<&FsmCodel> = Vec::new();
    for i in &infos {
        if !seen.iter().any(|f| f.span == i.fsm.span) {
            seen.push(&i.fsm);
        }
    }
    fsm_of(
        &seen,
        |state| {
            infos
                .iter()
                .find(|i| c.codels[i.codel].name.name == state)
                .map(|i| i.codel)
        },
        |k| k.and_then(|k| c.codels[k].wcet).map(|w| w.ns),
    )
}

/// Numbers every codel (slot states, then control codels) and computes
/// the exclusion lists (8.2). An activity's second slot shares its first
/// slot's keys: a key is a codel, whichever instance runs it.
fn number_keys(c: &Component, g: &Genom3Info, r: &mut Read) {
    let mut keys = Vec::new();
    for i in 0..r.slots.len() {
        if let Some(first) = r.slots[i].second_of {
            let shared: Vec<usize> = r.slots[first].fsm.states.iter().map(|s| s.key).collect();
            for (st, key) in r.slots[i].fsm.states.iter_mut().zip(shared) {
                st.key = key;
            }
            continue;
        }
        let slot = &mut r.slots[i];
        for (s, st) in slot.fsm.states.iter_mut().enumerate() {
            st.key = keys.len();
            let access = st
                .codel
                .and_then(|k| g.codels.iter().find(|x| x.codel == k))
                .map(|x| Access::of(&x.fsm))
                .unwrap_or_default();
            keys.push(Key {
                owner: KeyOwner::Slot(i, s),
                task: Some(slot.task),
                is_async: st.is_async,
                access,
                excl: Vec::new(),
            });
        }
    }
    // Permanent codels have no model codel: their accesses come from the
    // task's FSM codels, matched by span.
    for k in &mut keys {
        let KeyOwner::Slot(i, s) = k.owner else {
            continue;
        };
        if r.slots[i].service.is_none() {
            let span = r.slots[i].fsm.states[s].span;
            if let Some(f) = g
                .tasks
                .iter()
                .flat_map(|t| t.codels.iter())
                .find(|f| f.span == span)
            {
                k.access = Access::of(f);
            }
        }
    }
    for (sid, s) in c.services.iter() {
        for &k in &s.codels {
            let codel = &c.codels[k];
            if codel.kind != CodelKind::Control {
                continue;
            }
            let Some(info) = g.codels.iter().find(|i| i.codel == k) else {
                continue;
            };
            let list = r.ctl_codels.entry(sid).or_default();
            list.push(CtlCodel {
                name: codel.name.name.clone(),
                wcet_ns: codel.wcet.map_or(0, |w| w.ns),
                key: keys.len(),
                copy: false,
            });
            keys.push(Key {
                owner: KeyOwner::Ctl(sid, list.len() - 1),
                task: None,
                is_async: false,
                access: Access::of(&info.fsm),
                excl: Vec::new(),
            });
        }
        if g.services
            .iter()
            .any(|i| i.service == sid && i.kind == "attribute")
        {
            let list = r.ctl_codels.entry(sid).or_default();
            list.push(CtlCodel {
                name: "ids-copy".to_owned(),
                wcet_ns: 0,
                key: keys.len(),
                copy: true,
            });
            keys.push(Key {
                owner: KeyOwner::Ctl(sid, list.len() - 1),
                task: None,
                is_async: false,
                access: Access::of_attribute(s),
                excl: Vec::new(),
            });
        }
    }
    let excl: Vec<Vec<usize>> = (0..keys.len())
        .map(|k| {
            (0..keys.len())
                .filter(|&j| excludes(r, &keys, k, j))
                .collect()
        })
        .collect();
    for (k, e) in keys.iter_mut().zip(excl) {
        k.excl = e;
    }
    r.keys = keys;
}

/// Whether codel `k` waits while codel `j` runs: another thread, neither
/// `async`, conflicting accesses, and `j`'s activity does not interrupt
/// `k`'s (the generator's one-sided exemption).
fn excludes(r: &Read, keys: &[Key], k: usize, j: usize) -> bool {
    let (a, b) = (&keys[k], &keys[j]);
    if a.task == b.task || a.is_async || b.is_async {
        return false;
    }
    if let (KeyOwner::Slot(sk, _), KeyOwner::Slot(sj, _)) = (a.owner, b.owner) {
        if r.slots[sj].interrupts.contains(&sk) {
            return false;
        }
    }
    a.access
        .iter()
        .any(|x| b.access.iter().any(|y| x.conflicts(y)))
}
