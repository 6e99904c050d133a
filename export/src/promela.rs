//! The `promela` export: the untimed semantics of the component
//! (LANGUAGE.md section 3, docs/semantics.md sections 1–3) as a Promela
//! model for SPIN, written from the specification and independently of the
//! explorer (`checker/engine/src/kernel`, `dialect`), so that SPIN's verdicts can be compared
//! with genom-check's (`tests/differential/spin_diff.rs`, docs/testing/spin.md).
//!
//! A GenoM3 component is exported with GenoM3's own semantics instead
//! ([`crate::promela_genom3`]).
//!
//! The encoding (docs/exports/promela.md):
//!
//! - global state, per service `i`: `mode_i` (`IDLE`, `READY`, `RUN`,
//!   `RUNINT`, `STOPREADY`, `STOPRUN`), `at_i` (the codel, by its position in
//!   the service, from 1), `oi_i` (when `READY`: the `on-inter` of the codel
//!   it last ran, 0 for none), `pend_i` (a pending instance) and `wait_i_j`
//!   (the pending `i` waits for the interrupted `j` to end); per thread
//!   `busy_t` (local to the process); per lockable structure `rd_k`
//!   (readers) and `wr_k` (writer); `init_done`, `autos_due`;
//! - one process, `component`, whose loop offers every step: a request
//!   that is accepted (steps 1–6, one option per service), the begin and
//!   finish of each codel (one option per outcome) and the watchdogs
//!   (services with `max-time`: interrupt at any time). A step is an option
//!   of an `atomic` block: the guard, the effect and, except after a codel
//!   begins (which can start nothing), `settle()`: the urgent starts of
//!   step 7 and the deadlock assertion. SPIN stores no state inside an
//!   atomic block, so every transition of the semantics is one stored
//!   state (no bookkeeping steps); `settle()` has one copy, so every marker
//!   is one statement. Without an init service the autos are started in the
//!   initial state; `init` marks them started and runs `component`;
//! - verdicts: `assert` in `settle()` (a cycle of pending instances delayed by
//!   each other, none with `max-time`: a deadlock), and per-codel and
//!   per-service markers (`ran_K = 1`, `started_I = 1`, hidden, not part of
//!   the state) whose statements SPIN lists as "unreached" when no execution
//!   runs the codel or starts the service (`-o3` keeps each its own
//!   statement; they are outside `d_step`s, whose statements SPIN does not
//!   report). The loop head is an `end` label: waiting for a request or a
//!   codel is legitimate, so SPIN's own
//!   invalid-end-state check must never fire.

use std::fmt::Write as _;

use genom_model::component::{CodelId, Component, Idx, Outcome, ServiceId, StructureId};
use genom_model::kinds::{CodelKind, ServiceKind};

use crate::{ExportError, ExportInput, Exported};

/// The largest number of codels of one service (`at_i` is a `byte`).
const MAX_CODELS: usize = 250;

/// Exports the component's untimed semantics as a Promela model.
pub fn export(input: &ExportInput<'_>) -> Result<Exported, ExportError> {
    let c = input.component;
    supported(c)?;
    let mut out = String::new();
    header(&mut out, input);
    declarations(&mut out, c);
    inlines(&mut out, c);
    settle(&mut out, c);
    let (quiet, steps) = all_steps(c);
    process(&mut out, c, &quiet, &steps);
    init(&mut out, c);
    Ok(Exported::single(out))
}

/// Rejects what the encoding cannot express (never the case for a
/// component without static errors and with fewer than 250 codels per
/// service).
fn supported(c: &Component) -> Result<(), ExportError> {
    let unsupported = |reason: String| ExportError::Unsupported {
        format: "promela",
        reason,
    };
    for s in c.services.values() {
        if s.codels.len() > MAX_CODELS {
            return Err(unsupported(format!(
                "service `{}` has more than {MAX_CODELS} codels",
                s.name.name
            )));
        }
        if s.start.is_some() && s.thread.is_none() {
            return Err(unsupported(format!(
                "service `{}` has a start codel but no thread",
                s.name.name
            )));
        }
    }
    Ok(())
}

