//! Cause-effect chains on small systems: one whose bounds are computed by
//! hand below, and generated ones checked against the exact figures of
//! an exhaustive discrete-time simulation of the composed system
//! (`genom_oracles::chain_sim`, which reads the model only).

#![allow(clippy::expect_used, clippy::unwrap_used)]

use std::collections::BTreeMap;
use std::path::Path;

use genom_model::component::Component;
use genom_model::{Code, Span};
use genom_oracles::chain_sim::{self, Chain};
use genom_system::description::parse;
use genom_system::{Limits, SystemReport, analyse};

const MS: u64 = 1_000_000;

/// A component with one periodic task: `start` (no time), then codels
/// `k0..` with the WCETs `wcets` (ms), the one at `chain` reading port
/// `inp` and writing port `outp` (when `output`), the last pausing back
/// to `k0`.
fn component(name: &str, period_ms: u64, wcets: &[u64], chain: usize, output: bool) -> Component {
    let mut text =
        format!("struct sample {{ double v; }};\ncomponent {name} {{\n  port in sample inp;\n");
    if output {
        text.push_str("  port out sample outp;\n");
    }
    text.push_str(&format!(
        "  task t {{\n    period {period_ms} ms;\n    codel<start> s0() yield k0;\n"
    ));
    let mut wcet = "t.start 0ms\n".to_owned();
    for (i, w) in wcets.iter().enumerate() {
        let params = if i == chain {
            if output {
                "port in inp, port out outp"
            } else {
                "port in inp"
            }
        } else {
            ""
        };
        let next = if i + 1 == wcets.len() {
            "pause::k0".to_owned()
        } else {
            format!("k{}", i + 1)
        };
        text.push_str(&format!("    codel<k{i}> f{i}({params}) yield {next};\n"));
        wcet.push_str(&format!("t.k{i} {w}ms\n"));
    }
    text.push_str("  };\n};\n");
    genom3_frontend::load_clean(&text, Some(&wcet)).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The system file of a line `src -> c0 -> c1 -> ...`, the chain from
/// `src` to the last component's `inp`.
fn system_text(n: usize, source_ms: u64, extra: &str) -> String {
    let mut t = String::new();
    for k in 0..n {
        t.push_str(&format!("[component.c{k}]\nfile = \"c{k}.gen\"\n"));
    }
    t.push_str(&format!(
        "[external.src]\nperiod = \"{source_ms}ms\"\nfeeds = [\"c0.inp\"]\n"
    ));
    for k in 1..n {
        t.push_str(&format!(
            "[[connect]]\nfrom = \"c{}.outp\"\nto = \"c{k}.inp\"\n",
            k - 1
        ));
    }
    t.push_str(&format!(
        "[[chain]]\nfrom = \"src\"\nto = \"c{}.inp\"\n",
        n - 1
    ));
    t.push_str(extra);
    t
}

fn run(
    text: &str,
    comps: &BTreeMap<String, Component>,
) -> (Vec<genom_model::Diagnostic>, SystemReport) {
    let file = parse(text, 0, Path::new(".")).expect("parses");
    analyse(&file, &[], comps, Limits::default(), Span::default())
}

/// Two components, one chain. `src` publishes every 2 ms into `a` (period
/// 4 ms, codels of 1 ms and 2 ms, the first the chain's), which feeds `b`
/// (period 3 ms, one codel of 1 ms). No task overruns (3 ms of work in 4,
/// 1 in 3), and each codel's window (its latest end after its tick) is
/// what precedes it in the wake-up plus its WCET: `a`'s chain codel runs
/// first, 1 ms; `b`'s, 1 ms.
///
/// Data age (`a` reads a sample less than 2 ms old; `b` reads what `a`
/// wrote less than 4 + 1 ms after `a`'s read; `b`'s codel ends within 1 ms
/// of its tick): 2 + 5 + 1 = 8 ms.
/// Reaction (the first tick of `a` after the sample comes within 4 ms and
/// its write 1 ms after that tick; the same for `b`, 3 + 1): 5 + 4 = 9 ms.
/// From `a.outp` (age from the start of `a`'s codel): 5 + 1 = 6 ms; its
/// reaction, from that start: its write within 1 ms, then `b`: 5 ms.
#[test]
fn two_components_by_hand() {
    let mut comps = BTreeMap::new();
    comps.insert("a".to_owned(), component("a", 4, &[1, 2], 0, true));
    comps.insert("b".to_owned(), component("b", 3, &[1], 0, false));
    let text = "[component.a]\nfile = \"a.gen\"\n[component.b]\nfile = \"b.gen\"\n\
        [external.src]\nperiod = \"2ms\"\nfeeds = [\"a.inp\"]\n\
        [[connect]]\nfrom = \"a.outp\"\nto = \"b.inp\"\n\
        [[chain]]\nfrom = \"src\"\nto = \"b.inp\"\ndeadline = \"7ms\"\n\
        [[chain]]\nfrom = \"a.outp\"\nto = \"b\"\n";
    let (diags, report) = run(text, &comps);
    let from_src = &report.requests[0].chains;
    assert_eq!(from_src.len(), 1);
    assert_eq!(from_src[0].data_age_ns, Some(8 * MS));
    assert_eq!(from_src[0].reaction_ns, Some(9 * MS));
    let from_a = &report.requests[1].chains;
    assert_eq!(from_a.len(), 1);
    assert_eq!(from_a[0].data_age_ns, Some(6 * MS));
    assert_eq!(from_a[0].reaction_ns, Some(5 * MS));
    // 8 ms > 7 ms: the deadline is missed, with the timeline.
    let miss: Vec<_> = diags
        .iter()
        .filter(|d| d.code == Code::ChainDeadlineMiss)
        .collect();
    assert_eq!(miss.len(), 1, "{diags:?}");
    let trace = miss[0].trace.as_ref().expect("a timeline");
    assert_eq!(trace.steps.last().and_then(|s| s.time_ns), Some(8 * MS));
    // The timeline's instants add up: each stage reads before the previous
    // one's next write, the sink ends one window after its read.
    let times: Vec<u64> = from_src[0].age_trace.iter().map(|l| l.time_ns).collect();
    assert!(times.windows(2).all(|w| w[0] <= w[1]), "{times:?}");
    // The exact worst cases are no larger.
    let chain = Chain {
        source_period: 2,
        stages: vec![
            chain_sim::stage_of(&comps["a"], "inp", MS).expect("a stage"),
            chain_sim::stage_of(&comps["b"], "inp", MS).expect("a stage"),
        ],
    };
    let exact = chain_sim::exact(&chain, 2_000_000, 100).expect("small");
    assert!(
        exact.data_age * MS <= 13 * MS && exact.reaction * MS <= 14 * MS,
        "{exact:?}"
    );
}

/// The port checks: a type mismatch, an input connected twice, an
/// unconnected input, unknown names; each at its place in the file.
#[test]
fn port_checks_point_into_the_file() {
    let mut comps = BTreeMap::new();
    comps.insert("a".to_owned(), component("a", 4, &[1], 0, true));
    comps.insert("b".to_owned(), component("b", 3, &[1], 0, false));
    let odd = genom3_frontend::load_clean(
        "struct sample { long v; };\ncomponent c {\n  port in sample inp;\n  task t { period 1 ms; codel<start> s(port in inp) yield ether; };\n};\n",
        None,
    )
    .expect("valid");
    comps.insert("c".to_owned(), odd);
    let text = "[component.a]\nfile = \"a.gen\"\n[component.b]\nfile = \"b.gen\"\n[component.c]\nfile = \"c.gen\"\n\
        [[connect]]\nfrom = \"a.outp\"\nto = \"b.inp\"\n\
        [[connect]]\nfrom = \"a.outp\"\nto = \"b.inp\"\n\
        [[connect]]\nfrom = \"a.outp\"\nto = \"c.inp\"\n\
        [[connect]]\nfrom = \"a.outq\"\nto = \"d.inp\"\n";
    let (diags, _) = run(text, &comps);
    let codes: Vec<Code> = diags.iter().map(|d| d.code).collect();
    assert!(codes.contains(&Code::DuplicateConnection), "{codes:?}");
    assert!(codes.contains(&Code::PortTypeMismatch), "{codes:?}");
    assert!(codes.contains(&Code::UnknownSystemName), "{codes:?}");
    // `a.inp` is fed by nothing.
    let unconnected: Vec<_> = diags
        .iter()
        .filter(|d| d.code == Code::UnconnectedInput)
        .collect();
    assert_eq!(unconnected.len(), 1);
    assert!(unconnected[0].message.contains("a.inp"));
    let at = |needle: &str, nth: usize| -> u32 {
        text.match_indices(needle).nth(nth).expect("in text").0 as u32
    };
    let dup = diags
        .iter()
        .find(|d| d.code == Code::DuplicateConnection)
        .unwrap();
    assert_eq!(dup.span().start, at("\"b.inp\"", 1));
    let mismatch = diags
        .iter()
        .find(|d| d.code == Code::PortTypeMismatch)
        .unwrap();
    assert_eq!(mismatch.span().start, at("\"c.inp\"", 0));
    let unknown = diags
        .iter()
        .find(|d| d.code == Code::UnknownSystemName)
        .unwrap();
    assert_eq!(unknown.span().start, at("\"a.outq\"", 0));
}

/// A small deterministic generator (no dependency).
struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: u64) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 33) % n
    }
}

