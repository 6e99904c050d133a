//! Writes the Promela text of a GenoM3 component: the constants and state
//! variables, the reachability markers, the inlines shared by every step
//! (`flag_A`: an interruption of activity `A`'s instance; `settle`: the
//! boot order, the re-examination of pending interrupters, the shutdown
//! sequence), then the one process (its steps, from [`super::steps`], are
//! given).

use std::collections::BTreeSet;
use std::fmt::Write as _;

use genom_model::component::{Component, Idx, ServiceId};

use super::reading::Reading;

/// The model being written: the reading, and the markers allocated so far.
pub struct Model<'a> {
    /// The component.
    pub c: &'a Component,
    /// Its reading.
    pub r: &'a Reading,
    /// Services whose completion `after`/`before` read (`done_I` exists).
    pub watched: BTreeSet<ServiceId>,
    /// One comment per marker `m_N` (index N).
    pub markers: Vec<String>,
}

impl<'a> Model<'a> {
    /// A model with no marker yet.
    pub fn new(c: &'a Component, r: &'a Reading) -> Self {
        Model {
            c,
            r,
            watched: r.watched(),
            markers: Vec::new(),
        }
    }

    /// Allocates a marker described by `what`; its statement `m_N = 1`.
    pub fn marker(&mut self, what: String) -> String {
        let n = self.markers.len();
        self.markers.push(what);
        format!("m_{n} = 1")
    }

    /// The whole text after the header, the process offering `options`
    /// (the steps, which allocated their markers in this model).
    pub fn write(self, options: Vec<String>) -> String {
        let process = Self::process(options);
        let mut out = String::new();
        constants(&mut out);
        self.declarations(&mut out);
        self.flags(&mut out);
        self.settle(&mut out);
        out.push_str(&process);
        out
    }

    fn declarations(&self, out: &mut String) {
        out.push_str(
            "byte phase = P_BOOT;  /* the component's life cycle */\n\
             byte booted = 0;      /* tasks whose permanent activity ran its first codel (boot) */\n\
             byte pstop = 0;       /* index in the shutdown order of the stop path running */\n\
             hidden byte ended;    /* scratch: an instance ended in this step */\n\
             hidden byte booting;  /* scratch: this permanent codel is its task's first */\n\n",
        );
        for (t, task) in self.r.tasks.iter().enumerate() {
            let states: Vec<String> = task
                .fsm
                .states
                .iter()
                .enumerate()
                .map(|(i, s)| format!("{i} {}", s.name))
                .collect();
            let init = task.fsm.start.map_or((0, 0), |s| (1, s));
            let _ = writeln!(
                out,
                "bit pon_{t} = {}; byte pat_{t} = {};  /* task `{}`, permanent states: {} */",
                init.0,
                init.1,
                task.name,
                list(&states)
            );
        }
        for (a, act) in self.r.activities.iter().enumerate() {
            let states: Vec<String> = act
                .fsm
                .states
                .iter()
                .enumerate()
                .map(|(i, s)| format!("{i} {}", s.name))
                .collect();
            let _ = writeln!(
                out,
                "byte st_{a} = IDLE; byte at_{a};  /* activity `{}` on task `{}`, states: {} */",
                act.name,
                self.r.tasks[act.task].name,
                list(&states)
            );
        }
        for s in &self.watched {
            let _ = writeln!(
                out,
                "bit done_{};  /* `{}` completed successfully (run_map) */",
                s.index(),
                self.c.services[*s].name.name
            );
        }
        out.push_str("\n/* reachability markers: hidden, not part of the state */\n");
        for (n, what) in self.markers.iter().enumerate() {
            let _ = writeln!(out, "hidden byte m_{n};  /* {what} */");
        }
        out.push('\n');
    }

    /// `flag_A`: the interruption of activity `A`'s instance (5.1, 5.2,
    /// 5.4, 5.5 read at once, 14.3).
    fn flags(&self, out: &mut String) {
        for (a, act) in self.r.activities.iter().enumerate() {
            let running = match act.fsm.stop {
                Some(stop) => format!("st_{a} = STOP; at_{a} = {stop}  /* its stop path */"),
                None => format!("st_{a} = IDLE; at_{a} = 0; ended = 1  /* interrupted */"),
            };
            let _ = writeln!(
                out,
                "inline flag_{a}() {{  /* `{}` is interrupted */\n  if\n  \
                 :: st_{a} == DELAYED || st_{a} == READY -> st_{a} = IDLE; ended = 1\n  \
                 :: st_{a} == RUN -> {running}\n  \
                 :: else -> skip  /* idle, or already stopping */\n  fi\n}}",
                act.name
            );
        }
        out.push('\n');
    }

    /// `settle`: what follows every step at once.
    fn settle(&self, out: &mut String) {
        out.push_str("inline settle() {\n");
        self.boot(out);
        self.reexamine(out);
        self.shutdown(out);
        out.push_str("}\n\n");
    }