fn header(out: &mut String, input: &ExportInput<'_>) {
    crate::promela_opening(out, input, "The untimed semantics");
    out.push_str(
        " *\n\
         \x20* LANGUAGE.md section 3 without time (docs/semantics.md 2.3-2.4): any\n\
         \x20* interleaving of requests, codel begins and ends, and watchdog interrupts.\n\
         \x20* Run:   spin -a -o3 FILE.pml && gcc -O2 -DSAFETY -o pan pan.c\n\
         \x20*        ./pan -c0 -m1000000\n\
         \x20* Each step is one atomic block (the guard, the effect, then settle(): the\n\
         \x20* urgent starts and the deadlock check): one stored state per transition.\n\
         \x20* Read:  an assertion violation is a deadlock (pending instances delayed by\n\
         \x20*        each other, none with max-time); an unreached `started_I = 1` (every\n\
         \x20*        copy) is a dead service I; an unreached `ran_K = 1` (every copy) is a\n\
         \x20*        codel K that no execution runs. -o3 keeps each marker its own statement\n\
         \x20*        so that SPIN reports it. An invalid end state would be a bug of this\n\
         \x20*        model: every loop head is an end label.\n\
         \x20*/\n\n\
         #define IDLE      0\n\
         #define READY     1 /* active, at_i is next, not begun */\n\
         #define RUN       2 /* active, its thread runs at_i */\n\
         #define RUNINT    3 /* runs at_i, interrupted meanwhile */\n\
         #define STOPREADY 4 /* stopping, inter codel at_i is next */\n\
         #define STOPRUN   5 /* stopping, runs at_i */\n\n",
    );
}

/// The distinct `stops` targets of a service, in `stops` order.
fn targets(c: &Component, s: ServiceId) -> Vec<ServiceId> {
    let mut out: Vec<ServiceId> = Vec::new();
    for r in &c.services[s].stops {
        if !out.contains(&r.id) {
            out.push(r.id);
        }
    }
    out
}

/// The services that list `s` in `stops` (so that a pending one may wait
/// for `s`).
fn stoppers(c: &Component, s: ServiceId) -> Vec<ServiceId> {
    c.services
        .ids()
        .filter(|&r| targets(c, r).contains(&s))
        .collect()
}

/// The services `t != s` that list `s` in `delays`.
fn delayers(c: &Component, s: ServiceId) -> Vec<ServiceId> {
    c.services
        .iter()
        .filter(|(t, ts)| *t != s && ts.delays.iter().any(|r| r.id == s))
        .map(|(t, _)| t)
        .collect()
}

/// The position of a codel in its service, from 1 (the value of `at_i`).
fn local(c: &Component, k: CodelId) -> usize {
    let s = &c.services[c.codels[k].service];
    s.codels.iter().position(|&x| x == k).map_or(0, |p| p + 1)
}

fn has_instance(t: ServiceId) -> String {
    let t = t.index();
    format!("(pend_{t} || mode_{t} != IDLE)")
}

fn declarations(out: &mut String, c: &Component) {
    let init = c.init_service();
    let _ = writeln!(
        out,
        "bit init_done = {};  /* the init service has completed successfully */",
        u8::from(init.is_none())
    );
    out.push_str("bit autos_due;  /* initialisation completed: the auto services start now */\n");
    out.push('\n');
    for (id, s) in c.services.iter() {
        let i = id.index();
        let codels: Vec<String> = s
            .codels
            .iter()
            .filter(|&&k| c.codels[k].kind != CodelKind::Control)
            .map(|&k| format!("{} {}", local(c, k), c.codels[k].name.name))
            .collect();
        let _ = writeln!(
            out,
            "/* service {i} `{}`{}{}; codels: {} */",
            s.name.name,
            match s.kind {
                ServiceKind::Plain => "",
                ServiceKind::Init => " (init)",
                ServiceKind::Auto => " (auto)",
            },
            if s.max_time.is_some() {
                ", max-time"
            } else {
                ""
            },
            if codels.is_empty() {
                "none".to_owned()
            } else {
                codels.join(", ")
            }
        );
        let _ = writeln!(
            out,
            "byte mode_{i}{}; byte at_{i}{}; byte oi_{i}; bit pend_{i};",
            initial(c, id).map_or(String::new(), |_| " = READY".to_owned()),
            initial(c, id).map_or(String::new(), |l| format!(" = {l}"))
        );
        for t in targets(c, id) {
            let _ = writeln!(
                out,
                "bit wait_{i}_{};  /* pending `{}` waits for the interrupted `{}` */",
                t.index(),
                s.name.name,
                c.services[t].name.name
            );
        }
    }
    resources(out, c);
    markers(out, c);
}

