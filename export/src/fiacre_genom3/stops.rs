//! Interruption, the end of an instance and the shutdown, as Fiacre
//! statements (docs/genom3-semantics.md 5, 10.2, 15.6 and 15.8), in the
//! reading the UPPAAL/TChecker network of the component makes of them
//! (`genom_translate::timed_automata::genom3`, its `stmts` module): a
//! slot is interrupted (ended if accepted, flagged if its codel runs or is
//! due, else sent to its `stop` state), a request's effect (an accepted
//! instance, or a function's interruptions and `kill`'s drain), and the
//! steps that follow at once in the same transition: the pending
//! interrupters re-examined while instances end (5.3), and the shutdown
//! (the permanent stop paths, last task first, once `kill` drained every
//! instance).
//!
//! Every function returns statements each followed by `; ` (or nothing),
//! to be put before the rest of a transition.

use genom_translate::timed_automata::genom3::read::CtlKind;

use super::control::Thread;
use super::layout::{Layout, ReqKind, Request, SlotL};
use super::process::Proc;

/// Statements with their trailing `; ` as one statement list (`null`
/// when empty), for `then ... end`.
pub(super) fn block(s: &str) -> String {
    let s = s.trim_end().trim_end_matches(';').trim_end();
    if s.is_empty() {
        "null".to_owned()
    } else {
        s.to_owned()
    }
}

