//! Cross-check of the Petri net (`genom_model::petri`) against the explorer
//! (`engine::system`): for every component, the net's reachable stable
//! markings, projected onto (init done; per service: position, pending and
//! wait bits), are exactly the explorer's configurations, and the steps
//! between them are the same. Components: `specs/*.gen`, the valid
//! fixtures, hand-written components exercising each rule of LANGUAGE.md
//! section 3, and components from a small seeded generator.

#![allow(clippy::expect_used, clippy::print_stdout)] // test support code outside #[test] functions

use crate::petri_common;

use std::path::{Path, PathBuf};

use genom_model::behaviour::Behaviour;
use genom_model::petri::PetriNet;
use genom_translate::petri::BuildPetriNet;
use petri_common::{Sizes, cross_check, load, parse};

const LIMIT: usize = 200_000;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

fn gen_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("directory exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "gen"))
        .collect();
    files.sort();
    files
}

fn show(name: &str, s: Sizes) {
    println!(
        "{name}: {} places, {} transitions; {} configurations = stable markings, {} steps, {} urgent firings",
        s.places, s.transitions, s.configs, s.edges, s.urgent_firings
    );
}

#[test]
fn specs_agree() {
    let files = gen_files(&root().join("specs"));
    assert!(files.len() >= 7);
    for f in files {
        let name = f
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let c = load(&f).unwrap_or_else(|e| panic!("{name} has static errors: {e:?}"));
        let sizes = cross_check(&name, &c, LIMIT).unwrap_or_else(|| panic!("{name}: too large"));
        show(&name, sizes);
    }
}

#[test]
fn valid_fixtures_agree() {
    let mut checked = 0;
    for f in gen_files(&root().join("tests/fixtures/valid")) {
        let name = f
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let Ok(c) = load(&f) else {
            println!("{name}: skipped (static errors)");
            continue;
        };
        let sizes = cross_check(&name, &c, LIMIT).unwrap_or_else(|| panic!("{name}: too large"));
        show(&name, sizes);
        checked += 1;
    }
    assert!(checked >= 5);
}

const HEADER: &str = "component t { lang: C; }\n\
    ids d { long x; long y; }\n\
    thread main { period: 10ms; }\n\
    thread other { period: 10ms; }\n";

