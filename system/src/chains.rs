//! Cause-effect chains across components and their worst-case data age
//! and reaction time, composed from each component's timing
//! (docs/functional-layer.md).
//!
//! A chain is a path of data: a source (an external source, or a
//! component's out port), then codels each reading the previous datum and
//! writing the next (an ids member, a local, an out port, which a
//! connection carries to an in port), up to the codel that reads the sink
//! port. Each step is a *stage*: the codels of one component that read
//! that datum and write the next, on tasks proven never to overrun, so
//! that each runs in every wake-up within `[tick, tick + W]` (`W`, the
//! task's window, is its period). With `P` the period:
//!
//! - a reader's read is less than `P + W` after the read of the execution
//!   whose write it sees (that execution read at or after its tick; the
//!   next wake-up's write comes at most `P + W` after that tick);
//! - data age `<= g0 + sum of (P + W) over the stages before the sink +
//!   W(sink)`, with `g0` the source's gap: its period for an external
//!   source, `P + W` of the writers of a component's out port (the age
//!   runs from the start of the codel that wrote the sample);
//! - reaction time (from the sample to the end of the first sink codel
//!   that uses it or a newer one) `<= r0 + sum of (P + W) over all stages`,
//!   `r0` being 0 for an external source and `W` of the writers otherwise.
//!
//! A chain does not pass twice through one codel: a codel that writes an
//! ids member it reads again later (an integrator) keeps older data
//! forever, and such feedback is not a cause-effect chain.

use std::collections::BTreeMap;

use genom_model::duration::format_ns;
use genom_model::trace::{Event, Trace, TraceStep};
use serde::Serialize;

use crate::flow::{Datum, Site};
use crate::timing::ComponentTiming;

/// Paths explored per chain request, at most.
pub const MAX_PATHS: usize = 4096;

/// One component as the chains see it.
#[derive(Debug, Clone)]
pub struct Node {
    /// Its codels on tasks.
    pub sites: Vec<Site>,
    /// Its tasks' timing.
    pub timing: ComponentTiming,
    /// Its in ports.
    pub inputs: Vec<String>,
}

/// The wiring: per `(component, in port)`, what feeds it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Feed {
    /// Another component's out port.
    Port(String, String),
    /// An external source, with its period.
    External(String, Option<u64>),
}

/// Where a chain starts.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Source {
    /// An external source.
    External(String, Option<u64>),
    /// A component's out port.
    Port(String, String),
}

impl Source {
    /// As the report writes it.
    pub fn text(&self) -> String {
        match self {
            Source::External(e, _) => e.clone(),
            Source::Port(c, p) => format!("{c}.{p}"),
        }
    }
}

/// One stage of a chain: the codels of one component that read a datum
/// and write the next (or, last, read the sink port).
#[derive(Debug, Clone, Serialize)]
pub struct Stage {
    /// The component.
    pub component: String,
    /// The task.
    pub task: String,
    /// The codel (`owner.state (function)`).
    pub codel: String,
    /// What it reads.
    pub reads: String,
    /// What it writes (`None` for the sink).
    pub writes: Option<String>,
    /// Its period (the worst of the component's codels doing this step).
    pub period_ns: Option<u64>,
    /// Its window after the tick: the latest end of its codel (of the
    /// component's codels doing this step, for a stage before the sink).
    pub window_ns: Option<u64>,
}

/// One line of a chain's trace.
#[derive(Debug, Clone, Serialize)]
pub struct TraceLine {
    /// When, from the source sample.
    pub time_ns: u64,
    /// What happens.
    pub text: String,
}

/// The bounds of one chain.
#[derive(Debug, Clone, Serialize)]
pub struct ChainReport {
    /// Its source.
    pub source: String,
    /// Its sink port.
    pub sink: String,
    /// Its stages, source side first.
    pub stages: Vec<Stage>,
    /// The source's gap: its period (external), or the period plus the
    /// window of the codels writing it; when bounded.
    pub source_gap_ns: Option<u64>,
    /// Worst-case data age, when bounded.
    pub data_age_ns: Option<u64>,
    /// Worst-case reaction time, when bounded.
    pub reaction_ns: Option<u64>,
    /// Why it has no bound.
    pub unbounded: Option<String>,
    /// Over- and under-sampling along it.
    pub sampling: Vec<String>,
    /// A timeline reaching the data-age bound.
    pub age_trace: Vec<TraceLine>,
    /// A timeline reaching the reaction-time bound.
    pub reaction_trace: Vec<TraceLine>,
}