/// Without an init service, the auto services start at once: an auto
/// service with a start codel is `READY` at it in the initial state (the
/// position of the codel); one without completes at once.
fn initial(c: &Component, id: ServiceId) -> Option<usize> {
    let s = &c.services[id];
    let auto = c.init_service().is_none() && s.kind == ServiceKind::Auto;
    s.start.filter(|_| auto).map(|k| local(c, k))
}

fn resources(out: &mut String, c: &Component) {
    out.push('\n');
    for (id, s) in c.structures.iter() {
        let k = id.index();
        let _ = writeln!(
            out,
            "byte rd_{k}; bit wr_{k};  /* lock of `{}`: readers, writer */",
            s.path()
        );
    }
}

fn markers(out: &mut String, c: &Component) {
    out.push_str("\n/* reachability markers: hidden, not part of the state */\n");
    for (k, codel) in c.codels.iter() {
        let _ = writeln!(
            out,
            "hidden byte ran_{};  /* {} codel `{}` */",
            k.index(),
            codel.kind.keyword(),
            c.codel_label(k)
        );
    }
    for (id, s) in c.services.iter() {
        let _ = writeln!(
            out,
            "hidden byte started_{};  /* `{}` {} */",
            id.index(),
            s.name.name,
            if s.start.is_some() {
                "starts"
            } else {
                "is accepted"
            }
        );
        let _ = writeln!(out, "hidden byte cand_{};", id.index());
    }
    out.push_str("hidden byte chg;  /* deadlock check scratch */\n\n");
}

/// `end_i` (the main instance ends without success), `succeed_i`,
/// `drop_i` (the pending instance ends) and `interrupt_i`.
fn inlines(out: &mut String, c: &Component) {
    for id in c.services.ids() {
        let i = id.index();
        let mut end = format!("  mode_{i} = IDLE; at_{i} = 0; oi_{i} = 0");
        for r in stoppers(c, id) {
            let _ = write!(end, ";\n  wait_{}_{i} = 0", r.index());
        }
        let _ = writeln!(out, "inline end_{i}() {{\n{end}\n}}");
        let _ = writeln!(
            out,
            "inline succeed_{i}() {{\n  end_{i}(){}\n}}",
            init_completes(c, id)
        );
        let mut drop = format!("  pend_{i} = 0");
        for t in targets(c, id) {
            let _ = write!(drop, ";\n  wait_{i}_{} = 0", t.index());
        }
        let _ = writeln!(out, "inline drop_{i}() {{\n{drop}\n}}");
        let _ = writeln!(
            out,
            "inline interrupt_{i}() {{\n  if\n  \
             :: mode_{i} == READY && oi_{i} != 0 -> mode_{i} = STOPREADY; at_{i} = oi_{i}; oi_{i} = 0\n  \
             :: mode_{i} == READY && oi_{i} == 0 -> end_{i}()\n  \
             :: mode_{i} == RUN -> mode_{i} = RUNINT\n  \
             :: else -> skip\n  fi\n}}\n"
        );
    }
}

/// For the init service: its first success completes initialisation, and
/// the auto services are due to start (the engine starts them next).
fn init_completes(c: &Component, id: ServiceId) -> String {
    if c.init_service() != Some(id) {
        return String::new();
    }
    ";\n  if\n  :: !init_done -> init_done = 1; autos_due = 1\n  :: else -> skip\n  fi".to_owned()
}

/// The engine's first duty once initialisation completes: every auto
/// service starts at once, whatever `delays` or `forbids` it lists about
/// the others (autos are never pending).
fn start_autos(c: &Component) -> String {
    let mut body = String::from("autos_due = 0");
    for (a, s) in c.services.iter() {
        if s.kind == ServiceKind::Auto {
            let i = a.index();
            if s.start.is_none() {
                let _ = write!(body, "; started_{i} = 1");
            }
            let _ = write!(body, "; {}", start(c, a));
        }
    }
    format!("if :: autos_due -> {body} :: else -> skip fi;\n  ")
}