/// Hand-written components, each exercising some rules of section 3.
const CASES: &[(&str, &str)] = &[
    (
        "self-stop with on-inter (pilot)",
        "service m { thread: main; report: FAR; stops: m;
           control codel { exec: mc(d.x); }
           start codel { exec: ms(); on-inter: stop; next: goto, stop; }
           exec codel goto { exec: mg(d.x, d.y); on-inter: stop; next: goto, stop, FAR; }
           inter codel stop { exec: mh(d.y); next: ; } }",
    ),
    (
        "stops another with an inter chain",
        "service a { thread: main; stops: b; start codel { exec: as1(); next: end; } }
         service b { thread: other;
           start codel { exec: bs(); on-inter: h1; next: run; }
           exec codel run { exec: br(); on-inter: h1; next: run, end; }
           inter codel h1 { exec: bh1(); next: h2; }
           inter codel h2 { exec: bh2(); next: end; } }",
    ),
    (
        "mutual and self stops",
        "service a { thread: main; stops: a, b;
           start codel { exec: as1(); on-inter: ha; next: r; }
           exec codel r { exec: ar(); on-inter: ha; next: r, end; }
           inter codel ha { exec: ah(); } }
         service b { thread: other; stops: b, a;
           start codel { exec: bs(); on-inter: hb; next: end; }
           inter codel hb { exec: bh(); next: hb, end; } }",
    ),
    (
        "delays cycle (deadlock)",
        "service a { thread: main; delays: b; start codel { exec: as1(); next: end; } }
         service b { thread: other; delays: a; start codel { exec: bs(); next: end; } }",
    ),
    (
        "delays with a loop and max-time",
        "service a { thread: main; delays: b; max-time: 1s;
           start codel { exec: as1(); next: r; }
           exec codel r { exec: ar(); next: r, end; } }
         service b { thread: other; start codel { exec: bs(); next: end; } }",
    ),
    (
        "forbids",
        "service a { thread: main; forbids: b, a; start codel { exec: as1(); next: end; } }
         service b { thread: other; forbids: c; start codel { exec: bs(); next: end; } }
         service c { report: NO; control codel { exec: cc(d.x); } }",
    ),
    (
        "init that may fail, auto, plain stopping the auto",
        "init service i { thread: main; report: FAIL; start codel { exec: is(); next: end, FAIL; } }
         auto service w { thread: other;
           start codel { exec: ws(); next: lp; }
           exec codel lp { exec: wl(); next: lp; } }
         service p { thread: main; stops: w; start codel { exec: ps(); next: end; } }",
    ),
    (
        "init without start codel and two autos",
        "init service i { report: BAD; control codel { exec: ic(d.x); } }
         auto service w1 { thread: main; start codel { exec: w1s(); next: l; } exec codel l { exec: w1l(); next: l; } }
         auto service w2 { thread: other; delays: p; start codel { exec: w2s(); next: end; } }
         service p { thread: other; start codel { exec: ps(); next: end; } }",
    ),
    (
        "watchdog on pending waits",
        "service a { thread: main; stops: b; max-time: 1s; start codel { exec: as1(); next: end; } }
         service b { thread: other;
           start codel { exec: bs(); on-inter: h; next: end; }
           inter codel h { exec: bh(); next: h, end; } }",
    ),
    (
        "lock conflicts across threads and with a control codel",
        "service a { thread: main; start codel { exec: as1(d.x); next: end; } }
         service b { thread: other; start codel { exec: bs(const d.x); next: r; }
           exec codel r { exec: br(d.y); next: end; } }
         service c { report: E; control codel { exec: cc(d.y); } }
         service e { thread: other; start codel { exec: es(const d.x); next: end; } }",
    ),
    (
        "shared thread",
        "service a { thread: main; start codel { exec: as1(); next: r; } exec codel r { exec: ar(); next: end; } }
         service b { thread: main; start codel { exec: bs(); next: end; } }
         service c { thread: main; stops: a; start codel { exec: cs(); next: end; } }",
    ),
    (
        "setter stopping a running service",
        "service set { report: E; stops: run; control codel { exec: sc(d.x); } }
         service run { thread: main;
           start codel { exec: rs(); on-inter: h; next: l; }
           exec codel l { exec: rl(const d.x); on-inter: h; next: l, end; }
           inter codel h { exec: rh(); } }",
    ),
    (
        "self-stop, stops another, delayed",
        "service a { thread: main; stops: a, b;
           start codel { exec: as1(); on-inter: h; next: end; }
           inter codel h { exec: ah(); } }
         service b { thread: other; delays: a;
           start codel { exec: bs(); on-inter: hb; next: r; }
           exec codel r { exec: br(); on-inter: hb; next: end; }
           inter codel hb { exec: bh(); } }",
    ),
    (
        "inter codel with a report",
        "service a { thread: main; report: ERR; stops: a;
           start codel { exec: as1(); on-inter: h; next: end, ERR; }
           inter codel h { exec: ah(); next: end, ERR; } }",
    ),
    (
        "stops chain",
        "service a { thread: main; stops: b; start codel { exec: as1(); next: end; } }
         service b { thread: other; stops: c; start codel { exec: bs(); on-inter: h; next: end; } inter codel h { exec: bh(); } }
         service c { thread: main; start codel { exec: cs(); on-inter: h; next: l; } exec codel l { exec: cl(); next: l, end; } inter codel h { exec: ch(); } }",
    ),
    (
        "autos without init, one delays the other",
        "auto service w1 { thread: main; delays: w2; start codel { exec: w1s(); next: l; } exec codel l { exec: w1l(); next: l; } }
         auto service w2 { thread: other; start codel { exec: w2s(); next: l; } exec codel l { exec: w2l(); next: l; } }",
    ),
    (
        "const-only sharing does not conflict",
        "service a { thread: main; start codel { exec: as1(const d.x); next: end; } }
         service b { thread: other; start codel { exec: bs(const d.x); next: end; } }
         service c { thread: other; start codel { exec: cs(d.x); next: end; } }",
    ),
    (
        "no-start services delayed and stopping",
        "service a { thread: main; delays: q; start codel { exec: as1(); next: l; } exec codel l { exec: al(); next: l, end; } }
         service q { report: E; stops: a; control codel { exec: qc(d.y); } }
         service g { }",
    ),
    (
        "self delay and self forbid are ignored",
        "service a { thread: main; delays: a; forbids: a; stops: a; start codel { exec: as1(); next: end; } }",
    ),
    (
        "init self-stop with max-time",
        "init service i { thread: main; stops: i; max-time: 2s; report: F;
           start codel { exec: is(); on-inter: h; next: r; }
           exec codel r { exec: ir(); on-inter: h; next: r, end, F; }
           inter codel h { exec: ih(); } }
         auto service w { thread: other; start codel { exec: ws(); next: l; } exec codel l { exec: wl(); next: l; } }",
    ),
    (
        "interrupt during the start codel without on-inter",
        "service a { thread: main; stops: b; start codel { exec: as1(); next: end; } }
         service b { thread: other; start codel { exec: bs(); next: r; } exec codel r { exec: br(); next: end; } }",
    ),
    (
        "on-inter only on the start codel",
        "service a { thread: main; stops: a;
           start codel { exec: as1(); on-inter: h; next: r; }
           exec codel r { exec: ar(); next: r, end; }
           inter codel h { exec: ah(); } }",
    ),
    (
        "forbidding the init service",
        "init service i { thread: main; start codel { exec: is(); next: end; } }
         service p { thread: other; forbids: i; start codel { exec: ps(); next: l; } exec codel l { exec: pl(); next: l, end; } }",
    ),
    (
        "stopping a service that delays the stopper",
        "service a { thread: main; stops: b; start codel { exec: as1(); next: end; } }
         service b { thread: other; delays: a;
           start codel { exec: bs(); on-inter: h; next: l; }
           exec codel l { exec: bl(); on-inter: h; next: l, end; }
           inter codel h { exec: bh(); } }",
    ),
    (
        "three self-stopping services on one thread with locks",
        "service a { thread: main; stops: a; start codel { exec: as1(d.x); on-inter: h; next: end; } inter codel h { exec: ah(d.x); } }
         service b { thread: main; stops: b; start codel { exec: bs(d.x); next: end; } }
         service c { thread: other; stops: c; control codel { exec: cc(d.x); } start codel { exec: cs(d.x); next: end; } }",
    ),
    (
        "removing a pending instance that waits",
        "service s { thread: main; stops: t; start codel { exec: ss(); next: end; } }
         service t { thread: main; stops: u; start codel { exec: ts(); next: end; } }
         service u { thread: other; start codel { exec: us(); on-inter: h; next: end; } inter codel h { exec: uh(); next: h, end; } }",
    ),
    (
        "autos that delay each other",
        "init service i { thread: main; start codel { exec: is(); next: end; } }
         auto service w1 { thread: main; delays: w2; start codel { exec: w1s(); next: end; } }
         auto service w2 { thread: other; delays: w1; start codel { exec: w2s(); next: end; } }",
    ),
    (
        "setter with stops and a pending slot",
        "service s { stops: t, s; control codel { exec: sc(d.x); } }
         service t { thread: main; start codel { exec: ts(const d.x); on-inter: h; next: end; } inter codel h { exec: th(); } }",
    ),
    (
        "watchdog on every position",
        "service a { thread: main; max-time: 1s; report: E;
           start codel { exec: as1(); on-inter: h; next: r, E; }
           exec codel r { exec: ar(); next: r, end; }
           inter codel h { exec: ah(); next: h2; }
           inter codel h2 { exec: ah2(); next: end, E; } }",
    ),
    (
        "delayed self-stopper waits on itself",
        "service a { thread: main; stops: a; delays: b; start codel { exec: as1(); on-inter: h; next: end; } inter codel h { exec: ah(); } }
         service b { thread: other; stops: a; start codel { exec: bs(); next: end; } }",
    ),
    (
        "init stopping, forbidding and delaying",
        "init service i { thread: main; stops: p; forbids: q; delays: p; start codel { exec: is(); next: end; } }
         service p { thread: other; start codel { exec: ps(); next: end; } }
         service q { thread: other; start codel { exec: qs(); next: end; } }",
    ),
    (
        "four services mixing everything",
        "service a { thread: main; stops: a, c; max-time: 1s; control codel { exec: ac(d.y); }
           start codel { exec: as1(d.x); on-inter: h; next: r; }
           exec codel r { exec: ar(d.x); on-inter: h; next: r, end; }
           inter codel h { exec: ah(d.x); } }
         service b { thread: other; delays: c; forbids: d; start codel { exec: bs(const d.x); next: end; } }
         service c { thread: other; start codel { exec: cs(d.y); on-inter: h; next: end; } inter codel h { exec: ch(); } }
         service d { report: E; control codel { exec: dc(const d.y); } }",
    ),
];

