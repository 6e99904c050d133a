//! The layout of the GenoM3 Fiacre model: the time unit, the identifiers
//! (unique, made of the `.gen` names), the shared variables of the root
//! component, and per task and per instance slot what its processes
//! read and write. Built once from the timed network's reading of the
//! component ([`Read`]); the printers only read it.

use std::collections::BTreeSet;

use genom_model::component::ServiceId;
use genom_translate::timed_automata::genom3::read::{CtlKind, Read};

use crate::ExportInput;
use crate::fiacre::Names;

/// A shared variable of the root component.
pub(super) struct Var {
    pub name: String,
    pub ty: &'static str,
    pub init: String,
}

/// A task: its processes and shared variables (indices into
/// [`Layout::vars`]).
pub(super) struct TaskL {
    /// Its `.gen` name.
    pub name: String,
    /// Its name as an identifier part.
    pub ident: String,
    /// Its place in the declaration (and boot) order.
    pub index: usize,
    /// Period and first tick (`delay`), in units; `None`: aperiodic.
    pub period: Option<(u64, u64)>,
    pub tick: usize,
    pub work: usize,
    pub cont: usize,
    pub running: usize,
    pub timer: Option<String>,
    pub watch: Option<String>,
    pub manager: String,
    /// With locks: its place in the resource FIFO, the slot its ticket is
    /// for, the key + 1 of the codel it runs.
    pub fifo: Option<TaskFifo>,
    /// With interruptions (`kill`, `abort_activity`, `interrupts`): the
    /// turn of the slot whose codel runs (0: none).
    pub cur: Option<usize>,
    /// Its slots (indices into [`Layout::slots`]), in sweep order.
    pub slots: Vec<usize>,
    pub span: genom_model::Span,
}

/// A task's variables of GenoM3's resource FIFO and locks (8.3).
#[derive(Clone, Copy)]
pub(super) struct TaskFifo {
    pub pos: usize,
    pub slot: usize,
    pub run: usize,
}

/// The component's variables of the resource FIFO and locks.
#[derive(Clone, Copy)]
pub(super) struct Fifo {
    /// Tickets queued.
    pub len: usize,
    /// The control task's place in the queue.
    pub cpos: usize,
    /// The key + 1 of the control codel running.
    pub crun: usize,
}

/// An instance slot: a task's permanent activity, or one instance of an
/// activity.
pub(super) struct SlotL {
    /// The reading's slot.
    pub read: usize,
    /// Its task (index into [`Layout::tasks`]).
    pub task: usize,
    /// Its number in its task's sweep (from 1; what a ticket is for).
    pub turn: usize,
    /// Its process.
    pub process: String,
    /// What it is, for comments.
    pub what: String,
    pub st: usize,
    pub q: usize,
    pub due: usize,
    pub pz: usize,
    /// For a slot something may interrupt: interrupted while its codel
    /// runs or is due (it goes to `stop` after that codel, 15.6).
    pub fl: Option<usize>,
    /// The slots it interrupts when accepted (indices into
    /// [`Layout::slots`]; every instance of each target activity).
    pub targets: Vec<usize>,
    /// The process state of each codel state of its machine.
    pub states: Vec<String>,
}

/// A service the client may request (an activity, or a function or
/// attribute with a control codel some task's codel contends), with its
/// request flag, its slots (none for a function or attribute) and its
/// control codels that take part in the locks (indices into the reading's
/// `ctl_codels`).
pub(super) struct Request {
    pub service: ServiceId,
    /// What it does once its control codels succeeded.
    pub kind: ReqKind,
    /// Its request flag, when requests go through the control task (some
    /// request of the component has contended control codels).
    pub rq: Option<usize>,
    pub slots: Vec<usize>,
    pub timed: Vec<usize>,
}

/// What a request does once its control codels succeeded.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum ReqKind {
    /// An activity's request: an instance is accepted into a free slot.
    Accept,
    /// A function or attribute (index into the reading's `controls`):
    /// it marks itself done and interrupts its targets; `kill` then
    /// drains the component (10.2).
    Call(usize),
}

/// An activity codel's property name, its label, and the (process,
/// state) pairs where it runs.
pub(super) type CodelStates = (String, String, Vec<(String, String)>);