/// Generated lines of 1 to 3 components: the composed bounds are never
/// below the exact worst cases of the composed system, and the ratio is
/// reported.
#[test]
#[allow(clippy::print_stderr)]
fn generated_systems_against_the_exact_oracle() {
    let mut rng = Lcg(0x5eed);
    let (mut compared, mut age_ratio, mut reaction_ratio) = (0u32, 0.0f64, 0.0f64);
    for case in 0..40 {
        let n = 1 + rng.below(3) as usize;
        let source = 1 + rng.below(3);
        let mut comps = BTreeMap::new();
        let mut stages = Vec::new();
        for k in 0..n {
            let max_period = if n == 3 { 3 } else { 4 };
            let period = 1 + rng.below(max_period);
            let codels = 1 + rng.below(2) as usize;
            let mut left = period;
            let wcets: Vec<u64> = (0..codels)
                .map(|_| {
                    let w = rng.below(left + 1);
                    left -= w;
                    w
                })
                .collect();
            let chain = rng.below(codels as u64) as usize;
            let c = component(&format!("c{k}"), period, &wcets, chain, k + 1 < n);
            stages.push(chain_sim::stage_of(&c, "inp", MS).expect("a stage"));
            comps.insert(format!("c{k}"), c);
        }
        let (_, report) = run(&system_text(n, source, ""), &comps);
        let chains = &report.requests[0].chains;
        assert_eq!(chains.len(), 1, "case {case}");
        let (Some(age), Some(reaction)) = (chains[0].data_age_ns, chains[0].reaction_ns) else {
            continue;
        };
        let chain = Chain {
            source_period: source,
            stages,
        };
        let Some(exact) = chain_sim::exact(&chain, 3_000_000, 200) else {
            continue;
        };
        assert!(
            age >= exact.data_age * MS && reaction >= exact.reaction * MS,
            "case {case}: bound {age}/{reaction} below exact {exact:?} for {chain:?}"
        );
        compared += 1;
        age_ratio += age as f64 / (exact.data_age.max(1) * MS) as f64;
        reaction_ratio += reaction as f64 / (exact.reaction.max(1) * MS) as f64;
    }
    assert!(compared >= 20, "only {compared} cases compared");
    eprintln!(
        "{compared} generated systems: the bound is on average {:.2}x the exact data age, {:.2}x the exact reaction time",
        age_ratio / f64::from(compared),
        reaction_ratio / f64::from(compared)
    );
}