#[test]
fn hand_written_components_agree() {
    assert!(CASES.len() >= 30);
    for (name, body) in CASES {
        let c = parse(&format!("{HEADER}{body}")).unwrap_or_else(|e| panic!("{name}: {e:?}"));
        let sizes = cross_check(name, &c, LIMIT).unwrap_or_else(|| panic!("{name}: too large"));
        show(name, sizes);
    }
}

/// splitmix64.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    fn percent(&mut self, p: usize) -> bool {
        self.below(100) < p
    }
}

/// A random small component: 2–4 services, 1–2 threads, random kinds,
/// rules (self included), max-times, control codels, codel graphs with
/// on-inter chains and lock uses.
fn generated(seed: u64) -> String {
    let mut r = Rng(seed);
    let n = 2 + r.below(3);
    let threads = 1 + r.below(2);
    let mut out = String::from("component g { lang: C; }\nids d { long x; long y; }\n");
    for t in 0..threads {
        out.push_str(&format!("thread t{t} {{ period: 10ms; }}\n"));
    }
    let init = r.percent(30);
    for i in 0..n {
        out.push_str(&service(&mut r, i, n, threads, init && i == 0));
    }
    out
}

fn service(r: &mut Rng, i: usize, n: usize, threads: usize, init: bool) -> String {
    let auto = !init && r.percent(20);
    let kind = if init {
        "init "
    } else if auto {
        "auto "
    } else {
        ""
    };
    let start = r.percent(80);
    let mut s = format!("{kind}service s{i} {{\n");
    if start {
        s.push_str(&format!("  thread: t{};\n", r.below(threads)));
    }
    let report = r.percent(40);
    if report {
        s.push_str("  report: E;\n");
    }
    if r.percent(30) {
        s.push_str("  max-time: 1s;\n");
    }
    for (rule, p) in [("stops", 25), ("delays", 15), ("forbids", 10)] {
        let targets: Vec<String> = (0..n)
            .filter(|_| r.percent(p))
            .map(|j| format!("s{j}"))
            .collect();
        if !targets.is_empty() {
            s.push_str(&format!("  {rule}: {};\n", targets.join(", ")));
        }
    }
    if r.percent(40) {
        s.push_str(&format!("  control codel {{ exec: c{i}({}); }}\n", args(r)));
    }
    if start {
        s.push_str(&codels(r, i, report));
    }
    s.push_str("}\n");
    s
}

