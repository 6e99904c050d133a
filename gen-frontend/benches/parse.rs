//! Parser throughput: a generated 20,000-line component (IDL types, IDS
//! members, export/import data, threads, services with codels) and the
//! canonical example `specs/pilot.gen`.
//!
//! `cargo bench -p gen-frontend --bench parse -- --warm-up-time 1 --measurement-time 5`

use std::fmt::Write as _;
use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use gen_frontend::parse_str;

const PILOT: &str = include_str!("../../specs/pilot.gen");

/// Lines in the generated component.
const LINES: usize = 20_000;

/// A realistic component of at least `lines` lines.
fn generate(lines: usize) -> String {
    let mut s = String::with_capacity(lines * 40);
    s.push_str("/* Generated benchmark component. */\n");
    s.push_str("component bench {\n  category: default;\n  lang: C;\n  version: \"1.0\";\n");
    s.push_str(
        "  doc: \"A large generated component\";\n  credentials: none < user < admin;\n}\n\n",
    );

    // IDL: constants, enums, structs, modules.
    for i in 0..60 {
        let _ = writeln!(s, "const long N{i} = 2 * {i} + 1;");
        let _ = writeln!(s, "enum mode{i} {{ IDLE{i}, RUN{i}, STOP{i} }};");
        let _ = writeln!(s, "typedef struct state{i} {{");
        let _ = writeln!(s, "  double position;   /* current position */");
        let _ = writeln!(s, "  double speed[3];    // per axis");
        let _ = writeln!(s, "  unsigned long long stamp;");
        let _ = writeln!(s, "  sequence<double, 16> history;");
        let _ = writeln!(s, "  string<32> label;");
        let _ = writeln!(s, "}} state{i};");
        let _ = writeln!(
            s,
            "module m{i} {{\n  typedef double vec3[3];\n  struct pose {{ vec3 p; vec3 q; }};\n}};\n"
        );
    }

    // IDS: many members with defaults and docs.
    s.push_str("ids benchIds {\n");
    for i in 0..2_000 {
        match i % 4 {
            0 => {
                let _ = writeln!(s, "  double ref{i} := 0.{i} \"Reference {i}\";");
            }
            1 => {
                let _ = writeln!(s, "  long count{i} := -{i};");
            }
            2 => {
                let _ = writeln!(s, "  m{}::vec3 v{i} := {{1.0, 2.0, 3.0}};", i % 60);
            }
            _ => {
                let _ = writeln!(s, "  state{} st{i};", i % 60);
            }
        }
    }
    s.push_str("}\n\n");

    // Exported and imported data with struct initialisers.
    for i in 0..100 {
        let _ = writeln!(s, "export out{i} {{");
        let _ = writeln!(s, "  state{} st {{", i % 60);
        let _ = writeln!(s, "    position := 0.0 \"Current position\";");
        let _ = writeln!(s, "    speed := {{0.0, 0.0, 0.0}} \"Current speed\";");
        let _ = writeln!(s, "  }}");
        let _ = writeln!(s, "  double battery := 12.0 \"Battery voltage\";\n}}");
        let _ = writeln!(s, "import in{i} {{ state{} target \"Target\"; }}\n", i % 60);
    }

    // Threads.
    for i in 0..50 {
        let _ = writeln!(s, "thread task{i} {{");
        let _ = writeln!(s, "  priority: {};\n  period: {}ms;", i % 5, 10 + i);
        let _ = writeln!(s, "  stack: 64k;\n  start: init{i};\n  stop: end{i};\n}}\n");
    }

    // Services until the line count is reached.
    let mut i = 0;
    while s.lines().count() < lines {
        let kind = match i % 10 {
            0 => "auto ",
            _ => "",
        };
        let ids = i % 2_000 / 4 * 4;
        let _ = writeln!(s, "{kind}service svc{i} {{");
        let _ = writeln!(s, "  doc: \"Service number {i}\";");
        let _ = writeln!(s, "  thread: task{};", i % 50);
        let _ = writeln!(s, "  report: TOO_FAR{i}, BLOCKED{i};");
        let _ = writeln!(s, "  max-time: 2s;\n  credential: user;");
        let _ = writeln!(s, "  stops: svc{i};\n  delays: svc{};", i + 1);
        let _ = writeln!(
            s,
            "  input: benchIds.ref{ids} := 0.0 \"Distance\", double speed := 0.1;"
        );
        let _ = writeln!(
            s,
            "  output: double reached \"Final position\", benchIds.ref{ids};"
        );
        let _ = writeln!(
            s,
            "  control codel {{ exec: check{i}(benchIds.ref{ids}); }}"
        );
        let _ = writeln!(s, "  start codel {{");
        let _ = writeln!(
            s,
            "    exec: begin{i}(const benchIds.ref{ids}, out{}.st);",
            i % 100
        );
        let _ = writeln!(s, "    on-inter: stop;\n    next: main, stop;\n  }}");
        let _ = writeln!(s, "  exec codel main {{");
        let _ = writeln!(
            s,
            "    exec: step{i}(benchIds.ref{ids}, out{}.st.speed[2]);",
            i % 100
        );
        let _ = writeln!(s, "    update: benchIds.ref{ids};");
        let _ = writeln!(s, "    on-inter: stop;\n    max-time: 20ms;");
        let _ = writeln!(s, "    next: main, stop, TOO_FAR{i};\n  }}");
        let _ = writeln!(s, "  inter codel stop {{");
        let _ = writeln!(s, "    exec: halt{i}(out{}.st);", i % 100);
        let _ = writeln!(
            s,
            "    update: out{}.st;\n    next: ;   // done\n  }}\n}}\n",
            i % 100
        );
        i += 1;
    }
    s
}

fn bench_parse(c: &mut Criterion) {
    let big = generate(LINES);
    let parsed = parse_str("bench.gen", &big);
    assert!(
        parsed.diagnostics.is_empty(),
        "the generated component must parse clean: {:#?}",
        parsed.diagnostics
    );
    assert!(parsed.ast.items().count() > 500);

    let mut group = c.benchmark_group("parse");
    group.throughput(Throughput::Bytes(big.len() as u64));
    group.bench_function(format!("generated_{LINES}_lines"), |b| {
        b.iter(|| parse_str("bench.gen", black_box(&big)));
    });
    group.throughput(Throughput::Bytes(PILOT.len() as u64));
    group.bench_function("pilot.gen", |b| {
        b.iter(|| parse_str("pilot.gen", black_box(PILOT)));
    });
    group.finish();
}

criterion_group!(benches, bench_parse);
criterion_main!(benches);
