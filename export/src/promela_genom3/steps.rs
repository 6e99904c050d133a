//! The steps of the GenoM3 model (docs/genom3-semantics.md 14.2), one
//! option each (a guard, then its effect; the process runs each in one
//! `atomic` block followed by `settle()`): a permanent
//! codel (with each of its outcomes), an activity request accepted, a
//! function or attribute that succeeds, `abort_activity` on an instance,
//! an instance starting, an instance's codel (with each outcome).

use std::fmt::Write as _;

use genom_model::component::{Idx, ServiceId};

use super::emit::Model;
use super::reading::{ControlKind, Next};

/// Every option of the process loop, in a fixed order.
pub fn options(m: &mut Model<'_>) -> Vec<String> {
    let mut out = Vec::new();
    for t in 0..m.r.tasks.len() {
        permanent(m, t, &mut out);
    }
    for a in 0..m.r.activities.len() {
        accept(m, a, &mut out);
    }
    for k in 0..m.r.controls.len() {
        call(m, k, &mut out);
    }
    for a in 0..m.r.activities.len() {
        start(m, a, &mut out);
        codels(m, a, &mut out);
    }
    out
}

/// `after` all done and `before` none done (4.1, 4.2).
fn admissible(m: &Model<'_>, sid: ServiceId) -> String {
    let mut g = Vec::new();
    for x in m.r.after.get(&sid).into_iter().flatten() {
        g.push(format!("done_{}", x.index()));
    }
    for x in m.r.before.get(&sid).into_iter().flatten() {
        g.push(format!("!done_{}", x.index()));
    }
    g.into_iter().map(|x| format!(" && {x}")).collect()
}

/// Marks service `sid` completed, when some `after`/`before` reads it.
fn done(m: &Model<'_>, sid: ServiceId) -> String {
    if m.watched.contains(&sid) {
        format!("done_{} = 1; ", sid.index())
    } else {
        String::new()
    }
}

fn flags(targets: &[usize]) -> String {
    targets.iter().map(|t| format!("flag_{t}(); ")).collect()
}

/// Task `t`'s permanent codels: in the boot, only tasks already booted
/// and the one booting; never after the component stopped or failed.
fn permanent(m: &mut Model<'_>, t: usize, out: &mut Vec<String>) {
    let task = m.r.tasks[t].clone();
    for (s, state) in task.fsm.states.iter().enumerate() {
        let marker = m.marker(format!(
            "codel `{}` of task `{}` (state `{}`) runs",
            state.function, task.name, state.name
        ));
        let mut body =
            format!("{marker};\n       booting = (phase == P_BOOT && booted == {t});\n       if\n");
        for y in &state.yields {
            match *y {
                Next::State(n) => {
                    let _ = writeln!(
                        body,
                        "       :: pat_{t} = {n}  /* yields `{}` */",
                        task.fsm.states[n].name
                    );
                }
                Next::Ether => {
                    let _ = writeln!(body, "       :: pon_{t} = 0; pat_{t} = 0  /* ether */");
                }
            }
        }
        let _ = write!(
            body,
            "       :: if :: booting -> phase = P_FAILED :: else -> pon_{t} = 0; pat_{t} = 0 fi  /* an exception (9.4) */\n       \
             fi;\n       if :: booting -> booted = {} :: else -> skip fi;\n       ",
            t + 1
        );
        out.push(format!(
            "pon_{t} && pat_{t} == {s} && (phase == P_RUN || phase == P_DRAIN || phase == P_PSTOP || (phase == P_BOOT && booted >= {t})) ->\n       \
             {body}"
        ));
    }
}

/// A request of activity `a` accepted (validate succeeded): it interrupts
/// its targets, then pends while one of them is stopping (5.1, 5.3).
fn accept(m: &Model<'_>, a: usize, out: &mut Vec<String>) {
    let act = &m.r.activities[a];
    let delay = if act.targets.is_empty() {
        format!("st_{a} = READY")
    } else {
        format!(
            "if :: {} -> st_{a} = READY :: else -> st_{a} = DELAYED fi",
            m.none_stopping(&act.targets)
        )
    };
    out.push(format!(
        "phase == P_RUN && st_{a} == IDLE{} ->  /* request `{}` accepted */\n       \
         {}{delay}; ",
        admissible(m, act.service),
        act.name,
        flags(&act.targets)
    ));
}