/// The lock condition of a codel: every structure it writes is free, every
/// one it reads has no writer.
fn can_lock(c: &Component, k: CodelId) -> Vec<String> {
    structures(c, k)
        .into_iter()
        .map(|(s, w)| {
            let s = s.index();
            if w {
                format!("rd_{s} == 0 && !wr_{s}")
            } else {
                format!("!wr_{s}")
            }
        })
        .collect()
}

fn structures(c: &Component, k: CodelId) -> Vec<(StructureId, bool)> {
    c.codels[k].structures()
}

fn acquire(c: &Component, k: CodelId) -> String {
    structures(c, k)
        .into_iter()
        .map(|(s, w)| {
            let s = s.index();
            if w {
                format!("; wr_{s} = 1")
            } else {
                format!("; rd_{s}++")
            }
        })
        .collect()
}

fn release(c: &Component, k: CodelId) -> String {
    structures(c, k)
        .into_iter()
        .map(|(s, w)| {
            let s = s.index();
            if w {
                format!("wr_{s} = 0; ")
            } else {
                format!("rd_{s}--; ")
            }
        })
        .collect()
}

/// Writes the one process, `component`: its loop offers `quiet` steps
/// (nothing can start after them: codel begins) and `steps` (followed by
/// `settle()`), each one `atomic` block, so that SPIN stores one state per
/// transition; `settle()` has one copy, so that each marker of its starts
/// is one statement.
fn process(out: &mut String, c: &Component, quiet: &[String], steps: &[String]) {
    out.push_str(
        "/* every step of the component: requests, codels, watchdogs */\nproctype component() {\n",
    );
    for (id, t) in c.threads.iter() {
        let _ = writeln!(
            out,
            "  bit busy_{};  /* thread `{}` runs a codel */",
            id.index(),
            t.name.name
        );
    }
    out.push_str("end:\n  do\n");
    if quiet.is_empty() && steps.is_empty() {
        out.push_str("  :: false\n");
    }
    for (options, tail) in [(quiet, ""), (steps, ";\n       settle()")] {
        if options.is_empty() {
            continue;
        }
        out.push_str("  :: atomic {\n       if\n");
        for o in options {
            let _ = writeln!(out, "       :: {o}");
        }
        let _ = writeln!(out, "       fi{tail} }}");
    }
    out.push_str("  od\n}\n\n");
}

fn request(c: &Component, id: ServiceId) -> String {
    let s = &c.services[id];
    let i = id.index();
    let mut guard = Vec::new();
    if c.init_service().is_some_and(|x| x != id) {
        guard.push("init_done".to_owned());
    }
    for (t, ts) in c.services.iter() {
        if t != id && ts.forbids.iter().any(|r| r.id == id) {
            guard.push(format!("!{}", has_instance(t)));
        }
    }
    let targets = targets(c, id);
    if !targets.contains(&id) {
        guard.push(format!("!{}", has_instance(id)));
    }
    let mut body = String::new();
    if let Some(k) = s.control {
        guard.extend(can_lock(c, k));
        let _ = write!(body, "ran_{} = 1; ", k.index());
    }
    if s.start.is_none() {
        let _ = write!(body, "started_{i} = 1; ");
    }
    for t in &targets {
        let t = t.index();
        let _ = write!(
            body,
            "if :: pend_{t} -> drop_{t}() :: else -> skip fi; interrupt_{t}(); "
        );
    }
    let _ = write!(body, "pend_{i} = 1");
    for t in &targets {
        let t = t.index();
        let _ = write!(body, "; wait_{i}_{t} = (mode_{t} != IDLE)");
    }
    if guard.is_empty() {
        guard.push("true".to_owned());
    }
    format!(
        "{} ->  /* request `{}` */\n            {body}",
        guard.join(" && "),
        s.name.name
    )
}

/// The steps of the component: `quiet` (codel begins, after which nothing
/// can start) and the others (requests, codel finishes, watchdogs).
fn all_steps(c: &Component) -> (Vec<String>, Vec<String>) {
    let mut quiet = Vec::new();
    let mut steps: Vec<String> = c.services.ids().map(|s| request(c, s)).collect();
    for (sid, s) in c.services.iter() {
        let Some(t) = s.thread.map(|r| r.id.index()).filter(|_| s.start.is_some()) else {
            continue;
        };
        for &k in &s.codels {
            if c.codels[k].kind != CodelKind::Control {
                quiet.extend(begins(c, sid, k, t));
                steps.extend(finishes(c, sid, k, t));
            }
        }
    }
    steps.extend(watchdog(c));
    (quiet, steps)
}

