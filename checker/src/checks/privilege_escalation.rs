//! `privilege-escalation`: a service `W` that a weaker credential class may
//! request controls a service `S` that needs a stronger one (LANGUAGE.md 2.6
//! and 4), either
//!
//! - by naming `S` in its `stops`, `delays` or `forbids`, or
//! - by writing data that `S` takes as input. `W` writes data `D` when one
//!   of its codels passes `D` as a non-`const` argument, or when it has an
//!   input parameter stored into `D`; `S` takes `D` as input when one of its
//!   codels passes `D` as an argument (`const` or not), or when it has an
//!   input parameter stored into `D`. Two data references overlap when they
//!   are in the same lockable structure and one member path is a prefix of
//!   the other (`ids.pose` and `ids.pose.x` overlap, `ids.pose.x` and
//!   `ids.pose.y` do not).
//!
//! Credentials are access control: a client allowed to request `W` but not
//! `S` could still interrupt, hold back or block `S`, or change what it
//! computes with, through `W`.

use std::collections::{BTreeMap, BTreeSet};

use genom_model::component::{Component, DataPath, Ref, Service, ServiceId, Step, StructureId};
use genom_model::{Code, Diagnostic, Span};

use super::registry::{Applies, StaticCheck};

/// `genom-check explain privilege-escalation`.
pub const EXPLANATION: &str = r#"A service that a weaker credential class may request controls a service that
needs a stronger one: it lists it in `stops`, `delays` or `forbids`, or it
writes data that the stronger service takes as input.

A service writes data when one of its codels passes it as a non-`const`
argument, or when it has an input parameter stored into it (`input:
ids.member`). A service takes data as input when one of its codels passes
it as an argument (`const` or not), or when it has an input parameter
stored into it. `ids.pose` and `ids.pose.x` overlap; `ids.pose.x` and
`ids.pose.y` do not.

Why it matters: credentials are the component's access control. A client
allowed to request the weaker service but not the stronger one could still
interrupt it, hold it back or have it rejected, or change the data it
computes with, through the weaker service: the credential of the stronger
service protects nothing.

Example:

```
component arm { lang: C; credentials: guest < operator < expert; }
ids lim { double qmax; }
service SetLimits {
  credential: expert;
  input: lim.qmax;
  control codel { exec: checkLimits(const lim.qmax); }
}
service Tweak {
  credential: guest;
  stops: SetLimits;                            // privilege-escalation
  control codel { exec: tweak(lim.qmax); }     // privilege-escalation: writes lim.qmax
}
```

Give the weaker service the stronger credential, or remove the reference or
the write."#;

/// How a service can control another through its attributes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Relation {
    /// `stops`: interrupts it.
    Stops,
    /// `delays`: holds it back.
    Delays,
    /// `forbids`: has its requests rejected.
    Forbids,
}

impl Relation {
    /// The attribute name.
    pub fn keyword(self) -> &'static str {
        match self {
            Relation::Stops => "stops",
            Relation::Delays => "delays",
            Relation::Forbids => "forbids",
        }
    }

    fn effect(self, strong: &str) -> String {
        match self {
            Relation::Stops => format!("interrupt `{strong}`"),
            Relation::Delays => format!("hold back the start of `{strong}`"),
            Relation::Forbids => format!("have the requests of `{strong}` rejected"),
        }
    }

    fn refs(self, service: &Service) -> &[Ref<ServiceId>] {
        match self {
            Relation::Stops => &service.stops,
            Relation::Delays => &service.delays,
            Relation::Forbids => &service.forbids,
        }
    }
}

/// One side of an escalation: a service's name, its credential class, where
/// its name and (for the stronger side) its credential are written.
#[derive(Debug, Clone, Copy)]
pub struct Side<'a> {
    /// The service name.
    pub name: &'a str,
    /// Its credential class.
    pub credential: &'a str,
    /// Where to point at it: its credential when written, else its name.
    pub span: Span,
}

fn side<'a>(c: &'a Component, s: &'a Service, prefer_credential: bool) -> Side<'a> {
    let span = s.credential_span.filter(|_| prefer_credential);
    Side {
        name: &s.name.name,
        credential: c.credential_name(s.credential),
        span: span.unwrap_or(s.name.span),
    }
}