/// A function or attribute that succeeds (6.1): completed, then its
/// interruptions without waiting; `kill` then drains (5.7, 10.2);
/// `abort_activity` interrupts one instance (5.6).
fn call(m: &mut Model<'_>, k: usize, out: &mut Vec<String>) {
    let ctl = m.r.controls[k].clone();
    let guard = format!("phase == P_RUN{}", admissible(m, ctl.service));
    let done = done(m, ctl.service);
    match ctl.kind {
        ControlKind::Abort => {
            for a in 0..m.r.activities.len() {
                let marker = m.marker(format!("service `{}` is accepted", ctl.name));
                out.push(format!(
                    "{guard} && (st_{a} == DELAYED || st_{a} == READY || st_{a} == RUN) ->  /* `{}` on `{}` */\n       \
                     {marker}; {done}flag_{a}(); ",
                    ctl.name, m.r.activities[a].name
                ));
            }
        }
        ControlKind::Plain | ControlKind::Kill => {
            let marker = m.marker(format!("service `{}` is accepted", ctl.name));
            let kill = if ctl.kind == ControlKind::Kill {
                "phase = P_DRAIN; "
            } else {
                ""
            };
            out.push(format!(
                "{guard} ->  /* `{}` succeeds */\n       \
                 {marker}; {done}{}{kill}",
                ctl.name,
                flags(&ctl.targets)
            ));
        }
    }
}

/// An accepted instance of `a` starts (1.4) and runs its `start` codel in
/// the same step (GenoM3's sweep runs a new instance's first codel at once:
/// no stop flag is read in between); without a `start` codel it completes
/// at once.
fn start(m: &mut Model<'_>, a: usize, out: &mut Vec<String>) {
    let act = m.r.activities[a].clone();
    let marker = m.marker(format!("service `{}` starts", act.name));
    let go = match act.fsm.start {
        Some(s) => format!("st_{a} = RUN; at_{a} = {s};\n       {}", codel(m, a, s)),
        None => format!(
            "st_{a} = IDLE; at_{a} = 0; {}ended = 1; ",
            done(m, act.service)
        ),
    };
    out.push(format!(
        "st_{a} == READY ->  /* `{}` starts */\n       {marker}; {go}",
        act.name
    ));
}

/// One codel of `a`'s instance, with each of its yields and an exception
/// (9.1, 9.2); a stopping instance stays stopping.
fn codels(m: &mut Model<'_>, a: usize, out: &mut Vec<String>) {
    for s in 0..m.r.activities[a].fsm.states.len() {
        let body = codel(m, a, s);
        let act = &m.r.activities[a];
        out.push(format!(
            "(st_{a} == RUN || st_{a} == STOP) && at_{a} == {s} ->  /* `{}` runs `{}` */\n       \
             {body}",
            act.name, act.fsm.states[s].name
        ));
    }
}

/// The effect of the codel of `a`'s state `s`: its marker, then one of its
/// yields or an exception.
fn codel(m: &mut Model<'_>, a: usize, s: usize) -> String {
    let act = m.r.activities[a].clone();
    let done = done(m, act.service);
    let state = &act.fsm.states[s];
    let marker = m.marker(format!(
        "codel `{}` of activity `{}` (state `{}`) runs",
        state.function, act.name, state.name
    ));
    let mut body = format!("{marker};\n       if\n");
    for y in &state.yields {
        match *y {
            Next::State(n) => {
                let _ = writeln!(
                    body,
                    "       :: at_{a} = {n}  /* yields `{}` */",
                    act.fsm.states[n].name
                );
            }
            Next::Ether => {
                let _ = writeln!(
                    body,
                    "       :: st_{a} = IDLE; at_{a} = 0; {done}ended = 1  /* ether */"
                );
            }
        }
    }
    let _ = write!(
        body,
        "       :: st_{a} = IDLE; at_{a} = 0; ended = 1  /* an exception */\n       fi"
    );
    body
}
