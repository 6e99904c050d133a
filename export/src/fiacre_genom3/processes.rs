//! The processes of the GenoM3 Fiacre model, as text: the client and the
//! control task, and per task its timer, its overrun watcher and its
//! manager, and per instance slot the process that runs its codels. Each
//! process takes by reference (`&x`) the shared variables it reads or
//! writes, in the order of their declaration.

use std::collections::BTreeSet;
use std::fmt::Write as _;

use genom_translate::timed_automata::genom3::read::State;

use super::layout::{Layout, SlotL, TaskL};
use super::process::Proc;

use crate::fiacre::comment;
use crate::pnml::location;

/// ` (file.gen:12:5)` or nothing.
fn at(l: &Layout<'_>, span: genom_model::Span) -> String {
    location(l.input.sources, span)
        .map_or_else(String::new, |(f, line, col)| format!(" ({f}:{line}:{col})"))
}

impl Layout<'_> {
    /// Every process, in the order of the root component's `par`.
    pub fn processes(&self) -> Vec<Proc> {
        let mut out = Vec::new();
        if !self.requests.is_empty() {
            out.push(self.client_process());
        }
        if self.requests.iter().any(|r| r.rq.is_some()) {
            out.push(self.control_process());
        }
        for t in &self.tasks {
            if let Some(p) = self.timer_process(t) {
                out.push(p);
            }
            if let Some(p) = self.watch_process(t) {
                out.push(p);
            }
            out.push(self.manager_process(t));
            for &s in &t.slots {
                out.push(self.slot_process(&self.slots[s]));
            }
        }
        out
    }

    pub(super) fn service_name(&self, r: &super::layout::Request) -> &str {
        &self.input.component.services[r.service].name.name
    }

    fn client_process(&self) -> Proc {
        let mut p = Proc::new(
            &self.client,
            "The clients: each activity may be requested at any time once the boot ended (10.1), while one of its instance slots is free (--max-instances); without contended control codels in the component, the control task takes no time a task sees and the request is accepted at once.".to_owned(),
            &["ready"],
        );
        let serving = self.serving(&mut p);
        let mut alts = Vec::new();
        for r in &self.requests {
            let free: Vec<String> = r
                .slots
                .iter()
                .map(|&s| format!("{} = 0", p.v(self, self.slots[s].st)))
                .collect();
            let free = if free.is_empty() {
                String::new()
            } else {
                format!(" and ({})", free.join(" or "))
            };
            let what = self.service_name(r).to_owned();
            let ok = self.admissible(&mut p, r);
            let ready = format!("on {serving}{free}{ok}");
            alts.push(match r.rq {
                Some(rq) => {
                    let rq = p.v(self, rq);
                    format!("/* request {what} */ {ready} and not {rq}; {rq} := true; loop")
                }
                None => format!(
                    "/* request {what}, accepted at once */ {ready}; {}loop",
                    self.effect(&mut p, r)
                ),
            });
        }
        if !self.requests.iter().any(|r| r.rq.is_some()) {
            alts.extend(self.aborts(&mut p));
        }
        p.from("ready", "", &alts);
        p
    }

    /// The requests of `abort_activity`, one per instance slot it may
    /// interrupt (accepted, pending or running, 5.6), at any time.
    pub(super) fn aborts(&self, p: &mut Proc) -> Vec<String> {
        let Some(sid) = self.abort else {
            return Vec::new();
        };
        let serving = self.serving(p);
        let ok = self
            .requests
            .iter()
            .find(|r| r.service == sid)
            .map_or_else(String::new, |r| self.admissible(p, r));
        let mut out = Vec::new();
        for (k, s) in self.slots.iter().enumerate() {
            if self.r.slots[s.read].service.is_none() || s.fl.is_none() {
                continue;
            }
            let st = p.v(self, s.st);
            out.push(format!(
                "/* abort_activity of {} */ on {serving}{ok} and {st} >= 1 and {st} <= 3; {}loop",
                s.process,
                self.abort(p, k)
            ));
        }
        out
    }

    fn timer_process(&self, t: &TaskL) -> Option<Proc> {
        let (period, delay) = t.period?;
        let name = t.timer.as_deref()?;
        let mut p = Proc::new(
            name,
            format!(
                "Task {}{}: its timer, a tick every {} units from {} (1.2); a tick is a boolean, so ticks coalesce.",
                t.name,
                at(self, t.span),
                period,
                delay
            ),
            &["first", "periodic"],
        );
        let tick = p.v(self, t.tick);
        p.from(
            "first",
            "",
            &[format!(
                "wait [{delay},{delay}]; {tick} := true; to periodic"
            )],
        );
        p.from(
            "periodic",
            "",
            &[format!(
                "wait [{period},{period}]; {tick} := true; to periodic"
            )],
        );
        Some(p)
    }

    fn watch_process(&self, t: &TaskL) -> Option<Proc> {
        let name = t.watch.as_deref()?;
        let mut p = Proc::new(
            name,
            format!(
                "Task {}: its overrun watcher. A tick that finds the task's work unfinished makes it late; if time passes before the task takes the tick, the task overran (15.1).",
                t.name
            ),
            &["watching", "late", "overrun"],
        );
        let (tick, work) = (p.v(self, t.tick), p.v(self, t.work));
        let alive = self.alive(&mut p);
        p.from(
            "watching",
            "",
            &[format!(
                "wait [0,0]; on {tick} and {work} and {alive}; to late"
            )],
        );
        p.from(
            "late",
            "",
            &[
                format!("/* the tick is taken at the same instant (or the component stopped) */ wait [0,0]; on not {tick} or not ({alive}); to watching"),
                "/* time passes first: an overrun */ wait ]0,1]; to overrun".to_owned(),
            ],
        );
        Some(p)
    }

    /// The sweep's pre-pass over the slots of `t` (1.4): with `runnable`,
    /// accepted instances start and paused ones resume; without, only the
    /// unpaused running ones are due (1.5).
    fn pre_pass(&self, p: &mut Proc, t: &TaskL, runnable: bool) -> String {
        let mut out = Vec::new();
        let mut ends = false;
        for &s in &t.slots {
            let sl = &self.slots[s];
            let (st, q, due, pz) = (
                p.v(self, sl.st),
                p.v(self, sl.q),
                p.v(self, sl.due),
                p.v(self, sl.pz),
            );
            let on_path = if self.may_stop(sl) {
                format!("({st} = 3 or {st} = 4)")
            } else {
                format!("{st} = 3")
            };
            if !runnable {
                out.push(format!("if {on_path} and not {pz} then {due} := true end"));
                continue;
            }
            let resume = format!("{on_path} then {pz} := false; {due} := true");
            let rs = &self.r.slots[sl.read];
            if rs.service.is_none() {
                out.push(format!("if {resume} end"));
                continue;
            }
            let start = match rs.fsm.start {
                Some(k) => format!("{st} := 3; {q} := {k}; {pz} := false; {due} := true"),
                None if self.done.is_empty() && self.ended.is_none() && self.phase.is_none() => {
                    format!("{st} := 0")
                }
                None => {
                    ends = true;
                    super::stops::block(&self.end_slot(p, sl, true))
                }
            };
            out.push(format!("if {st} = 2 then {start} elsif {resume} end"));
        }
        if ends {
            let settle = self.settle(p);
            if !settle.is_empty() {
                out.push(super::stops::block(&settle));
            }
        }
        out.join("; ")
    }

    /// Whether slot `s` may be on a stop path (status 4): something
    /// interrupts it, or it is a permanent activity `kill` stops.
    pub(super) fn may_stop(&self, s: &SlotL) -> bool {
        s.fl.is_some() || (self.phase.is_some() && self.r.slots[s.read].service.is_none())
    }

    fn manager_process(&self, t: &TaskL) -> Proc {
        let mut p = Proc::new(
            &t.manager,
            format!(
                "Task {}{}: its manager. {}; then it sweeps its slots (1.4): every due slot runs one codel (its process begins it), in any order (15.2), one at a time; after a sweep with an unpaused transition it sweeps again at once.",
                t.name,
                at(self, t.span),
                match t.period {
                    Some(_) =>
                        "At each tick it starts the accepted instances and resumes the paused ones (only at a tick, 1.5)",
                    None =>
                        "Without a period it is activated at any time while an instance is accepted, running or stopping (15.4; as the network)",
                }
            ),
            &["sleep", "sweep"],
        );
        let alive = self.alive(&mut p);
        let booted = p.v(self, self.booted);
        let (work, cont, running) = (p.v(self, t.work), p.v(self, t.cont), p.v(self, t.running));
        let wake = self.pre_pass(&mut p, t, true);
        let wake = if wake.is_empty() {
            String::new()
        } else {
            format!("{wake}; ")
        };
        let spawned = format!("{alive} and {booted} >= {}", t.index);
        let sleep = match t.period {
            Some(_) => {
                let tick = p.v(self, t.tick);
                vec![format!(
                    "wait [0,0]; on {tick}; {tick} := false; if {spawned} then {wake}{cont} := false; {work} := true; to sweep else loop end"
                )]
            }
            None => {
                let waiting: Vec<String> = t
                    .slots
                    .iter()
                    .map(|&s| format!("{} >= 2", p.v(self, self.slots[s].st)))
                    .collect();
                if waiting.is_empty() {
                    Vec::new()
                } else {
                    vec![format!(
                        "on {spawned} and ({}); {wake}{cont} := false; {work} := true; to sweep",
                        waiting.join(" or ")
                    )]
                }
            }
        };
        p.from("sleep", "", &sleep);
        let dues: Vec<String> = t
            .slots
            .iter()
            .map(|&s| p.v(self, self.slots[s].due))
            .collect();
        let mut alts = Vec::new();
        let none_due = if dues.is_empty() {
            String::new()
        } else {
            format!(" and not ({})", dues.join(" or "))
        };
        let again = self.pre_pass(&mut p, t, t.period.is_none());
        let again = if again.is_empty() {
            String::new()
        } else {
            format!("{again}; ")
        };
        alts.push(format!(
            "/* sweep again */ wait [0,0]; on {alive} and not {running}{none_due} and {cont}; {cont} := false; {again}to sweep"
        ));
        alts.push(format!(
            "/* the work of this wake-up is done */ wait [0,0]; on {alive} and not {running}{none_due} and not {cont}; {work} := false; to sleep"
        ));
        p.from("sweep", "", &alts);
        p
    }

    /// How slot `s` begins the codel of its state when it is due and its
    /// task runs no codel: at once, or (with locks) when its locks are free
    /// and the resource FIFO lets it, after taking a ticket if they are
    /// not (8.3, 15.5). Its codel states are named `states`.
    fn begins(&self, p: &mut Proc, t: &TaskL, sl: &SlotL) -> Vec<String> {
        let alive = self.alive(p);
        let running = p.v(self, t.running);
        let (due, q) = (p.v(self, sl.due), p.v(self, sl.q));
        let ready = format!("{alive} and not {running} and {due}");
        let mut go = format!("{due} := false; {running} := true");
        if let Some(cur) = t.cur {
            go.push_str(&format!("; {} := {}", p.v(self, cur), sl.turn));
        }
        let th = super::control::Thread::Task(t.index);
        let mut alts = Vec::new();
        for (k, st) in self.r.slots[sl.read].fsm.states.iter().enumerate() {
            let at = format!("{ready} and {q} = {k}");
            let to = &sl.states[k];
            let Some(tf) = t.fifo else {
                alts.push(format!("wait [0,0]; on {at}; {go}; to {to}"));
                continue;
            };
            if st.is_async {
                // No lock and no ticket (7.2): it begins when its task
                // holds no ticket.
                let pos = p.v(self, tf.pos);
                alts.push(format!(
                    "/* async */ wait [0,0]; on {at} and {pos} = 0; {go}; to {to}"
                ));
                continue;
            }
            let run = p.v(self, tf.run);
            let begin = self
                .may_begin(p, th, Some(sl.turn), st.key)
                .unwrap_or_else(|| "true".into());
            let leave = self.leave_queue(p, th);
            alts.push(format!(
                "wait [0,0]; on {at} and {begin}; {leave}{go}; {run} := {}; to {to}",
                st.key + 1
            ));
            if let Some(w) = self.must_wait(p, th, st.key) {
                let take = self.take_ticket(p, th, Some(sl.turn));
                alts.push(format!(
                    "/* a ticket for state {} */ wait [0,0]; on {at} and {w}; {take}; loop",
                    st.name
                ));
            }
        }
        alts
    }

    fn slot_process(&self, s: &SlotL) -> Proc {
        let rs = &self.r.slots[s.read];
        let t = &self.tasks[s.task];
        let mut states = vec!["idle"];
        states.extend(s.states.iter().map(String::as_str));
        let mut p = Proc::new(
            &s.process,
            format!(
                "Task {}: {} (slot {} of its sweep).",
                t.name, s.what, s.turn
            ),
            &states,
        );
        let begin = self.begins(&mut p, t, s);
        p.from("idle", "due, it begins its codel", &begin);
        let killed = self.killed(&mut p, s);
        for (k, st) in rs.fsm.states.iter().enumerate() {
            let w = self.units(st.wcet_ns);
            let note = format!(
                "codel {} in state {}{}, {}",
                self.codel_name(st),
                st.name,
                at(self, st.span),
                if !self.timed {
                    "untimed: any duration".to_owned()
                } else if st.is_async {
                    format!(
                        "async: at least {}, no upper bound",
                        genom_model::duration::format_ns(st.wcet_ns)
                    )
                } else if st.wcet_ns == 0 {
                    "no WCET: takes no time".to_owned()
                } else {
                    format!("WCET {}", genom_model::duration::format_ns(st.wcet_ns))
                }
            );
            let wait = if !self.timed {
                "wait [0,...[".to_owned()
            } else if st.is_async {
                format!("wait [{w},...[")
            } else {
                format!("wait [0,{w}]")
            };
            let (ends, tail) = self.outcomes(&mut p, s, st);
            let select = match ends.as_slice() {
                [one] => one.clone(),
                _ => format!("select\n      {}\n    end", ends.join("\n    []\n      ")),
            };
            let body = match &killed {
                None => format!("{wait};\n    {select};\n    {tail}"),
                Some(cond) => format!(
                    "select\n      {wait}; if {cond} then to idle else {select}; {tail} end\n    []\n      /* killed by the shutdown: forgotten */ wait [0,0]; on {cond}; to idle\n    end"
                ),
            };
            let _ = writeln!(
                p.froms,
                "  from {}  /* {} */\n    {body}",
                s.states[k],
                comment(&note)
            );
        }
        p
    }

    /// With `kill`, the condition under which permanent slot `s`'s codel
    /// was killed by the shutdown (its task no longer runs it).
    fn killed(&self, p: &mut Proc, s: &SlotL) -> Option<String> {
        self.phase?;
        if self.r.slots[s.read].service.is_some() {
            return None;
        }
        let cur = self.tasks[s.task].cur?;
        Some(format!("{} <> {}", p.v(self, cur), s.turn))
    }

    /// A codel state: the `wait` of its duration, then a `select` of its
    /// outcomes (`ends[0]` carries the `wait`).
    pub(super) fn select_after_wait(&self, p: &mut Proc, state: &str, note: &str, ends: &[String]) {
        if ends.len() == 1 {
            p.from(state, note, ends);
            return;
        }
        let Some((wait, first)) = ends[0].split_once("; ") else {
            p.from(state, note, ends);
            return;
        };
        let mut alts = vec![first.to_owned()];
        alts.extend(ends[1..].iter().cloned());
        let mut body = format!("{wait};\n    select");
        for (i, a) in alts.iter().enumerate() {
            if i > 0 {
                body.push_str("\n    []");
            }
            let _ = write!(body, "\n      {a}");
        }
        body.push_str("\n    end");
        let _ = writeln!(
            p.froms,
            "  from {state}  /* {} */\n    {body}",
            comment(note)
        );
    }

    fn codel_name(&self, st: &State) -> String {
        st.codel.map_or_else(
            || st.name.clone(),
            |k| self.input.component.codels[k].name.name.clone(),
        )
    }

    /// The outcomes of a codel (9.1): each yield, the end (`ether`, or an
    /// exception, which ends the instance the same way), and for the
    /// permanent activity an exception at boot, which fails the start
    /// (9.4); and what follows every one of them (the task runs no codel,
    /// the steps that follow at once, back to `idle`).
    fn outcomes(&self, p: &mut Proc, s: &SlotL, st: &State) -> (Vec<String>, String) {
        use super::stops::block;
        let t = &self.tasks[s.task];
        let (running, cont) = (p.v(self, t.running), p.v(self, t.cont));
        let running = match t.fifo {
            Some(f) => format!("{} := 0; {running}", p.v(self, f.run)),
            None => running,
        };
        let running = match t.cur {
            Some(c) => format!("{} := 0; {running}", p.v(self, c)),
            None => running,
        };
        let settle = self.settle(p);
        let tail = format!("{running} := false; {settle}to idle");
        let (stv, q, pz) = (p.v(self, s.st), p.v(self, s.q), p.v(self, s.pz));
        let perm = self.r.slots[s.read].service.is_none();
        let boot = if perm {
            let b = p.v(self, self.booted);
            format!(
                "if {b} = {} then {b} := {} end; ",
                t.index,
                self.next_boot(t.index)
            )
        } else {
            String::new()
        };
        let mut seen = BTreeSet::new();
        let mut out = Vec::new();
        for &(next, pause) in &st.yields {
            let Some(n) = next else { continue };
            if !seen.insert((n, pause)) {
                continue;
            }
            let name = &self.r.slots[s.read].fsm.states[n].name;
            let unpaused = if pause {
                String::new()
            } else {
                format!("{cont} := true; ")
            };
            let mut land = format!("{q} := {n}; {pz} := {pause}; ");
            if let (Some(fl), false) = (s.fl, perm) {
                // Interrupted while it ran: to `stop` (15.6).
                let fl = p.v(self, fl);
                land = format!(
                    "if {fl} and {stv} = 3 then {} else {}; {fl} := false end; ",
                    block(&self.to_stop(p, s)),
                    block(&land)
                );
            }
            out.push(format!(
                "/* yield {}{name} */ {}",
                if pause { "pause::" } else { "" },
                block(&format!("{land}{unpaused}{boot}"))
            ));
        }
        if !perm {
            let ok = self.end_slot(p, s, true);
            let ko = self.end_slot(p, s, false);
            if st.yields.iter().any(|y| y.0.is_none()) {
                out.push(format!("/* ether: the instance ends */ {}", block(&ok)));
            }
            out.push(format!(
                "/* an exception: the instance ends */ {}",
                block(&ko)
            ));
            return (out, tail);
        }
        let end = if self.phase.is_some() {
            self.clear(p, s)
        } else {
            format!("{stv} := 0; {q} := 0; {pz} := false; ")
        };
        let (b, f) = (p.v(self, self.booted), p.v(self, self.failed));
        if st.yields.iter().any(|y| y.0.is_none()) {
            out.push(format!(
                "/* ether: the activity ends */ {}",
                block(&format!("{boot}{end}"))
            ));
        }
        out.push(format!(
            "/* an exception: the activity ends; at boot, the component's start fails (9.4) */ if {b} = {} then {f} := true end; {}",
            t.index,
            block(&end)
        ));
        (out, tail)
    }
}