/// Everything the printers read.
pub(super) struct Layout<'a> {
    pub input: &'a ExportInput<'a>,
    pub r: &'a Read,
    /// Nanoseconds per unit of time.
    pub unit: u64,
    pub instances: usize,
    pub root: String,
    pub vars: Vec<Var>,
    pub tasks: Vec<TaskL>,
    pub slots: Vec<SlotL>,
    pub requests: Vec<Request>,
    pub booted: usize,
    pub failed: usize,
    /// With `kill`: 0 boot or run, 2 drain, 3 permanent stop paths, 4
    /// stopped (10.2); and the task whose permanent stop path runs.
    pub phase: Option<usize>,
    pub pstop: Option<usize>,
    /// With pending interrupters (some activity interrupts others): an
    /// instance ended in this step (the pending ones are re-examined, 5.3).
    pub ended: Option<usize>,
    /// Per service some `after` or `before` names: it completed once.
    pub done: std::collections::BTreeMap<ServiceId, usize>,
    /// `abort_activity` (the `genom` interface's), when requested.
    pub abort: Option<ServiceId>,
    /// With WCETs (else the untimed reading: every codel takes any time,
    /// no watcher).
    pub timed: bool,
    /// With locks (some codel's exclusion list is not empty).
    pub fifo: Option<Fifo>,
    pub client: String,
    pub control: String,
    pub names: std::cell::RefCell<Names>,
}

/// Process states the slots' codel states must not take.
const SLOT_STATES: [&str; 1] = ["idle"];

impl<'a> Layout<'a> {
    pub fn new(input: &'a ExportInput<'a>, r: &'a Read, instances: usize, timed: bool) -> Self {
        let mut names = Names::default();
        let root = names.take("", &input.component.name.name);
        let client = names.take("", "client");
        let control = names.take("", "control");
        let mut l = Layout {
            input,
            r,
            unit: r.unit_ns(),
            instances,
            root,
            vars: Vec::new(),
            tasks: Vec::new(),
            slots: Vec::new(),
            requests: Vec::new(),
            booted: 0,
            failed: 0,
            phase: None,
            pstop: None,
            ended: None,
            done: Default::default(),
            abort: None,
            timed,
            fifo: None,
            client,
            control,
            names: std::cell::RefCell::new(names),
        };
        l.booted = l.var("booted", "nat", initial_boot(r).to_string());
        l.failed = l.var("failed", "bool", "false".to_owned());
        let has = |k: CtlKind| r.controls.iter().any(|c| c.kind == k);
        if has(CtlKind::Kill) {
            l.phase = Some(l.var("phase", "nat", "0".into()));
            l.pstop = Some(l.var("pstop", "nat", "0".into()));
        }
        if r.slots.iter().any(|s| !s.interrupts.is_empty()) {
            l.ended = Some(l.var("ended", "bool", "false".into()));
        }
        let named: BTreeSet<ServiceId> = r
            .after
            .values()
            .chain(r.before.values())
            .flatten()
            .copied()
            .collect();
        for s in named {
            let name = &input.component.services[s].name.name;
            let v = l.var(&format!("done_{name}"), "bool", "false".into());
            l.done.insert(s, v);
        }
        l.abort = r
            .controls
            .iter()
            .find(|c| c.kind == CtlKind::Abort)
            .map(|c| c.service);
        if r.keys.iter().any(|k| !k.excl.is_empty()) {
            l.fifo = Some(Fifo {
                len: l.var("qlen", "nat", "0".into()),
                cpos: l.var("cpos", "nat", "0".into()),
                crun: l.var("crun", "nat", "0".into()),
            });
        }
        let interrupted = l.interrupted();
        for t in 0..r.tasks.len() {
            l.task(t, &interrupted);
        }
        l.targets();
        l.requests();
        l
    }

    fn var(&mut self, want: &str, ty: &'static str, init: String) -> usize {
        let name = self.names.borrow_mut().take("", want);
        self.vars.push(Var { name, ty, init });
        self.vars.len() - 1
    }

    fn ident(&self, prefix: &str, want: &str) -> String {
        self.names.borrow_mut().take(prefix, want)
    }

    /// Durations in units (GenoM3's nanoseconds divided by [`Layout::unit`]).
    pub fn units(&self, ns: u64) -> u64 {
        ns / self.unit
    }

