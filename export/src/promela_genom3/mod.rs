//! The `promela` export of a GenoM3 component: GenoM3's **untimed**
//! execution semantics (docs/genom3-semantics.md section 14 and the rules
//! of sections 1-10 it cites) as a Promela model for SPIN. It is written
//! from the semantics document and the model ([`Component`] and its
//! `Genom3Info`), independently of genom-check's GenoM3 engine
//! (`checker/engine/src/genom3/`), so that SPIN's verdicts can be compared
//! with the engine's (`tests/differential/spin_diff_genom3.rs`).
//!
//! The encoding (docs/exports/promela.md, section "GenoM3 components"):
//!
//! - state: the component's `phase` (boot, run, drain after `kill`, the
//!   permanent stop paths, stopped, failed start) with `booted` (tasks
//!   booted) and `pstop` (whose stop path runs); per service read by an
//!   `after` or `before`, `done_I` (its `run_map` entry); per activity one
//!   instance, `st_A` (`IDLE`, `DELAYED`, `READY`, `RUN`, `STOP`) and
//!   `at_A` (its state); per task `pon_T`/`pat_T` (its permanent activity
//!   lives, and its state);
//! - one process whose loop offers every transition of 14.2 as an `atomic`
//!   step (a request accepted, a function or attribute that succeeds,
//!   `abort_activity` on an instance, an instance starting, one codel with
//!   one of its outcomes), each followed by the steps that follow at once
//!   (`settle`: the boot order, pending interrupters re-examined after an
//!   end, the shutdown sequence);
//! - verdicts: hidden markers `m_N = 1` (a service accepted or started, a
//!   codel run) whose statements SPIN lists as unreached when no execution
//!   reaches them; the loop head is an `end` label.

mod emit;
use genom_translate::genom3_reading as reading;
mod steps;

use crate::{ExportError, ExportInput, Exported};

pub use reading::{ControlKind, Fsm, Next, Reading};

/// The largest number of states of one machine, and of activities of one
/// task (so that every index fits a `byte` and the slot pool, 32 per task
/// with the permanent activity, never fills with one instance per activity).
const MAX_STATES: usize = 250;
const MAX_ACTIVITIES_PER_TASK: usize = 30;

/// Exports a GenoM3 component's untimed semantics as a Promela model.
pub fn export(input: &ExportInput<'_>) -> Result<Exported, ExportError> {
    let c = input.component;
    let unsupported = |reason: String| ExportError::Unsupported {
        format: "promela",
        reason,
    };
    let r = Reading::new(c).ok_or_else(|| unsupported("not a GenoM3 component".to_owned()))?;
    supported(&r).map_err(unsupported)?;
    let mut out = String::new();
    header(&mut out, input);
    let mut model = emit::Model::new(c, &r);
    let options = steps::options(&mut model);
    let body = model.write(options);
    out.push_str(&body);
    Ok(Exported::single(out))
}

/// Rejects what the encoding cannot express.
fn supported(r: &Reading) -> Result<(), String> {
    let machines = r
        .activities
        .iter()
        .map(|a| (format!("activity `{}`", a.name), &a.fsm))
        .chain(
            r.tasks
                .iter()
                .map(|t| (format!("task `{}`", t.name), &t.fsm)),
        );
    for (who, fsm) in machines {
        if fsm.states.len() > MAX_STATES {
            return Err(format!("{who} has more than {MAX_STATES} states"));
        }
    }
    if r.tasks.len() > MAX_STATES {
        return Err(format!("more than {MAX_STATES} tasks"));
    }
    for (t, task) in r.tasks.iter().enumerate() {
        let n = r.activities.iter().filter(|a| a.task == t).count();
        if n > MAX_ACTIVITIES_PER_TASK {
            return Err(format!(
                "task `{}` has {n} activities: the slot pool could fill (not encoded)",
                task.name
            ));
        }
    }
    Ok(())
}

fn header(out: &mut String, input: &ExportInput<'_>) {
    crate::promela_opening(out, input, "GenoM3's untimed semantics");
    out.push_str(
        " *\n\
         \x20* docs/genom3-semantics.md section 14: any interleaving of the permanent\n\
         \x20* activities' codels, accepted requests, successful functions and\n\
         \x20* attributes, abort_activity, instance starts and codels (every yield, and\n\
         \x20* an exception), one instance per activity (14.3).\n\
         \x20* Run:   spin -a -o3 FILE.pml && gcc -O1 -DSAFETY -DNOREDUCE -o pan pan.c\n\
         \x20*        ./pan -m1000000\n\
         \x20* Read:  an unreached `m_N = 1` (every copy) is a service never accepted or\n\
         \x20*        started, or a codel never run (the declaration of m_N says which).\n\
         \x20*        -o3 keeps each marker its own statement so that SPIN reports it.\n\
         \x20*        An invalid end state would be a bug of this model.\n\
         \x20*/\n\n",
    );
}

#[cfg(test)]
mod tests {
    use std::collections::{BTreeMap, BTreeSet};

    use genom_model::component::{Idx, ServiceId};

    use super::reading::{Activity, Task};
    use super::*;

    fn reading(activities: usize) -> Reading {
        Reading {
            tasks: vec![Task {
                name: "t".to_owned(),
                span: genom_model::Span::default(),
                fsm: Fsm::default(),
            }],
            activities: (0..activities)
                .map(|k| Activity {
                    service: ServiceId::new(k),
                    name: format!("a{k}"),
                    task: 0,
                    fsm: Fsm::default(),
                    targets: Vec::new(),
                })
                .collect(),
            controls: Vec::new(),
            after: BTreeMap::new(),
            before: BTreeMap::new(),
            builtin: BTreeSet::new(),
        }
    }

    #[test]
    fn a_task_whose_slot_pool_could_fill_is_refused() {
        assert!(supported(&reading(MAX_ACTIVITIES_PER_TASK)).is_ok());
        let refused = supported(&reading(MAX_ACTIVITIES_PER_TASK + 1));
        assert!(refused.is_err_and(|e| e.contains("slot pool")));
    }
}