impl ChainReport {
    /// The data-age trace as the diagnostics' trace type.
    pub fn trace(&self) -> Trace {
        Trace {
            steps: self
                .age_trace
                .iter()
                .map(|l| TraceStep {
                    time_ns: Some(l.time_ns),
                    ..TraceStep::new(Event::Delay, l.text.clone())
                })
                .collect(),
            ..Trace::default()
        }
    }
}

/// A step of a path: a site of a component, the datum it reads, the one
/// it writes.
#[derive(Debug, Clone)]
struct Step {
    component: String,
    site: usize,
    reads: Datum,
    writes: Option<Datum>,
}

/// The graph the chains walk.
pub struct Graph<'a> {
    /// The components, by name.
    pub nodes: &'a BTreeMap<String, Node>,
    /// What feeds each in port.
    pub feeds: &'a BTreeMap<(String, String), Feed>,
}

impl Graph<'_> {
    /// Every chain from `source` to the in port `sink` of `sink_component`.
    pub fn chains(&self, source: &Source, sink_component: &str, sink: &str) -> Vec<ChainReport> {
        let mut paths = Vec::new();
        let start: Vec<(String, Datum)> = match source {
            Source::External(e, _) => self
                .feeds
                .iter()
                .filter(|(_, f)| matches!(f, Feed::External(n, _) if n == e))
                .map(|((c, p), _)| (c.clone(), Datum::Port(p.clone())))
                .collect(),
            Source::Port(c, p) => vec![(c.clone(), Datum::Port(p.clone()))],
        };
        for (c, d) in start {
            let mut seen = vec![(c.clone(), d.clone())];
            self.walk(
                &c,
                &d,
                (sink_component, sink),
                &mut Vec::new(),
                &mut seen,
                &mut paths,
            );
        }
        paths
            .iter()
            .map(|p| self.report(source, sink_component, sink, p))
            .collect()
    }

    fn walk(
        &self,
        comp: &str,
        d: &Datum,
        sink: (&str, &str),
        path: &mut Vec<Step>,
        seen: &mut Vec<(String, Datum)>,
        out: &mut Vec<Vec<Step>>,
    ) {
        if out.len() >= MAX_PATHS {
            return;
        }
        // An out port: follow its connections to in ports.
        if let Datum::Port(q) = d {
            for ((c, p), f) in self.feeds {
                if f == &Feed::Port(comp.to_owned(), q.clone()) {
                    let next = (c.clone(), Datum::Port(p.clone()));
                    if !seen.contains(&next) {
                        seen.push(next);
                        self.walk(c, &Datum::Port(p.clone()), sink, path, seen, out);
                        seen.pop();
                    }
                }
            }
        }
        let Some(node) = self.nodes.get(comp) else {
            return;
        };
        let at_sink = comp == sink.0 && *d == Datum::Port(sink.1.to_owned());
        for (i, s) in node.sites.iter().enumerate() {
            if !s.reads.iter().any(|r| d.overlaps(r)) {
                continue;
            }
            if path.iter().any(|st| st.component == comp && st.site == i) {
                continue;
            }
            if at_sink {
                let mut done = path.clone();
                done.push(Step {
                    component: comp.to_owned(),
                    site: i,
                    reads: d.clone(),
                    writes: None,
                });
                out.push(done);
                continue;
            }
            for w in &s.writes {
                let next = (comp.to_owned(), w.clone());
                if seen.contains(&next) {
                    continue;
                }
                path.push(Step {
                    component: comp.to_owned(),
                    site: i,
                    reads: d.clone(),
                    writes: Some(w.clone()),
                });
                seen.push(next);
                self.walk(comp, w, sink, path, seen, out);
                seen.pop();
                path.pop();
            }
        }
    }

    /// The period and window of a site's task, or why it has none.
    fn window(&self, comp: &str, site: &Site) -> Result<(u64, u64), String> {
        let node = self
            .nodes
            .get(comp)
            .ok_or_else(|| format!("unknown component `{comp}`"))?;
        let t = node
            .timing
            .task(site.thread)
            .ok_or_else(|| format!("task `{}` of `{comp}` is not modelled", site.task))?;
        if let Some(why) = &t.unbounded {
            return Err(why.clone());
        }
        match (t.period_ns, t.window_ns) {
            (Some(p), Some(w)) => {
                // The codel's own latest end after its tick, when explored
                // (the largest over the states it runs in).
                let own = site
                    .states
                    .iter()
                    .map(|s| node.timing.window(site.thread, site.service, s))
                    .collect::<Option<Vec<u64>>>()
                    .and_then(|v| v.into_iter().max());
                Ok((p, own.map_or(w, |o| o.min(w))))
            }
            _ => Err(format!("task `{}` of `{comp}` has no period", site.task)),
        }
    }

    /// The worst `(P + W, W, P)` over the sites of `comp` that read `r`
    /// and write `w` (the stream whose latest write a reader sees).
    fn stream(&self, comp: &str, r: Option<&Datum>, w: &Datum) -> Result<(u64, u64, u64), String> {
        let node = self
            .nodes
            .get(comp)
            .ok_or_else(|| format!("unknown component `{comp}`"))?;
        let mut worst: Option<(u64, u64, u64)> = None;
        for s in &node.sites {
            let reads = r.is_none_or(|r| s.reads.iter().any(|x| r.overlaps(x)));
            if !reads || !s.writes.iter().any(|x| x.overlaps(w)) {
                continue;
            }
            let (p, win) = self.window(comp, s)?;
            let cand = (p + win, win, p);
            worst = Some(worst.map_or(cand, |x| x.max(cand)));
        }
        worst.ok_or_else(|| format!("no codel on a task of `{comp}` writes {}", w.describe()))
    }

    fn report(&self, source: &Source, sink_comp: &str, sink: &str, path: &[Step]) -> ChainReport {
        let mut stages = Vec::new();
        for st in path {
            let s = &self.nodes[&st.component].sites[st.site];
            // A stage before the sink: its stream (every codel of the
            // component doing that step), whose worst the bound takes.
            let win = match &st.writes {
                Some(w) => self
                    .stream(&st.component, Some(&st.reads), w)
                    .ok()
                    .map(|(_, win, p)| (p, win)),
                None => self.window(&st.component, s).ok(),
            };
            stages.push(Stage {
                component: st.component.clone(),
                task: s.task.clone(),
                codel: s.label(),
                reads: st.reads.describe(),
                writes: st.writes.as_ref().map(Datum::describe),
                period_ns: win.map(|w| w.0),
                window_ns: win.map(|w| w.1),
            });
        }
        let mut report = ChainReport {
            source: source.text(),
            sink: format!("{sink_comp}.{sink}"),
            stages,
            source_gap_ns: None,
            data_age_ns: None,
            reaction_ns: None,
            unbounded: None,
            sampling: Vec::new(),
            age_trace: Vec::new(),
            reaction_trace: Vec::new(),
        };
        match self.bound(source, path) {
            Ok(b) => {
                report.source_gap_ns = Some(b.gap);
                report.data_age_ns = Some(b.age);
                report.reaction_ns = Some(b.reaction);
                report.sampling = b.sampling;
                report.age_trace = b.age_trace;
                report.reaction_trace = b.reaction_trace;
            }
            Err(why) => report.unbounded = Some(why),
        }
        report
    }

    fn bound(&self, source: &Source, path: &[Step]) -> Result<Bound, String> {
        // The source's gap, the writers' window, the period of its samples.
        let (g0, r0, mut prev_period, mut prev_jitter) = match source {
            Source::External(_, Some(p)) => (*p, 0, *p, 0),
            Source::External(e, None) => {
                return Err(format!("external source `{e}` has no period"));
            }
            Source::Port(c, q) => {
                let (gap, w, p) = self.stream(c, None, &Datum::Port(q.clone()))?;
                (gap, w, p, w)
            }
        };
        let mut age_trace = vec![TraceLine {
            time_ns: 0,
            text: match source {
                Source::External(e, _) => format!("`{e}` publishes a sample"),
                Source::Port(c, q) => format!(
                    "a codel of `{c}` writing port `{q}` starts (its task's tick) and writes the sample at once"
                ),
            },
        }];
        if let Source::Port(..) = source {
            age_trace.push(TraceLine {
                time_ns: g0,
                text: "the next sample is written at the latest here: the end of the next wake-up's window"
                    .to_owned(),
            });
        } else {
            age_trace.push(TraceLine {
                time_ns: g0,
                text: "the next sample is published".to_owned(),
            });
        }
        let mut reaction_trace = vec![TraceLine {
            time_ns: 0,
            text: age_trace[0].text.clone(),
        }];
        let mut t_age = g0;
        let mut t_react = r0;
        if r0 > 0 {
            reaction_trace.push(TraceLine {
                time_ns: r0,
                text: "the writing codel ends at the end of its window, publishing the sample"
                    .to_owned(),
            });
        }
        let mut sampling = Vec::new();
        let mut age = g0;
        let mut reaction = r0;
        for (j, st) in path.iter().enumerate() {
            let s = &self.nodes[&st.component].sites[st.site];
            let who = format!("`{}` task `{}` codel {}", st.component, s.task, s.label());
            let (p, w) = self.window(&st.component, s)?;
            sampling.push(sampling_note(prev_period, prev_jitter, p, w, &who));
            let (gap, win, period) = match &st.writes {
                Some(x) => self.stream(&st.component, Some(&st.reads), x)?,
                None => (p + w, w, p),
            };
            // Data age: this stage's tick (and read) comes just before the
            // previous stage's next write.
            age_trace.push(TraceLine {
                time_ns: t_age,
                text: format!(
                    "just before this instant, {who} wakes up, reads {} (the sample above){}",
                    st.reads.describe(),
                    match &st.writes {
                        Some(x) => format!(" and writes {} at once", x.describe()),
                        None => String::new(),
                    }
                ),
            });
            // Reaction: the tick just missed the previous write.
            reaction_trace.push(TraceLine {
                time_ns: t_react + period,
                text: format!(
                    "{who} wakes up one period after a tick that just missed the sample, reads {}",
                    st.reads.describe()
                ),
            });
            reaction += gap;
            t_react += gap;
            if st.writes.is_some() && j + 1 < path.len() {
                age += gap;
                t_age += gap;
                age_trace.push(TraceLine {
                    time_ns: t_age,
                    text: format!(
                        "{who}'s next wake-up writes {} at the end of its window: the next stage reads before it",
                        st.writes.as_ref().map(Datum::describe).unwrap_or_default()
                    ),
                });
            } else {
                age += win;
                age_trace.push(TraceLine {
                    time_ns: age,
                    text: format!(
                        "{who} ends, at the end of its window: data age {}",
                        format_ns(age)
                    ),
                });
            }
            reaction_trace.push(TraceLine {
                time_ns: t_react,
                text: match &st.writes {
                    Some(x) if j + 1 < path.len() => {
                        format!("{who} writes {} at the end of its window", x.describe())
                    }
                    _ => format!(
                        "{who} ends at the end of its window: reaction time {}",
                        format_ns(reaction)
                    ),
                },
            });
            prev_period = period;
            prev_jitter = win;
        }
        Ok(Bound {
            gap: g0,
            age,
            reaction,
            sampling,
            age_trace,
            reaction_trace,
        })
    }
}