fn base(weak: Side<'_>, message: String) -> Diagnostic {
    let label = format!("requestable with credential `{}`", weak.credential);
    Diagnostic::new(Code::PrivilegeEscalation, message, weak.span, label)
}

/// A weaker service that stops, delays or forbids a stronger one.
pub fn controls(weak: Side<'_>, strong: Side<'_>, relation: Relation, at: Span) -> Diagnostic {
    let (w, s, verb) = (weak.name, strong.name, relation.keyword());
    let message = format!(
        "service `{w}` (credential `{}`) {verb} service `{s}`, which needs credential `{}`",
        weak.credential, strong.credential
    );
    base(weak, message)
        .with_label(at, format!("{verb} `{s}`"))
        .with_label(
            strong.span,
            format!("`{s}` needs credential `{}`", strong.credential),
        )
        .with_help(format!(
            "any client allowed to request `{w}` can {} without being allowed to request it; \
             give `{w}` credential `{}`, or remove `{s}` from its `{verb}`",
            relation.effect(s),
            strong.credential
        ))
}

/// A weaker service that writes data a stronger one takes as input.
pub fn writes_input(
    weak: Side<'_>,
    strong: Side<'_>,
    written: &DataPath,
    read: &DataPath,
) -> Diagnostic {
    let (w, s) = (weak.name, strong.name);
    let message = format!(
        "service `{w}` (credential `{}`) writes `{}`, which service `{s}` (credential `{}`) takes \
         as input",
        weak.credential, written.text, strong.credential
    );
    base(weak, message)
        .with_label(
            written.span,
            format!("`{w}` writes `{}` here", written.text),
        )
        .with_label(
            strong.span,
            format!("`{s}` needs credential `{}`", strong.credential),
        )
        .with_label(
            read.span,
            format!("`{s}` takes `{}` as input here", read.text),
        )
        .with_help(format!(
            "a client with credential `{}` can change, through `{w}`, the data that `{s}` works \
             with; give `{w}` credential `{}`, or keep `{s}`'s inputs out of its reach",
            weak.credential, strong.credential
        ))
}

/// The data in lockable structures that a service's input parameters are
/// stored into and that its codels pass (only non-`const` arguments when
/// `writes`), in order: inputs, then codels and their arguments.
fn data_used<'a>(c: &'a Component, service: &'a Service, writes: bool) -> Vec<&'a DataPath> {
    let inputs = service.inputs.iter().filter_map(|p| p.data.as_ref());
    let args = service
        .codels
        .iter()
        .filter_map(|&id| c.codels[id].call.as_ref())
        .flat_map(|call| call.args.iter())
        .filter(|a| !(writes && a.is_const))
        .filter_map(|a| a.data.as_ref());
    inputs
        .chain(args)
        .filter(|d| d.structure().is_some())
        .collect()
}

/// Whether two references designate overlapping data: the same structure
/// and one member path a prefix of the other.
fn overlap(a: &DataPath, b: &DataPath) -> bool {
    a.structure().is_some()
        && a.structure() == b.structure()
        && (a.steps.starts_with(&b.steps) || b.steps.starts_with(&a.steps))
}

/// A step after every other (steps order fields first, then indices).
const LAST: Step = Step::Index(u64::MAX);

/// What each service reads and writes, computed once.
struct Uses<'a> {
    reads: Vec<&'a DataPath>,
    writes: Vec<&'a DataPath>,
}