/// The begin steps of codel `k` of service `sid` (from `READY` and from
/// `STOPREADY`): the thread is free and the codel's locks are.
fn begins(c: &Component, sid: ServiceId, k: CodelId, t: usize) -> Vec<String> {
    let i = sid.index();
    let l = local(c, k);
    let name = c.codel_label(k);
    let mut lock = vec![format!("!busy_{t}")];
    lock.extend(can_lock(c, k));
    let lock = lock.join(" && ");
    let acq = acquire(c, k);
    [
        ("READY", "RUN", "begins"),
        ("STOPREADY", "STOPRUN", "begins (stopping)"),
    ]
    .into_iter()
    .map(|(from, to, what)| {
        format!(
            "{lock} && mode_{i} == {from} && at_{i} == {l} ->  /* `{name}` {what} */\n            \
             ran_{} = 1; mode_{i} = {to}; oi_{i} = 0; busy_{t} = 1{acq}",
            k.index()
        )
    })
    .collect()
}

/// The finish steps of codel `k` of service `sid`: one per outcome, from
/// `RUN` and from `STOPRUN`, and the end of an interrupted run.
fn finishes(c: &Component, sid: ServiceId, k: CodelId, t: usize) -> Vec<String> {
    let i = sid.index();
    let l = local(c, k);
    let codel = &c.codels[k];
    let name = c.codel_label(k);
    let rel = format!("{}busy_{t} = 0; ", release(c, k));
    let mut steps = Vec::new();
    let oi = codel.on_inter.map_or(0, |r| local(c, r.id));
    for o in codel.outcomes() {
        let (go, stop_go) = match o {
            Outcome::Codel(d) => {
                let d = local(c, d);
                (
                    format!("mode_{i} = READY; at_{i} = {d}; oi_{i} = {oi}"),
                    format!("mode_{i} = STOPREADY; at_{i} = {d}"),
                )
            }
            Outcome::End => (format!("succeed_{i}()"), format!("end_{i}()")),
            Outcome::Report(_) => (format!("end_{i}()"), format!("end_{i}()")),
        };
        let label = outcome_name(c, sid, o);
        let what = format!("`{name}` ends with {label}");
        steps.push(finish(i, l, "RUN", &rel, &go, &what));
        let what = format!("`{name}` (stopping) ends with {label}");
        steps.push(finish(i, l, "STOPRUN", &rel, &stop_go, &what));
    }
    let interrupted = if oi == 0 {
        format!("end_{i}()")
    } else {
        format!("mode_{i} = STOPREADY; at_{i} = {oi}")
    };
    let what = format!("`{name}` ends, interrupted");
    steps.push(finish(i, l, "RUNINT", &rel, &interrupted, &what));
    steps
}

fn finish(i: usize, l: usize, mode: &str, rel: &str, go: &str, what: &str) -> String {
    format!(
        "mode_{i} == {mode} && at_{i} == {l} ->  /* {what} */\n            \
         {rel}{go}"
    )
}

fn outcome_name(c: &Component, sid: ServiceId, o: Outcome) -> String {
    match o {
        Outcome::Codel(d) => c.codels[d].name.name.clone(),
        Outcome::End => "end".to_owned(),
        Outcome::Report(r) => c.services[sid]
            .reports
            .get(r)
            .map_or_else(|| "a report".to_owned(), |n| n.name.clone()),
    }
}

/// Services with `max-time`: the watchdog may interrupt their pending or
/// main instance at any time (untimed reading of the deadline).
fn watchdog(c: &Component) -> Vec<String> {
    let mut steps = Vec::new();
    for (id, s) in c.services.iter() {
        if s.max_time.is_none() {
            continue;
        }
        let i = id.index();
        let name = &s.name.name;
        steps.push(format!(
            "pend_{i} ->  /* the pending `{name}` times out */\n            drop_{i}()"
        ));
        steps.push(format!(
            "mode_{i} == READY || mode_{i} == RUN ->  /* `{name}` times out */\n            \
             interrupt_{i}()"
        ));
    }
    steps
}

