//! The Petri net of GenoM3 components (`export tina`: the net of
//! GenoM3's untimed semantics, built from the component independently of
//! the engine) against the untimed GenoM3 engine. The exported `.net` text
//! is read back by a reader of TINA's format (`tina_net`, written from the
//! format's reference), rebuilt as a net, and explored by the token game
//! of the oracles crate (`genom_oracles::petri::stable_graph`); the
//! services whose step transitions never fire and the codels whose
//! transitions never fire must be exactly genom-check's `dead-service` and
//! `unreachable-codel` verdicts. Also checked on every net: it is safe
//! (one token per place at most), every urgent cascade is finite and
//! deterministic, and the net read back is the net built
//! (`PetriNet::build_genom3`), arc for arc.
//!
//! Components: the semantics and timing fixtures (read untimed), the four
//! components written for the SPIN test, generated ones
//! (`generate_genom3`, small sizes) and the corpus when present; a
//! component whose net has more than [`BUDGET`] stable markings is
//! skipped and listed.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use genom_generate::{Genom3Config, generate_genom3};
use genom_model::component::Component;
use genom_model::petri::{G3_PRIORITY_STEP, PetriNet};
use genom_oracles::petri::stable_graph;
use genom_translate::petri_genom3::BuildGenom3PetriNet;

use genom_export::{ExportInput, Format, Verification, export};

use super::genom3_untimed::{HAND, Ours, Verdicts, files, ours};
use super::tina_net;

/// Generated components compared (seeds `0..GENERATED`).
const GENERATED: u64 = 60;
/// The bound on stable markings (and branching cascades) per net.
const BUDGET: usize = 30_000;

/// The net of `c` as its `tina` export describes it, read back; checked
/// against the net built.
fn exported_net(c: &Component) -> PetriNet {
    let verification = Verification::default();
    let sources = genom_model::SourceMap::default();
    let input = ExportInput {
        component: c,
        sources: &sources,
        verification: &verification,
    };
    let text = export(Format::Tina, &input).expect("exports").main;
    let read = tina_net::parse(&text).unwrap_or_else(|e| panic!("{}: {e}", c.name.name));
    let net = read
        .to_petri()
        .unwrap_or_else(|e| panic!("{}: {e}", c.name.name));
    let built = PetriNet::build_genom3(c).expect("a GenoM3 component");
    assert_eq!(
        net.initial, built.initial,
        "{}: initial marking",
        c.name.name
    );
    for (a, b) in net.transitions.iter().zip(&built.transitions) {
        let same = (&a.pre, &a.post, &a.read, &a.inhibit, a.priority)
            == (&b.pre, &b.post, &b.read, &b.inhibit, b.priority);
        assert!(
            same,
            "{}: transition {} read back differs",
            c.name.name, b.name
        );
    }
    assert_eq!(net.transitions.len(), built.transitions.len());
    // Untimed: the steps at any time, everything else urgent.
    for (t, b) in read.transitions.iter().zip(&built.transitions) {
        let urgent = if b.priority > G3_PRIORITY_STEP {
            "[0,0]"
        } else {
            "[0,w["
        };
        assert_eq!(t.interval, urgent, "{}: {}", c.name.name, t.name);
    }
    net
}

/// The label of a transition as the export's comment gives it: what it
/// stands for, before its priority.
fn label(comment: &str) -> &str {
    comment
        .rfind(" (priority ")
        .map_or(comment, |at| &comment[..at])
}

/// The verdicts the net shows, and its size, or why it was not compared.
fn net_verdicts(c: &Component) -> Result<(Verdicts, usize), String> {
    let net = exported_net(c);
    let g = stable_graph(&net, BUDGET);
    if g.stopped {
        return Err(format!("over {BUDGET} markings"));
    }
    assert!(!g.urgent_cycle, "{}: an urgent cascade loops", c.name.name);
    assert_eq!(g.nondeterministic, 0, "{}: a cascade branches", c.name.name);
    assert!(g.max_tokens <= 1, "{}: the net is not safe", c.name.name);
    assert_eq!(g.initial.len(), 1, "{}: one initial marking", c.name.name);
    let mut reached: BTreeMap<String, bool> = BTreeMap::new();
    let fired: std::collections::BTreeSet<usize> = g.edges.iter().map(|e| e.1.0 as usize).collect();
    for (k, t) in net.transitions.iter().enumerate() {
        if t.priority != G3_PRIORITY_STEP {
            continue;
        }
        for fact in label(&t.label).split("; ") {
            *reached.entry(fact.to_owned()).or_insert(false) |= fired.contains(&k);
        }
    }
    Ok((Verdicts::of_facts(c, &reached), g.markings.len()))
}

/// What comparing one component gave: its differences (empty when
/// none), and whether it has a dead service or an unreachable codel.
struct Compared {
    diff: String,
    found: bool,
}

/// Compares one file; `Err` says why it was skipped.
fn compare(path: &Path) -> Result<Option<Compared>, String> {
    let (component, verdicts) = match ours(path) {
        Ours::Verdicts(c, v, _) => (c, v),
        Ours::OverBudget => return Err(format!("{} (genom-check)", path.display())),
        Ours::NoComponent => return Ok(None),
    };
    let (net, markings) =
        net_verdicts(&component).map_err(|e| format!("{}: {e}", path.display()))?;
    let found = !(verdicts.dead.is_empty() && verdicts.unreachable.is_empty());
    let diff = if net == verdicts {
        String::new()
    } else {
        format!(
            "\n== {} ({markings} stable markings)\ngenom-check: {verdicts:?}\nnet:         {net:?}\n",
            path.display()
        )
    };
    Ok(Some(Compared { diff, found }))
}

#[test]
fn the_genom3_net_shows_the_engines_untimed_verdicts() {
    let started = Instant::now();
    let temp = tempfile::tempdir().expect("temporary directory");
    let mut jobs = files();
    for (name, text) in HAND {
        let path = temp.path().join(format!("{name}.gen"));
        std::fs::write(&path, text).expect("written");
        jobs.push(path);
    }
    for seed in 0..GENERATED {
        let generated = generate_genom3(&Genom3Config::small(seed));
        let path = temp.path().join(format!("generated-{seed}.gen"));
        std::fs::write(&path, generated.r#gen).expect("written");
        jobs.push(path);
    }
    let (mut compared, mut skipped, mut failures) = (0, Vec::new(), String::new());
    let mut with_findings = 0;
    for job in &jobs {
        match compare(job) {
            Ok(Some(c)) => {
                compared += 1;
                with_findings += usize::from(c.found);
                failures.push_str(&c.diff);
            }
            Ok(None) => {}
            Err(why) => skipped.push(why),
        }
    }
    eprintln!(
        "GenoM3 nets: {compared} components compared ({with_findings} with a dead service or an \
         unreachable codel) in {:.1} s; skipped: {skipped:?}",
        started.elapsed().as_secs_f64()
    );
    assert!(failures.is_empty(), "the net disagrees:{failures}");
    assert!(compared >= 80, "too few components compared: {compared}");
    assert!(
        with_findings >= 8,
        "too few findings to compare: {with_findings}"
    );
}