/// The escalations of `weak` over `strong`, in order: `stops`, `delays`,
/// `forbids`, then data.
fn escalations(
    c: &Component,
    weak: (&Service, &Uses<'_>),
    strong: (ServiceId, &Service, &Uses<'_>),
) -> Vec<Diagnostic> {
    let (weak, weak_uses) = weak;
    let (sid, s, strong_uses) = strong;
    let (w_side, s_side) = (side(c, weak, false), side(c, s, true));
    let mut out: Vec<Diagnostic> = [Relation::Stops, Relation::Delays, Relation::Forbids]
        .into_iter()
        .filter_map(|rel| {
            let r = rel.refs(weak).iter().find(|r| r.id == sid)?;
            Some(controls(w_side, s_side, rel, r.span))
        })
        .collect();
    let reads = &strong_uses.reads;
    let pair = weak_uses
        .writes
        .iter()
        .find_map(|w| Some((*w, *reads.iter().find(|r| overlap(w, r))?)));
    if let Some((written, read)) = pair {
        out.push(writes_input(w_side, s_side, written, read));
    }
    out
}

/// The registry's entry ([`super::STATIC_CHECKS`]).
pub const CHECK: StaticCheck = StaticCheck {
    name: "privilege escalation",
    applies: Applies::Always,
    run: check,
    codes: &[(Code::PrivilegeEscalation, EXPLANATION)],
};

/// Reports every pair of services where the one with the weaker credential
/// controls the other, in service order. Only the pairs that can escalate
/// are looked at (a service the weaker one names, or one that reads a
/// structure it writes), so the check is linear in the component plus
/// what it reports, not quadratic in the number of services.
pub fn check(c: &Component) -> Vec<Diagnostic> {
    let strongest = c.services.values().map(|s| s.credential).max().unwrap_or(0);
    let uses: BTreeMap<ServiceId, Uses<'_>> = c
        .services
        .iter()
        .map(|(id, s)| {
            let u = Uses {
                reads: data_used(c, s, false),
                writes: data_used(c, s, true),
            };
            (id, u)
        })
        .collect();
    // Who reads what: by structure and first step (`None`: the whole
    // structure), so that only paths that can overlap meet.
    let mut readers: BTreeMap<(StructureId, Option<&Step>), Vec<ServiceId>> = BTreeMap::new();
    for (&id, u) in &uses {
        for d in &u.reads {
            if let Some(structure) = d.structure() {
                readers
                    .entry((structure, d.steps.first()))
                    .or_default()
                    .push(id);
            }
        }
    }
    let mut out = Vec::new();
    for (wid, weak) in c.services.iter() {
        let Some(weak_uses) = uses.get(&wid) else {
            continue;
        };
        // Nobody is stronger than the strongest class.
        if weak.credential >= strongest {
            continue;
        }
        let named = [Relation::Stops, Relation::Delays, Relation::Forbids]
            .into_iter()
            .flat_map(|rel| rel.refs(weak).iter().map(|r| r.id));
        let reading = weak_uses
            .writes
            .iter()
            .filter_map(|d| Some((d.structure()?, d.steps.first())))
            .flat_map(|(s, first)| {
                // A whole-structure write meets every reader of the
                // structure; a member's, the readers of that member and
                // of the whole.
                let readers: Vec<&Vec<ServiceId>> = match first {
                    None => readers
                        .range((s, None)..=(s, Some(&LAST)))
                        .map(|(_, ids)| ids)
                        .collect(),
                    Some(step) => [(s, Some(step)), (s, None)]
                        .iter()
                        .filter_map(|key| readers.get(key))
                        .collect(),
                };
                readers.into_iter().flatten().copied()
            });
        let candidates: BTreeSet<ServiceId> = named.chain(reading).collect();
        for sid in candidates {
            let (Some(strong), Some(strong_uses)) = (c.services.get(sid), uses.get(&sid)) else {
                continue;
            };
            if weak.credential < strong.credential {
                out.extend(escalations(
                    c,
                    (weak, weak_uses),
                    (sid, strong, strong_uses),
                ));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use genom_model::{Code, Diagnostic};

    use crate::testing;

    const COMPONENT: &str = "component arm { lang: C; credentials: guest < operator < expert; }
ids lim { double qmax; double qmin; }
ids pose { double x; double y; }
";

    fn found(src: &str) -> Vec<Diagnostic> {
        testing::check(src)
            .diagnostics
            .into_iter()
            .filter(|d| d.code == Code::PrivilegeEscalation)
            .collect()
    }

    fn labels(src: &str, d: &Diagnostic) -> Vec<(String, String)> {
        d.labels
            .iter()
            .map(|l| {
                let text = &src[l.span.start as usize..l.span.end as usize];
                (text.to_owned(), l.message.clone())
            })
            .collect()
    }

    fn with(services: &str) -> String {
        format!("{COMPONENT}{services}")
    }

    const STOPS: &str = "service SetLimits {
  credential: expert;
  input: lim.qmax;
  control codel { exec: checkLimits(const lim.qmax); }
}
service Tweak {
  credential: guest;
  stops: SetLimits;
  forbids: SetLimits;
}
";

    #[test]
    fn a_weaker_service_that_stops_or_forbids_a_stronger_one() {
        let s = with(STOPS);
        let d = found(&s);
        assert_eq!(d.len(), 2, "{d:?}");
        assert_eq!(
            d[0].message,
            "service `Tweak` (credential `guest`) forbids service `SetLimits`, which needs \
             credential `expert`"
        );
        assert_eq!(
            d[1].message,
            "service `Tweak` (credential `guest`) stops service `SetLimits`, which needs \
             credential `expert`"
        );
        let l = labels(&s, &d[1]);
        assert_eq!(
            l,
            [
                ("Tweak".into(), "requestable with credential `guest`".into()),
                ("SetLimits".into(), "stops `SetLimits`".into()),
                (
                    "expert".into(),
                    "`SetLimits` needs credential `expert`".into()
                ),
            ]
        );
        assert!(
            d[1].help
                .as_deref()
                .is_some_and(|h| h.contains("can interrupt `SetLimits`"))
        );
    }

    #[test]
    fn the_same_or_a_stronger_credential_may_stop() {
        let s = with(&STOPS.replace("credential: guest", "credential: expert"));
        assert_eq!(testing::count(&s, Code::PrivilegeEscalation), 0);
        let reverse = with(
            "service A {
  credential: expert;
  delays: B;
}
service B {
  credential: operator;
}
",
        );
        assert_eq!(testing::count(&reverse, Code::PrivilegeEscalation), 0);
    }

    const WRITES: &str = "service SetLimits {
  credential: expert;
  input: lim.qmax;
  control codel { exec: checkLimits(const lim.qmax); }
}
service Move {
  credential: operator;
  control codel { exec: move(const lim.qmin, pose.x); }
}
service Tweak {
  credential: operator;
  control codel { exec: tweak(const pose.y, lim); }
}
";

    #[test]
    fn writing_an_enclosing_structure_overlaps_an_input_member() {
        let s = with(WRITES);
        let d = found(&s);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(
            d[0].message,
            "service `Tweak` (credential `operator`) writes `lim`, which service `SetLimits` \
             (credential `expert`) takes as input"
        );
        let l = labels(&s, &d[0]);
        assert_eq!(
            l[0],
            (
                "Tweak".into(),
                "requestable with credential `operator`".into()
            )
        );
        assert_eq!(l[1], ("lim".into(), "`Tweak` writes `lim` here".into()));
        assert_eq!(
            l[2],
            (
                "expert".into(),
                "`SetLimits` needs credential `expert`".into()
            )
        );
        assert_eq!(
            l[3],
            (
                "lim.qmax".into(),
                "`SetLimits` takes `lim.qmax` as input here".into()
            )
        );
    }

    #[test]
    fn const_arguments_and_disjoint_members_are_not_writes() {
        let s = with(&WRITES.replace("tweak(const pose.y, lim)", "tweak(const lim, pose.y)"));
        assert_eq!(testing::count(&s, Code::PrivilegeEscalation), 0);
    }

    #[test]
    fn an_input_parameter_stored_into_data_is_a_write() {
        let s = with(
            "service Monitor {
  credential: expert;
  thread: main;
  start codel { exec: watch(const pose.x); next: end; }
}
service SetPose {
  input: pose.x;
}
thread main { period: 10ms; }
",
        );
        let d = found(&s);
        assert_eq!(d.len(), 1, "{d:?}");
        assert!(
            d[0].message
                .starts_with("service `SetPose` (credential `guest`) writes `pose.x`")
        );
        let s = s.replace("input: pose.x", "input: pose.y");
        assert_eq!(testing::count(&s, Code::PrivilegeEscalation), 0);
    }

    #[test]
    fn report() {
        insta::assert_snapshot!(testing::render(&with(STOPS)));
        insta::assert_snapshot!("writes", testing::render(&with(WRITES)));
    }
}
