//! The control task and GenoM3's locks (docs/genom3-semantics.md 6, 8 and
//! 15.5): the conditions under which a codel may begin (no codel of its
//! exclusion list runs), GenoM3's resource FIFO (a thread that cannot
//! begin takes a ticket; only the head of the queue may begin: head-of-line
//! blocking), and the control task's process, whose contended control
//! codels (validate, a function's codels, an attribute's ids copy) wait
//! for their locks and run `wait [0,WCET]` like a task's.

use super::layout::{Layout, Request};
use super::process::Proc;

/// The thread a codel runs in: a task (index) or the control task.
#[derive(Clone, Copy)]
pub(super) enum Thread {
    Task(usize),
    Control,
}

impl Layout<'_> {
    /// `(key + 1 running) <> j + 1` for every key `j` the codel of key `k`
    /// waits for (8.2), on thread `th`; `None` when it waits for none.
    pub(super) fn lock_free(&self, p: &mut Proc, k: usize) -> Option<String> {
        let fifo = self.fifo?;
        let mut out = Vec::new();
        for &j in &self.r.keys[k].excl {
            let run = match self.r.keys[j].task {
                Some(u) => self.tasks[u].fifo?.run,
                None => fifo.crun,
            };
            out.push(format!("{} <> {}", p.v(self, run), j + 1));
        }
        (!out.is_empty()).then(|| out.join(" and "))
    }

    fn pos(&self, th: Thread) -> Option<usize> {
        match th {
            Thread::Task(t) => self.tasks[t].fifo.map(|f| f.pos),
            Thread::Control => self.fifo.map(|f| f.cpos),
        }
    }

    /// A codel of thread `th` (for the slot of turn `turn`) may begin: its
    /// locks are free, and it holds the head of the queue or no one waits.
    pub(super) fn may_begin(
        &self,
        p: &mut Proc,
        th: Thread,
        turn: Option<usize>,
        k: usize,
    ) -> Option<String> {
        let (fifo, pos) = (self.fifo?, self.pos(th)?);
        let (len, pos) = (p.v(self, fifo.len), p.v(self, pos));
        let mine = match (th, turn) {
            (Thread::Task(t), Some(i)) => {
                let slot = self.tasks[t].fifo?.slot;
                format!(" and {} = {i}", p.v(self, slot))
            }
            _ => String::new(),
        };
        let free = self
            .lock_free(p, k)
            .map_or_else(String::new, |f| format!("{f} and "));
        Some(format!(
            "{free}(({pos} = 0 and {len} = 0) or ({pos} = 1{mine}))"
        ))
    }

    /// A codel of thread `th` must take a ticket: it has none, and someone
    /// waits or its locks are taken.
    pub(super) fn must_wait(&self, p: &mut Proc, th: Thread, k: usize) -> Option<String> {
        let (fifo, pos) = (self.fifo?, self.pos(th)?);
        let (len, pos) = (p.v(self, fifo.len), p.v(self, pos));
        let free = self
            .lock_free(p, k)
            .map_or_else(String::new, |f| format!(" and {f}"));
        Some(format!("{pos} = 0 and not ({len} = 0{free})"))
    }

    /// Takes a ticket (for the slot of turn `turn`).
    pub(super) fn take_ticket(&self, p: &mut Proc, th: Thread, turn: Option<usize>) -> String {
        let (Some(fifo), Some(pos)) = (self.fifo, self.pos(th)) else {
            return String::new();
        };
        let (len, pos) = (p.v(self, fifo.len), p.v(self, pos));
        let mut out = format!("{pos} := {len} + 1; {len} := {len} + 1");
        if let (Thread::Task(t), Some(i), Some(f)) = (th, turn, self.tasks_fifo(th)) {
            let _ = t;
            out.push_str(&format!("; {} := {i}", p.v(self, f)));
        }
        out
    }

    fn tasks_fifo(&self, th: Thread) -> Option<usize> {
        match th {
            Thread::Task(t) => self.tasks[t].fifo.map(|f| f.slot),
            Thread::Control => None,
        }
    }

    /// Leaves the queue, if thread `th` holds a ticket (the ones behind
    /// move up), followed by `; ` when not empty.
    pub(super) fn leave_queue(&self, p: &mut Proc, th: Thread) -> String {
        let (Some(fifo), Some(me)) = (self.fifo, self.pos(th)) else {
            return String::new();
        };
        let me = p.v(self, me);
        let mut body = Vec::new();
        let others = (0..self.tasks.len())
            .map(Thread::Task)
            .chain([Thread::Control])
            .filter(|u| !same(*u, th));
        for u in others {
            if let Some(o) = self.pos(u) {
                let o = p.v(self, o);
                body.push(format!("if {o} > {me} then {o} := {o} - 1 end"));
            }
        }
        let len = p.v(self, fifo.len);
        body.push(format!("{len} := {len} - 1"));
        body.push(format!("{me} := 0"));
        if let Some(f) = self.tasks_fifo(th) {
            body.push(format!("{} := 0", p.v(self, f)));
        }
        format!("if {me} > 0 then {} end; ", body.join("; "))
    }

    /// The control task: it takes each request (4, 6.1); the control codels
    /// of a request that some task's codel contends wait for their locks
    /// and run in turn; then an activity's instance is accepted.
    pub(super) fn control_process(&self) -> Proc {
        let mut states = vec!["serve".to_owned()];
        for r in &self.requests {
            for &j in &r.timed {
                let (w, run) = self.ctl_states(r, j);
                states.extend([w, run]);
            }
        }
        let names: Vec<&str> = states.iter().map(String::as_str).collect();
        let mut p = Proc::new(
            &self.control,
            "The control task: it takes one request at a time (6.1). Control codels that no task's codel contends take no time a task sees (15.5) and are not modelled; the contended ones wait for their locks in the resource FIFO and take [0, WCET] each; an exception ends the request.".to_owned(),
            &names,
        );
        let mut serve = Vec::new();
        let serving = self.serving(&mut p);
        for r in &self.requests {
            let Some(rq) = r.rq else { continue };
            let rq = p.v(self, rq);
            let what = self.service_name(r).to_owned();
            let next = match r.timed.first() {
                Some(&j) => format!("to {}", self.ctl_states(r, j).0),
                None => format!("{}loop", self.effect(&mut p, r)),
            };
            // Taken when it is still admissible (`after`, `before`, not
            // shut down), else refused.
            let ok = self.admissible(&mut p, r);
            let ok = if self.phase.is_some() {
                format!("{serving}{ok}")
            } else {
                ok.trim_start_matches(" and ").to_owned()
            };
            if ok.is_empty() {
                serve.push(format!(
                    "/* take {what} */ wait [0,0]; on {rq}; {rq} := false; {next}"
                ));
            } else {
                serve.push(format!(
                    "/* take {what} */ wait [0,0]; on {rq} and {ok}; {rq} := false; {next}"
                ));
                serve.push(format!(
                    "/* refuse {what} */ wait [0,0]; on {rq} and not ({ok}); {rq} := false; loop"
                ));
            }
        }
        serve.extend(self.aborts(&mut p));
        p.from("serve", "", &serve);
        for r in &self.requests {
            for (n, &j) in r.timed.iter().enumerate() {
                self.control_codel(&mut p, r, n, j);
            }
        }
        p
    }

    /// The states where control codel `j` of request `r` waits and runs.
    fn ctl_states(&self, r: &Request, j: usize) -> (String, String) {
        let name = self.ctl_codel(r, j).map_or("codel", |k| k.name.as_str());
        let base = format!("{}_{name}", self.service_name(r));
        let clean: String = base
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '_' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        (format!("wait_{clean}"), format!("run_{clean}"))
    }

    fn ctl_codel(
        &self,
        r: &Request,
        j: usize,
    ) -> Option<&genom_translate::timed_automata::genom3::read::CtlCodel> {
        self.r.ctl_codels.get(&r.service)?.get(j)
    }

    fn control_codel(&self, p: &mut Proc, r: &Request, n: usize, j: usize) {
        let Some(codel) = self.ctl_codel(r, j) else {
            return;
        };
        let (wait, run) = self.ctl_states(r, j);
        let k = codel.key;
        let Some(fifo) = self.fifo else { return };
        let crun = p.v(self, fifo.crun);
        let begin = self
            .may_begin(p, Thread::Control, None, k)
            .unwrap_or_else(|| "true".into());
        let leave = self.leave_queue(p, Thread::Control);
        let mut alts = vec![format!(
            "/* its locks are free */ wait [0,0]; on {begin}; {leave}{crun} := {}; to {run}",
            k + 1
        )];
        if let Some(w) = self.must_wait(p, Thread::Control, k) {
            let take = self.take_ticket(p, Thread::Control, None);
            alts.push(format!(
                "/* it takes a ticket */ wait [0,0]; on {w}; {take}; loop"
            ));
        }
        p.from(
            &wait,
            &format!("{} of {}", codel.name, self.service_name(r)),
            &alts,
        );
        let done = match r.timed.get(n + 1) {
            Some(&next) => format!("to {}", self.ctl_states(r, next).0),
            None => format!("{}to serve", self.effect(p, r)),
        };
        let wait = if self.timed {
            format!("wait [0,{}]", self.units(codel.wcet_ns))
        } else {
            "wait [0,...[".to_owned()
        };
        let mut ends = vec![format!("{wait}; /* it succeeds */ {crun} := 0; {done}")];
        if !codel.copy {
            ends.push(format!(
                "/* an exception ends the request */ {crun} := 0; to serve"
            ));
        }
        self.select_after_wait(p, &run, &format!("{} runs", codel.name), &ends);
    }
}

fn same(a: Thread, b: Thread) -> bool {
    match (a, b) {
        (Thread::Task(x), Thread::Task(y)) => x == y,
        (Thread::Control, Thread::Control) => true,
        _ => false,
    }
}