fn args(r: &mut Rng) -> String {
    let mut v = Vec::new();
    for m in ["d.x", "d.y"] {
        match r.below(3) {
            0 => v.push(m.to_owned()),
            1 => v.push(format!("const {m}")),
            _ => {}
        }
    }
    v.join(", ")
}

fn pick(r: &mut Rng, options: &[String]) -> String {
    let chosen: Vec<&str> = options
        .iter()
        .filter(|_| r.percent(45))
        .map(String::as_str)
        .collect();
    chosen.join(", ")
}

fn codels(r: &mut Rng, i: usize, report: bool) -> String {
    let execs: Vec<String> = (0..r.below(3)).map(|k| format!("e{k}")).collect();
    let inters: Vec<String> = (0..r.below(3)).map(|k| format!("h{k}")).collect();
    let mut exits = vec!["end".to_owned()];
    if report {
        exits.push("E".to_owned());
    }
    let mut forward: Vec<String> = execs.clone();
    forward.extend(exits.iter().cloned());
    let mut s = String::new();
    let heads: Vec<String> = std::iter::once("start".to_owned())
        .chain(execs.iter().cloned())
        .collect();
    for (k, name) in heads.iter().enumerate() {
        let on_inter = if !inters.is_empty() && r.percent(60) {
            format!(" on-inter: {};", inters[r.below(inters.len())])
        } else {
            String::new()
        };
        let kind = if k == 0 {
            "start codel".to_owned()
        } else {
            format!("exec codel {name}")
        };
        let next = pick(r, &forward);
        s.push_str(&format!(
            "  {kind} {{ exec: f{i}_{name}({});{on_inter} next: {next}; }}\n",
            args(r)
        ));
    }
    let mut stop_next: Vec<String> = inters.clone();
    stop_next.extend(exits);
    for name in &inters {
        let next = pick(r, &stop_next);
        s.push_str(&format!(
            "  inter codel {name} {{ exec: f{i}_{name}({}); next: {next}; }}\n",
            args(r)
        ));
    }
    s
}