    /// The reading's slots something may interrupt (an activity, a
    /// function, `kill` or `abort_activity`).
    fn interrupted(&self) -> BTreeSet<usize> {
        let mut out: BTreeSet<usize> = self
            .r
            .slots
            .iter()
            .flat_map(|s| s.interrupts.iter().copied())
            .chain(
                self.r
                    .controls
                    .iter()
                    .flat_map(|c| c.interrupts.iter().copied()),
            )
            .collect();
        if self.r.controls.iter().any(|c| c.kind == CtlKind::Abort) {
            out.extend(self.r.slot_of.values().flatten().copied());
        }
        out
    }

    /// The layout slots of the reading's slots `read`.
    pub fn copies(&self, read: &[usize]) -> Vec<usize> {
        (0..self.slots.len())
            .filter(|&k| read.contains(&self.slots[k].read))
            .collect()
    }

    fn targets(&mut self) {
        for k in 0..self.slots.len() {
            let read = &self.r.slots[self.slots[k].read].interrupts;
            self.slots[k].targets = self.copies(read);
        }
    }

    fn task(&mut self, t: usize, interrupted: &BTreeSet<usize>) {
        let task = &self.r.tasks[t];
        let n = task.name.clone();
        let period = task
            .period_ns
            .map(|p| (self.units(p), self.units(task.delay_ns)));
        let tl = TaskL {
            ident: self.ident("", &n),
            index: t,
            period,
            tick: self.var(&format!("tick_{n}"), "bool", "false".into()),
            work: self.var(&format!("work_{n}"), "bool", "false".into()),
            cont: self.var(&format!("cont_{n}"), "bool", "false".into()),
            running: self.var(&format!("running_{n}"), "bool", "false".into()),
            timer: period.map(|_| self.ident("timer_", &n)),
            watch: period
                .filter(|_| self.timed)
                .map(|_| self.ident("watch_", &n)),
            manager: self.ident("manager_", &n),
            cur: (!interrupted.is_empty() || self.phase.is_some())
                .then(|| self.var(&format!("cur_{n}"), "nat", "0".into())),
            fifo: self.fifo.map(|_| TaskFifo {
                pos: self.var(&format!("tpos_{n}"), "nat", "0".into()),
                slot: self.var(&format!("tslot_{n}"), "nat", "0".into()),
                run: self.var(&format!("run_{n}"), "nat", "0".into()),
            }),
            slots: Vec::new(),
            span: task.span,
            name: n,
        };
        self.tasks.push(tl);
        for &i in &self.r.tasks[t].slots {
            // An activity has `instances` slots, plus the one restarting
            // it when it interrupts itself (the reading's second slot,
            // 15.8); a permanent activity has one.
            let rs = &self.r.slots[i];
            let copies = if rs.service.is_some() && rs.second_of.is_none() {
                self.instances
            } else {
                1
            };
            for copy in 0..copies {
                self.slot(t, i, copy, interrupted.contains(&i));
            }
        }
    }

    fn slot(&mut self, t: usize, i: usize, copy: usize, interrupted: bool) {
        let rs = &self.r.slots[i];
        let base = if copy == 0 {
            rs.name.clone()
        } else {
            format!("{}_{}", rs.name, copy + 1)
        };
        let perm_start = rs.service.is_none().then_some(rs.fsm.start).flatten();
        let what = match rs.service {
            Some(s) => format!(
                "instance {} of activity {}",
                copy + 1,
                self.input.component.services[s].name.name
            ),
            None => format!("the permanent activity of task {}", self.r.tasks[t].name),
        };
        let mut used: BTreeSet<String> = SLOT_STATES.iter().map(|s| (*s).to_owned()).collect();
        let states = rs
            .fsm
            .states
            .iter()
            .map(|s| fresh_state(&mut used, &s.name))
            .collect();
        let slot = SlotL {
            read: i,
            task: t,
            turn: self.tasks[t].slots.len() + 1,
            process: self.ident("slot_", &base),
            what,
            st: self.var(
                &format!("st_{base}"),
                "nat",
                if perm_start.is_some() { "3" } else { "0" }.into(),
            ),
            q: self.var(
                &format!("q_{base}"),
                "nat",
                perm_start.unwrap_or(0).to_string(),
            ),
            due: self.var(&format!("due_{base}"), "bool", "false".into()),
            pz: self.var(&format!("pz_{base}"), "bool", "false".into()),
            fl: interrupted.then(|| self.var(&format!("fl_{base}"), "bool", "false".into())),
            targets: Vec::new(),
            states,
        };
        self.slots.push(slot);
        let k = self.slots.len() - 1;
        self.tasks[t].slots.push(k);
    }