impl Layout<'_> {
    /// The component runs: its start did not fail, and `kill` did not
    /// stop it.
    pub(super) fn alive(&self, p: &mut Proc) -> String {
        let failed = p.v(self, self.failed);
        match self.phase {
            Some(ph) => format!("not {failed} and {} < 4", p.v(self, ph)),
            None => format!("not {failed}"),
        }
    }

    /// The component takes requests: booted, and not shut down.
    pub(super) fn serving(&self, p: &mut Proc) -> String {
        let (booted, failed) = (p.v(self, self.booted), p.v(self, self.failed));
        let phase = self
            .phase
            .map_or_else(String::new, |ph| format!(" and {} = 0", p.v(self, ph)));
        format!("not {failed} and {booted} = {}{phase}", self.tasks.len())
    }

    /// `after`/`before` admit request `r` (4.1, 4.2), as ` and ...`.
    pub(super) fn admissible(&self, p: &mut Proc, r: &Request) -> String {
        let mut out = String::new();
        for (list, want) in [(&self.r.after, ""), (&self.r.before, "not ")] {
            for x in list.get(&r.service).into_iter().flatten() {
                if let Some(&d) = self.done.get(x) {
                    out.push_str(&format!(" and {want}{}", p.v(self, d)));
                }
            }
        }
        out
    }

    /// Slot `s`'s codel runs.
    fn busy(&self, p: &mut Proc, s: &SlotL) -> Option<String> {
        let cur = self.tasks[s.task].cur?;
        Some(format!("{} = {}", p.v(self, cur), s.turn))
    }

    /// Slot `s`'s task drops its ticket for it, if it holds one.
    pub(super) fn drop_ticket(&self, p: &mut Proc, s: &SlotL) -> String {
        let Some(f) = self.tasks[s.task].fifo else {
            return String::new();
        };
        let leave = self.leave_queue(p, Thread::Task(s.task));
        format!(
            "if {} = {} then {} end; ",
            p.v(self, f.slot),
            s.turn,
            block(&leave)
        )
    }

    /// Empties slot `s`.
    pub(super) fn clear(&self, p: &mut Proc, s: &SlotL) -> String {
        let mut out = self.drop_ticket(p, s);
        out.push_str(&format!(
            "{} := 0; {} := 0; {} := false; {} := false; ",
            p.v(self, s.st),
            p.v(self, s.q),
            p.v(self, s.due),
            p.v(self, s.pz)
        ));
        if let Some(fl) = s.fl {
            out.push_str(&format!("{} := false; ", p.v(self, fl)));
        }
        out
    }

    /// `done_S := true` for service `sid`, when some `after`/`before`
    /// names it.
    pub(super) fn mark_done(&self, p: &mut Proc, sid: genom_model::component::ServiceId) -> String {
        self.done
            .get(&sid)
            .map_or_else(String::new, |&d| format!("{} := true; ", p.v(self, d)))
    }

    /// Slot `s` ends (`success`: it reached `ether`, which counts for
    /// `after`, 4.1).
    pub(super) fn end_slot(&self, p: &mut Proc, s: &SlotL, success: bool) -> String {
        let mut out = self.clear(p, s);
        let Some(sid) = self.r.slots[s.read].service else {
            return out;
        };
        if success {
            out.push_str(&self.mark_done(p, sid));
        }
        if let Some(e) = self.ended {
            out.push_str(&format!("{} := true; ", p.v(self, e)));
        }
        out
    }

    /// Slot `s` on its way to `stop` (or ended, without a stop codel).
    pub(super) fn to_stop(&self, p: &mut Proc, s: &SlotL) -> String {
        match self.r.slots[s.read].fsm.stop {
            Some(stop) => {
                let mut out = format!(
                    "{} := 4; {} := {stop}; {} := false; ",
                    p.v(self, s.st),
                    p.v(self, s.q),
                    p.v(self, s.pz)
                );
                if let Some(fl) = s.fl {
                    out.push_str(&format!("{} := false; ", p.v(self, fl)));
                }
                out
            }
            None => self.end_slot(p, s, false),
        }
    }

    /// Interrupts slot `b` (`spare`: not if accepted and not started):
    /// an accepted one ends; a running one whose codel runs or is due is
    /// flagged (it goes to `stop` after that codel), another goes to
    /// `stop` at once; a stopping one is left alone (5.1-5.5, 15.6).
    pub(super) fn flag(&self, p: &mut Proc, b: usize, spare: bool) -> String {
        let s = &self.slots[b];
        let (Some(fl), Some(busy)) = (s.fl, self.busy(p, s)) else {
            return String::new();
        };
        let st = p.v(self, s.st);
        let mut out = String::new();
        if !spare {
            let end = self.end_slot(p, s, false);
            out.push_str(&format!(
                "if {st} = 1 or {st} = 2 then {} end; ",
                block(&end)
            ));
        }
        let (due, fl) = (p.v(self, s.due), p.v(self, fl));
        let stop = self.to_stop(p, s);
        out.push_str(&format!(
            "if {st} = 3 then if {busy} or {due} then {fl} := true else {} end end; ",
            block(&stop)
        ));
        out
    }

    /// Slot `b` is on its way to end by an interruption.
    fn stopping(&self, p: &mut Proc, b: usize) -> String {
        let s = &self.slots[b];
        let st = p.v(self, s.st);
        match s.fl {
            Some(fl) => format!("{st} = 4 or {}", p.v(self, fl)),
            None => format!("{st} = 4"),
        }
    }

    /// A request accepted into free slot `a`: it interrupts its targets
    /// (its activity's other instances too when it interrupts itself) and
    /// is accepted, or delayed while one of them stops (5.1, 5.3).
    fn accept_into(&self, p: &mut Proc, a: usize) -> String {
        let targets: Vec<usize> = self.slots[a]
            .targets
            .iter()
            .copied()
            .filter(|&b| b != a)
            .collect();
        let mut out = String::new();
        for &b in &targets {
            out.push_str(&self.flag(p, b, false));
        }
        let st = p.v(self, self.slots[a].st);
        if targets.is_empty() {
            out.push_str(&format!("{st} := 2; "));
        } else {
            let delayed: Vec<String> = targets.iter().map(|&b| self.stopping(p, b)).collect();
            out.push_str(&format!(
                "if {} then {st} := 1 else {st} := 2 end; ",
                delayed.join(" or ")
            ));
        }
        out
    }

    /// What request `r` does once its control codels succeeded, then the
    /// steps that follow at once.
    pub(super) fn effect(&self, p: &mut Proc, r: &Request) -> String {
        let mut out = String::new();
        match r.kind {
            ReqKind::Accept => {
                if r.slots.is_empty() {
                    return out;
                }
                for (i, &a) in r.slots.iter().enumerate() {
                    let st = p.v(self, self.slots[a].st);
                    let kw = if i == 0 { "if" } else { " elsif" };
                    let acc = self.accept_into(p, a);
                    out.push_str(&format!("{kw} {st} = 0 then {}", block(&acc)));
                }
                out.push_str(" end; ");
            }
            ReqKind::Call(k) => {
                let ctl = &self.r.controls[k];
                out.push_str(&self.mark_done(p, ctl.service));
                for b in self.copies(&ctl.interrupts) {
                    out.push_str(&self.flag(p, b, false));
                }
                if let (CtlKind::Kill, Some(ph)) = (ctl.kind, self.phase) {
                    out.push_str(&format!("{} := 2; ", p.v(self, ph)));
                }
            }
        }
        out.push_str(&self.settle(p));
        out
    }

    /// `abort_activity` on slot `a` (5.6): it interrupts that instance.
    pub(super) fn abort(&self, p: &mut Proc, a: usize) -> String {
        let mut out = self
            .abort
            .map_or_else(String::new, |s| self.mark_done(p, s));
        out.push_str(&self.flag(p, a, false));
        out.push_str(&self.settle(p));
        out
    }

    /// The steps that follow at once: the pending interrupters
    /// re-examined while instances end (5.3), then the shutdown.
    pub(super) fn settle(&self, p: &mut Proc) -> String {
        let mut out = String::new();
        if let Some(e) = self.ended {
            let e = p.v(self, e);
            let mut body = format!("{e} := false; ");
            for (a, s) in self.slots.iter().enumerate() {
                if s.targets.is_empty() {
                    continue;
                }
                let own = self.r.slots[s.read].service;
                let mut inner = String::new();
                for &b in &s.targets {
                    let spare = self.r.slots[self.slots[b].read].service == own;
                    inner.push_str(&self.flag(p, b, spare));
                }
                let delayed: Vec<String> = s.targets.iter().map(|&b| self.stopping(p, b)).collect();
                let st = p.v(self, self.slots[a].st);
                inner.push_str(&format!(
                    "if {st} = 1 and not ({}) then {st} := 2 end",
                    delayed.join(" or ")
                ));
                body.push_str(&format!("if {st} = 1 or {st} = 2 then {inner} end; "));
            }
            out.push_str(&format!("while {e} do {} end; ", block(&body)));
        }
        out.push_str(&self.shutdown(p));
        out
    }

    /// The shutdown (10.2): once `kill` drained every instance, the
    /// permanent activities' codels are forgotten and their stop paths
    /// run, last task first; then the component stops.
    fn shutdown(&self, p: &mut Proc) -> String {
        let (Some(ph), Some(ps)) = (self.phase, self.pstop) else {
            return String::new();
        };
        let (phase, pstop) = (p.v(self, ph), p.v(self, ps));
        let n = self.tasks.len();
        let mut drained = vec![format!("{phase} = 2")];
        let mut body = format!("{phase} := 3; {pstop} := {n}; ");
        let mut ended = vec![format!("{pstop} = {n}")];
        for s in &self.slots {
            if self.r.slots[s.read].service.is_some() {
                drained.push(format!("{} = 0", p.v(self, s.st)));
                continue;
            }
            body.push_str(&self.clear(p, s));
            let t = &self.tasks[s.task];
            if let (Some(cur), Some(busy)) = (t.cur, self.busy(p, s)) {
                let mut kill =
                    format!("{} := 0; {} := false", p.v(self, cur), p.v(self, t.running));
                if let Some(f) = t.fifo {
                    kill.push_str(&format!("; {} := 0", p.v(self, f.run)));
                }
                body.push_str(&format!("if {busy} then {kill} end; "));
            }
            ended.push(format!(
                "({pstop} = {} and {} = 0)",
                s.task,
                p.v(self, s.st)
            ));
        }
        let mut out = format!("if {} then {} end; ", drained.join(" and "), block(&body));
        let mut chain = String::new();
        for below in 0..=n {
            let kw = if below == 0 { " if" } else { " elsif" };
            let next = self.next_perm_stop(p, below);
            chain.push_str(&format!("{kw} {pstop} = {below} then {}", block(&next)));
        }
        out.push_str(&format!(
            "if {phase} = 3 and ({}) then{chain} end end; ",
            ended.join(" or ")
        ));
        out
    }

    /// The last task before `below` with a permanent stop codel goes on
    /// its stop path, or the component stops.
    fn next_perm_stop(&self, p: &mut Proc, below: usize) -> String {
        let (Some(ph), Some(ps)) = (self.phase, self.pstop) else {
            return String::new();
        };
        for t in (0..below).rev() {
            let Some(s) = self.tasks[t]
                .slots
                .iter()
                .map(|&k| &self.slots[k])
                .find(|s| self.r.slots[s.read].service.is_none())
            else {
                continue;
            };
            let Some(stop) = self.r.slots[s.read].fsm.stop else {
                continue;
            };
            let mut out = self.drop_ticket(p, s);
            out.push_str(&format!(
                "{} := 4; {} := {stop}; {} := false; {} := false; {} := {t}; ",
                p.v(self, s.st),
                p.v(self, s.q),
                p.v(self, s.pz),
                p.v(self, s.due),
                p.v(self, ps)
            ));
            return out;
        }
        format!("{} := 4; ", p.v(self, ph))
    }
}