struct Bound {
    gap: u64,
    age: u64,
    reaction: u64,
    sampling: Vec<String>,
    age_trace: Vec<TraceLine>,
    reaction_trace: Vec<TraceLine>,
}

/// Over- and under-sampling of a reader of period `pr` (window `wr`) on
/// samples written every `pw` with a jitter `jw`: consecutive writes are
/// `pw - jw` to `pw + jw` apart, consecutive reads `pr - wr` to `pr + wr`.
fn sampling_note(pw: u64, jw: u64, pr: u64, wr: u64, who: &str) -> String {
    let twice = pr.saturating_sub(wr) < pw + jw;
    let misses = pw.saturating_sub(jw) < pr + wr;
    let rate = if pr < pw {
        format!(
            "over-sampling: reads every {} samples written every {}",
            format_ns(pr),
            format_ns(pw)
        )
    } else if pr > pw {
        format!(
            "under-sampling: reads every {} samples written every {}",
            format_ns(pr),
            format_ns(pw)
        )
    } else {
        format!("same period ({})", format_ns(pr))
    };
    let may = match (twice, misses) {
        (true, true) => "can read one sample twice and can miss samples",
        (true, false) => "can read one sample twice, never misses one",
        (false, true) => "never reads a sample twice, can miss samples",
        (false, false) => "reads each sample exactly once",
    };
    format!("{who}: {rate}; {may}")
}