    fn requests(&mut self) {
        let mut by: std::collections::BTreeMap<ServiceId, Vec<usize>> = Default::default();
        for (k, s) in self.slots.iter().enumerate() {
            if let Some(sid) = self.r.slots[s.read].service {
                by.entry(sid).or_default().push(k);
            }
        }
        let timed = self.r.contended_control_codels();
        // `abort_activity` takes effect at once, its codels aside, as on
        // the network's control thread.
        for sid in timed.keys().filter(|&&s| Some(s) != self.abort) {
            by.entry(*sid).or_default();
        }
        // The functions and attributes whose request changes something a
        // task or a later request sees; `abort_activity` is the client's
        // own (one request per instance slot).
        let mut calls = std::collections::BTreeMap::new();
        for (k, ctl) in self.r.controls.iter().enumerate() {
            let acts = ctl.kind != CtlKind::Plain
                || !ctl.interrupts.is_empty()
                || self.done.contains_key(&ctl.service);
            if ctl.kind == CtlKind::Abort {
                continue;
            }
            if acts || timed.contains_key(&ctl.service) {
                by.entry(ctl.service).or_default();
                calls.insert(ctl.service, k);
            }
        }
        let via_control = !timed.is_empty();
        for (service, slots) in by {
            let name = self.input.component.services[service].name.name.clone();
            let rq = via_control.then(|| self.var(&format!("rq_{name}"), "bool", "false".into()));
            let timed = timed.get(&service).cloned().unwrap_or_default();
            let kind = calls
                .get(&service)
                .map_or(ReqKind::Accept, |&k| ReqKind::Call(k));
            self.requests.push(Request {
                service,
                kind,
                rq,
                slots,
                timed,
            });
        }
    }

    /// The task booted after task `t`'s permanent activity ran its first
    /// codel (10.1): the next one whose permanent activity starts, or the
    /// number of tasks when none is left (boot ended).
    pub fn next_boot(&self, t: usize) -> usize {
        (t + 1..self.r.tasks.len())
            .find(|&u| starts(self.r, u))
            .unwrap_or(self.r.tasks.len())
    }

    /// Per activity codel: its property name, its label, and the
    /// (process, state) pairs where it runs.
    pub fn codel_states(&self) -> Vec<CodelStates> {
        let c = self.input.component;
        let mut out: std::collections::BTreeMap<genom_model::component::CodelId, CodelStates> =
            Default::default();
        for s in &self.slots {
            let rs = &self.r.slots[s.read];
            let Some(sid) = rs.service else { continue };
            for (k, st) in rs.fsm.states.iter().enumerate() {
                let Some(codel) = st.codel else { continue };
                let entry = out.entry(codel).or_insert_with(|| {
                    let name = self.ident(
                        "codel_",
                        &format!(
                            "{}_{}_never_runs",
                            c.services[sid].name.name, c.codels[codel].name.name
                        ),
                    );
                    (name, c.codel_label(codel), Vec::new())
                });
                entry.2.push((s.process.clone(), s.states[k].clone()));
            }
        }
        out.into_values().collect()
    }
}

/// Whether task `t` has a permanent activity with a `start` codel (it
/// runs at boot).
fn starts(r: &Read, t: usize) -> bool {
    r.tasks[t]
        .perm
        .is_some_and(|p| r.slots[p].fsm.start.is_some())
}

/// The first task whose permanent activity starts (the boot begins with
/// it), or the number of tasks.
fn initial_boot(r: &Read) -> usize {
    (0..r.tasks.len())
        .find(|&t| starts(r, t))
        .unwrap_or(r.tasks.len())
}

/// A process state `c_NAME` not in `used`.
fn fresh_state(used: &mut BTreeSet<String>, want: &str) -> String {
    let mut base = String::from("c_");
    base.extend(want.chars().map(|ch| {
        if ch.is_ascii_alphanumeric() || ch == '_' {
            ch
        } else {
            '_'
        }
    }));
    let mut id = base.clone();
    let mut n = 2;
    while used.contains(&id) {
        id = format!("{base}_{n}");
        n += 1;
    }
    used.insert(id.clone());
    id
}