#[test]
fn generated_components_agree() {
    let (mut checked, mut skipped, mut too_large, mut total) = (0, 0, 0, 0usize);
    for seed in 0..300u64 {
        let src = generated(seed);
        let c = match parse(&src) {
            Ok(c) => c,
            Err(e) => {
                println!("seed {seed}: skipped, static errors {e:?}\n{src}");
                skipped += 1;
                continue;
            }
        };
        let name = format!("generated seed {seed}");
        match cross_check(&name, &c, 20_000) {
            Some(sizes) => {
                checked += 1;
                total += sizes.configs;
            }
            None => too_large += 1,
        }
    }
    println!(
        "generated: {checked} compared ({total} configurations), {skipped} with static errors, {too_large} too large"
    );
    assert!(
        checked >= 200,
        "only {checked} generated components compared"
    );
}

#[test]
fn pilot_net_listing() {
    let c = load(&root().join("specs/pilot.gen")).expect("pilot checks clean");
    let net = PetriNet::build(&c, &Behaviour::new(&c));
    let listing = net.listing();
    assert!(
        listing
            .contains("moveDistance.ready.goto.stop: moveDistance at goto (ready, on-inter: stop)")
    );
    assert!(listing.contains("request moveDistance: interrupt moveDistance running goto"));
    println!("{listing}");
}

#[test]
fn places_and_transitions_are_named_located_and_ranked() {
    use genom_model::Span;
    use genom_model::petri::{
        PRIORITY_CLEAR, PRIORITY_DROP, PRIORITY_REQUEST, PRIORITY_START, PRIORITY_STEP,
        TransitionKind as K,
    };
    for f in gen_files(&root().join("specs")) {
        let c = load(&f).expect("specs check clean");
        let net = PetriNet::build(&c, &Behaviour::new(&c));
        for p in &net.places {
            assert!(
                p.span != Span::default() && !p.label.is_empty(),
                "{}",
                p.name
            );
        }
        for t in &net.transitions {
            assert!(
                t.span != Span::default() && !t.label.is_empty(),
                "{}",
                t.name
            );
            let level = match t.kind {
                K::Request(_) | K::Begin(..) | K::Finish(..) | K::Watchdog(..) => PRIORITY_STEP,
                K::Start(_) => PRIORITY_START,
                K::ClearWait(..) => PRIORITY_CLEAR,
                K::RequestStep(_) | K::Acknowledge(_) => PRIORITY_REQUEST,
                K::Drop(_) => PRIORITY_DROP,
                K::Genom3(_) => panic!("a GenoM3 transition in a LANGUAGE.md net: {}", t.name),
            };
            assert_eq!(t.priority, level, "{}", t.name);
        }
    }
}