/// Whether pending `s` may start now (step 7).
fn can_start(c: &Component, s: ServiceId) -> String {
    let i = s.index();
    let mut cond = vec![format!("pend_{i}"), format!("mode_{i} == IDLE")];
    for t in targets(c, s) {
        cond.push(format!("!wait_{i}_{}", t.index()));
    }
    for t in delayers(c, s) {
        cond.push(format!("!{}", has_instance(t)));
    }
    format!("({})", cond.join(" && "))
}

fn start(c: &Component, s: ServiceId) -> String {
    let i = s.index();
    match c.services[s].start {
        Some(k) => format!(
            "pend_{i} = 0; started_{i} = 1; mode_{i} = READY; at_{i} = {}; oi_{i} = 0",
            local(c, k)
        ),
        None => format!("pend_{i} = 0; succeed_{i}()"),
    }
}

/// `settle()`: the urgent starts after every transition (step 7), then the
/// deadlock assertion. Called at the end of every atomic step but codel
/// begins, and by `init` on the initial state.
fn settle(out: &mut String, c: &Component) {
    let mut body = format!("inline settle() {{\n  {}do\n  :: ", start_autos(c));
    let mut any = Vec::new();
    for s in c.services.ids() {
        let cond = can_start(c, s);
        let _ = write!(
            body,
            "if :: {cond} -> {} :: else -> skip fi;\n     ",
            start(c, s)
        );
        any.push(cond);
    }
    if any.is_empty() {
        any.push("false".to_owned());
    }
    let _ = write!(
        body,
        "if :: {} -> skip :: else -> break fi\n  od;\n  skip;\n{}}}\n\n",
        any.join(" || "),
        deadlock_check(c)
    );
    out.push_str(&body);
}

/// `init`: marks the auto services started in the initial state (without
/// an init service they start at once, [`initial`]), then runs the
/// component, in one atomic step.
fn init(out: &mut String, c: &Component) {
    let mut body = String::new();
    if c.init_service().is_none() {
        for (a, s) in c.services.iter() {
            if s.kind == ServiceKind::Auto {
                let _ = write!(body, "started_{} = 1; ", a.index());
            }
        }
    }
    let _ = writeln!(out, "init {{\n  atomic {{ {body}run component() }}\n}}");
}

/// Removes, until nothing changes, every candidate (pending, no `max-time`)
/// that no candidate delays; what remains is a cycle of pending instances
/// delayed by each other: `assert` it is empty.
fn deadlock_check(c: &Component) -> String {
    let eligible: Vec<ServiceId> = c
        .services
        .iter()
        .filter(|(_, s)| s.max_time.is_none())
        .map(|(id, _)| id)
        .collect();
    let delayed_by = |s: ServiceId| -> Vec<ServiceId> {
        delayers(c, s)
            .into_iter()
            .filter(|t| eligible.contains(t))
            .collect()
    };
    let mut cands = eligible.clone();
    loop {
        let kept: Vec<ServiceId> = cands
            .iter()
            .copied()
            .filter(|&s| delayed_by(s).iter().any(|t| cands.contains(t)))
            .collect();
        if kept.len() == cands.len() {
            break;
        }
        cands = kept;
    }
    if cands.is_empty() {
        return "       /* no deadlock possible: no delays between services without max-time */\n"
            .to_owned();
    }
    let mut text = String::from("       d_step {\n");
    for &s in &cands {
        let _ = writeln!(text, "         cand_{0} = pend_{0};", s.index());
    }
    text.push_str("         do\n         :: chg = 0;\n");
    for &s in &cands {
        let by: Vec<String> = delayed_by(s)
            .into_iter()
            .filter(|t| cands.contains(t))
            .map(|t| format!("cand_{}", t.index()))
            .collect();
        let _ = writeln!(
            text,
            "            if :: cand_{0} && !({1}) -> cand_{0} = 0; chg = 1 :: else -> skip fi;",
            s.index(),
            if by.is_empty() {
                "0".to_owned()
            } else {
                by.join(" || ")
            }
        );
    }
    let all: Vec<String> = cands
        .iter()
        .map(|s| format!("cand_{}", s.index()))
        .collect();
    let _ = write!(
        text,
        "            if :: chg -> skip :: else -> break fi\n         od;\n         skip\n       }};\n       \
         assert(!({}));  /* deadlock */\n",
        all.join(" || ")
    );
    text
}