    /// 10.1: tasks boot in order; a task without a living permanent
    /// activity is passed; requests once every task booted.
    fn boot(&self, out: &mut String) {
        let n = self.r.tasks.len();
        out.push_str("  /* boot order (10.1) */\n  if\n  :: phase == P_BOOT ->\n     do\n");
        for t in 0..n {
            let _ = writeln!(
                out,
                "     :: booted == {t} && !pon_{t} -> booted = {}",
                t + 1
            );
        }
        let _ = writeln!(
            out,
            "     :: else -> break\n     od;\n     \
             if :: booted == {n} -> phase = P_RUN :: else -> skip fi\n  \
             :: else -> skip\n  fi;"
        );
    }

    /// 5.3: after an end, every accepted instance not started re-examines
    /// its interruptions in activity order, until no further end.
    fn reexamine(&self, out: &mut String) {
        out.push_str("  /* pending interrupters re-examine after an end (5.3) */\n  do\n  :: ended ->\n     ended = 0");
        for (a, act) in self.r.activities.iter().enumerate() {
            if act.targets.is_empty() {
                continue;
            }
            let flags: String = act
                .targets
                .iter()
                .map(|t| format!("flag_{t}(); "))
                .collect();
            let _ = write!(
                out,
                ";\n     if\n     :: st_{a} == DELAYED || st_{a} == READY ->  /* `{}` */\n        \
                 {flags}\n        \
                 if :: st_{a} == DELAYED && {} -> st_{a} = READY :: else -> skip fi\n     \
                 :: else -> skip\n     fi",
                act.name,
                self.none_stopping(&act.targets)
            );
        }
        out.push_str("\n  :: else -> break\n  od;\n");
    }

    /// `!(st_X == STOP) && ...` over the targets.
    pub fn none_stopping(&self, targets: &[usize]) -> String {
        targets
            .iter()
            .map(|t| format!("st_{t} != STOP"))
            .collect::<Vec<_>>()
            .join(" && ")
    }

    /// 10.2: once `kill` drained every instance, the permanent activities
    /// run their stop paths one by one, last task first.
    fn shutdown(&self, out: &mut String) {
        let order: Vec<(usize, usize)> = self
            .r
            .tasks
            .iter()
            .enumerate()
            .rev()
            .filter_map(|(t, task)| task.fsm.stop.map(|s| (t, s)))
            .collect();
        let idle: Vec<String> = (0..self.r.activities.len())
            .map(|a| format!("st_{a} == IDLE"))
            .collect();
        let off: String = (0..self.r.tasks.len())
            .map(|t| format!("pon_{t} = 0; pat_{t} = 0; "))
            .collect();
        let mut start = String::from("if\n");
        for (k, (t, s)) in order.iter().enumerate() {
            let _ = writeln!(
                start,
                "       :: pstop == {k} -> pon_{t} = 1; pat_{t} = {s}  /* task `{}` */",
                self.r.tasks[*t].name
            );
        }
        start.push_str("       :: else -> phase = P_STOPPED\n       fi");
        let ended: Vec<String> = order
            .iter()
            .enumerate()
            .map(|(k, (t, _))| format!("(pstop == {k} && !pon_{t})"))
            .collect();
        let _ = writeln!(
            out,
            "  /* shutdown (10.2) */\n  if\n  :: phase == P_DRAIN && {} ->\n     \
             phase = P_PSTOP; {off}pstop = 0;\n     {start}\n  :: else -> skip\n  fi;",
            if idle.is_empty() {
                "true".to_owned()
            } else {
                idle.join(" && ")
            }
        );
        if !ended.is_empty() {
            let _ = writeln!(
                out,
                "  if\n  :: phase == P_PSTOP && ({}) ->\n     pstop++;\n     {start}\n  \
                 :: else -> skip\n  fi",
                ended.join(" || ")
            );
        }
    }

    /// The process: every step, then the loop head.
    fn process(options: Vec<String>) -> String {
        let mut out = String::from(
            "/* the component: every transition of docs/genom3-semantics.md 14.2 */\n\
             active proctype component() {\n  atomic { settle() };\nend:\n  do\n  :: atomic {\n     if\n",
        );
        if options.is_empty() {
            out.push_str("     :: false\n");
        }
        for o in options {
            let o = o.trim_end().trim_end_matches(';');
            let _ = writeln!(out, "     :: {o}");
        }
        out.push_str("     fi;\n     settle()\n     }\n  od\n}\n");
        out
    }
}

fn list(v: &[String]) -> String {
    if v.is_empty() {
        "none".to_owned()
    } else {
        v.join(", ")
    }
}

fn constants(out: &mut String) {
    out.push_str(
        "#define P_BOOT    0  /* tasks boot one after the other (10.1) */\n\
         #define P_RUN     1  /* requests are handled */\n\
         #define P_DRAIN   2  /* kill succeeded: waiting for every instance to end */\n\
         #define P_PSTOP   3  /* the permanent activities' stop paths (10.2) */\n\
         #define P_STOPPED 4  /* stopped (terminal) */\n\
         #define P_FAILED  5  /* a permanent activity failed during the boot (terminal) */\n\n\
         #define IDLE    0  /* no instance */\n\
         #define DELAYED 1  /* accepted, waits for interrupted instances to end (5.1) */\n\
         #define READY   2  /* accepted, starts at its task's next sweep */\n\
         #define RUN     3  /* runs its state machine, at_A next */\n\
         #define STOP    4  /* interrupted: on its stop path, at_A next */\n\n",
    );
}