/// A model whose `stops` lists a service twice (the resolver drops repeated
/// names, so only a hand-built model can): both the net and the explorer
/// keep one wait per distinct target.
#[test]
fn repeated_stops_entries_agree() {
    let src = format!(
        "{HEADER}service a {{ thread: main; stops: b; start codel {{ exec: as1(); next: end; }} }}
         service b {{ thread: other; start codel {{ exec: bs(); next: r; }} exec codel r {{ exec: br(); next: end; }} }}"
    );
    let mut c = parse(&src).expect("clean");
    let a = c.service_named("a").expect("a");
    let again = c.services[a].stops[0];
    c.services[a].stops.push(again);
    cross_check("repeated stops entry", &c, LIMIT);
}

/// The worked example of `docs/semantics.md`: in the pilot, a request of
/// `moveDistance` waits while `goto` runs (its control codel writes
/// `demoIds`, which `goto` holds), then interrupts the instance between
/// two codels; the new instance starts once `stop` has run.
#[test]
fn pilot_worked_example() {
    use genom_oracles::petri::{fire, fireable, is_stable};
    let c = load(&root().join("specs/pilot.gen")).expect("pilot checks clean");
    let net = PetriNet::build(&c, &Behaviour::new(&c));
    let id = |name: &str| {
        let i = net.transitions.iter().position(|t| t.name == name);
        genom_model::petri::TransitionId(u32::try_from(i.expect(name)).expect("small"))
    };
    let marked = |m: &[u32]| {
        let names: Vec<&str> = net
            .places
            .iter()
            .zip(m)
            .filter(|(_, n)| **n > 0)
            .map(|(p, _)| p.name.as_str())
            .collect();
        names.join(", ")
    };
    let mut m = net.initial.clone();
    let script = [
        "moveDistance.request",
        "moveDistance.req.0.nopending.moveDistance",
        "moveDistance.req.1.moveDistance.idle",
        "moveDistance.ack",
        "moveDistance.start",
        "moveDistance.begin.ready.start",
        "moveDistance.finish.run.start.0",
        "moveDistance.begin.ready.goto.stop",
        "moveDistance.finish.run.goto.0",
        "moveDistance.request",
        "moveDistance.req.0.nopending.moveDistance",
        "moveDistance.req.1.moveDistance.ready.goto.stop",
        "moveDistance.ack",
        "moveDistance.begin.stopready.stop",
        "moveDistance.finish.stoprun.stop.0",
        "moveDistance.clear.moveDistance",
        "moveDistance.start",
    ];
    println!("initial: {}", marked(&m));
    for name in script {
        let t = id(name);
        if name == "moveDistance.finish.run.goto.0" {
            assert!(
                !net.transitions[id("moveDistance.request").0 as usize].enabled(&m),
                "locked by goto"
            );
        }
        assert!(
            fireable(&net, &m).contains(&t),
            "{name} cannot fire in {}",
            marked(&m)
        );
        m = fire(&net, &m, t).expect("fires");
        let stable = if is_stable(&net, &m) {
            "stable"
        } else {
            "unstable"
        };
        println!("{name} -> {stable}: {}", marked(&m));
    }
    assert_eq!(
        net.position(&m, c.service_named("moveDistance").expect("service")),
        Some(1)
    );
}
