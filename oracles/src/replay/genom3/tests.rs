//! Tests of the GenoM3 replay: engine traces replay, tampered ones do not.

use std::path::Path;

use genom_engine::genom3::{Machine, analyse_genom3, steps::Engine, trace::render};
use genom_engine::kernel::explore::{Limits, Model};

use super::*;

const F1A: &str = "component f1a {
  ids { long n; };
  task t { period 10 ms; };
  activity spin() {
    task t;
    codel<start> f1_start(out n) yield step, ether;
    codel<step> f1_step(inout n) yield step;
  };
  activity other() { task t; codel<start, w> f1_other() yield pause::w, ether; };
};";

const G: &str = "component g {
  task m { codel<start> g_s() yield main; codel<main> g_m() yield main, pause::main; };
  task t { period 10 ms; };
  function setup() { codel g_setup(); };
  activity go() {
    task t; after setup;
    codel<start> g_go() yield a; codel<a> g_a() yield b, ether; codel<b> g_b() yield a;
  };
  function late() { before go; codel g_late(); };
};";

const H: &str = "component h {
  task m { codel<start> h_s() yield ether; codel<stop> h_stop() yield ether; };
  task t { period 10 ms; };
  activity servo() {
    task t;
    codel<start, main> h_main() yield pause::main, main;
    codel<stop> h_halting() yield pause::stop, ether;
  };
  activity halt() { task t; interrupts servo; codel<start> h_halt() yield ether; };
};";

const K: &str = "component k {
  task m { codel<start> k_s() yield ether; codel<stop> k_stop() yield pause::stop, ether; };
  task t { period 10 ms; };
  activity mv() {
    task t; interrupts mv;
    codel<start> k_s2() yield run; codel<run> k_r() yield pause::run, run, ether;
    codel<stop> k_st() yield pause::stop, ether;
  };
  function halt() { interrupts mv; codel k_halt(); };
};";

fn load(text: &str) -> Component {
    crate::testing::load_genom3(text)
}

/// A trace after `component-start`, steps separated by `;`: `accept S
/// [pending]`, `start T S`, `abort S [state]`, `T S state>outcome` (S
/// `-`: T's permanent activity), `violation T`; `loop` opens the loop.
fn trace(text: &str) -> Trace {
    let mut t = Trace::default();
    t.steps.push(TraceStep::new(Event::ComponentStart, ""));
    for part in text.split(';') {
        let w: Vec<&str> = part.split_whitespace().collect();
        let (event, thread, rest) = match w[0] {
            "loop" => {
                t.loop_start = Some(t.steps.len());
                continue;
            }
            "accept" => (Event::Accept, "control", &w[1..]),
            "reject" => (Event::Reject, "control", &w[1..]),
            "abort" => (Event::Interrupt, "control", &w[1..]),
            "start" => (Event::Start, w[1], &w[2..]),
            "violation" => (Event::Violation, w[1], &w[2..]),
            task => (Event::CodelEnd, task, &w[1..]),
        };
        let mut s = TraceStep::new(event, "");
        s.thread = Some(thread.to_owned());
        let word = |k: usize| rest.get(k).map(|x| (*x).to_owned());
        s.service = word(0).filter(|x| x != "-");
        match event {
            Event::Accept => s.outcome = word(1),
            Event::Reject => s.outcome = Some("genom::disallowed".into()),
            Event::Interrupt => (s.codel, s.outcome) = (word(1), Some("abort_activity".into())),
            Event::Start => s.codel = Some("start".into()),
            Event::CodelEnd => {
                let (c, o) = rest[1].split_once('>').unwrap();
                (s.codel, s.outcome) = (Some(c.into()), Some(o.into()));
            }
            _ => {}
        }
        t.steps.push(s);
    }
    t
}

/// Each case is a trace for [`trace`] after `prefix`, then either
/// nothing (it replays) or `=> N why` (it fails at step N, 1-based,
/// saying `why`).
fn check(c: &Component, prefix: &str, cases: &[&str]) {
    for case in cases {
        let (steps, fail) = case.split_once("=>").unwrap_or((case, ""));
        let text = [prefix, steps].join(";");
        let got = replay_genom3(c, &trace(text.trim_matches(';')));
        match fail.trim().split_once(' ') {
            None => assert_eq!(got, Ok(()), "{case}"),
            Some((n, why)) => {
                let e = got.unwrap_err();
                assert!(
                    e.starts_with(&format!("step {n} ")) && e.contains(why),
                    "{e}"
                );
            }
        }
    }
}

/// The fixtures of the GenoM3 semantics and those above.
fn components() -> Vec<Component> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/genom3/semantics");
    let files = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path());
    let mut texts: Vec<String> = files.map(|p| std::fs::read_to_string(p).unwrap()).collect();
    texts.extend([F1A, G, H, K].map(str::to_owned));
    texts.iter().map(|t| load(t)).collect()
}

#[test]
fn engine_livelock_traces_replay() {
    for c in components() {
        for n in [1, 2] {
            for l in analyse_genom3(&c, n, Limits::default()).unwrap().livelocks {
                replay_genom3(&c, &l.trace).unwrap_or_else(|e| panic!("{e}\n{:#?}", l.trace));
            }
        }
    }
    let c = load(F1A);
    let spin = analyse_genom3(&c, 1, Limits::default())
        .unwrap()
        .livelocks
        .remove(0);
    assert_eq!(spin.trace.loop_start, Some(4));
    for (k, to, why) in [
        (4, "pause::step", "does not yield"),
        (3, "exception", "no started"),
    ] {
        let mut t = spin.trace.clone();
        t.steps[k].outcome = Some(to.to_owned());
        let e = replay_genom3(&c, &t).unwrap_err();
        assert!(e.starts_with("step 5 ") && e.contains(why), "{e}");
    }
}

/// Seeded random walks of the engine, rendered by the engine, replay.
#[test]
fn engine_random_walks_replay() {
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    for (c, n) in components().iter().flat_map(|c| [(c, 1), (c, 3)]) {
        let engine = Engine::new(Machine::new(c, n).unwrap());
        for _ in 0..100 {
            let (mut s, mut path, mut actions) = (engine.initial(), Vec::new(), Vec::new());
            for _ in 0..40 {
                actions.clear();
                engine.actions(&s, &mut actions);
                seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                let pick = (seed >> 33) as usize % actions.len().max(1);
                let Some(&a) = actions.get(pick) else { break };
                s = engine.next_state(&s, a).unwrap_or(s);
                path.push(a);
            }
            let t = render(&engine, &path);
            replay_genom3(c, &t).unwrap_or_else(|e| panic!("{e}\n{t:#?}"));
        }
    }
}

#[test]
fn codels_need_a_started_instance_and_one_of_their_yields() {
    check(
        &load(F1A),
        "",
        &[
            "t spin start>step => 2 no started instance of `spin` is at state `start`",
            "accept spin; t spin start>step => 3 no started instance of `spin`",
            "accept spin; start t spin; t spin start>w => 4 does not yield `w`",
            "accept other; start t other; start t other => 4 did not run its `start` codel at once",
            "accept other; start t other; t other start>pause::w; start t other => 5 no instance of `other` is ready",
            "accept other; start t other; t other start>w => 4 does not yield `w`",
            "accept other; start t other; t other start>pause::w; t other w>exception",
            "accept other; start t other; t other start>pause::w; t other w>exception; \
         t other w>ether => 6 no started instance",
        ],
    );
}

#[test]
fn after_before_and_boot_are_checked() {
    check(
        &load(G),
        "",
        &[
            "accept setup => 2 the component is still starting",
            "m - start>main; accept go => 3 `go` is `after setup`, which never completed",
            "m - start>main; accept late; accept setup; accept go; start t go; t go start>a; \
         m - main>pause::main; t go a>ether; accept late => 10 `late` is `before go`",
            "m - start>exception; accept setup => 3 the component failed to start",
            "m - start>main; m - main>exception; accept setup",
            "m - start>main; reject go; accept setup; reject setup => 5 is not refused",
            "m - start>main; accept setup; reject go => 4 `go` is not refused",
            "reject go => 2 once the component runs",
        ],
    );
}

#[test]
fn a_lasso_is_one_closed_unpaused_round() {
    let c = load(G);
    check(
        &c,
        "m - start>main; accept setup; accept go; start t go; t go start>a",
        &[
            "loop; t go a>b; t go b>a; violation t",
            "loop; t go a>b; violation t => 7 the loop is not closed",
            "loop; t go a>b; m - main>main; t go b>a => 8 runs the codels of one activity",
            "accept go; start t go; t go start>a; loop; t go a>b; t go a>b; violation t \
         => 11 the codel does not run in the state the previous one yielded",
        ],
    );
    check(
        &c,
        "m - start>main",
        &[
            "loop; m - main>main; violation m",
            "loop; m - main>pause::main; violation m => 3 without `pause::`",
            "violation m; m - main>main => 3 a violation is the last step",
        ],
    );
}

#[test]
fn interrupters_wait_for_the_stop_path() {
    // The end of `servo`'s stop path releases both waiting `halt`s.
    check(
        &load(H),
        "m - start>ether; accept servo; start t servo; t servo start>pause::main",
        &[
            "accept halt => 6 the new instance of `halt` is `pending`",
            "accept halt later => 6 an accepted request has no outcome `later`",
            "accept halt pending; start t halt => 7 no instance of `halt` is ready",
            "accept halt pending; t servo stop>pause::stop; accept halt pending; \
         t servo stop>ether; start t halt; t halt start>ether; start t halt; t halt start>ether",
            "accept halt pending; t servo stop>ether; t servo main>main => 8 no started instance",
        ],
    );
    // `mv` interrupts itself: a new instance waits for the old one
    // (to `stop`), and removes a waiting one; `halt` waits for nothing.
    check(
        &load(K),
        "m - start>ether; accept mv; start t mv; t mv start>run",
        &[
            "accept mv pending; accept mv pending; t mv stop>ether; start t mv; t mv start>run; \
         start t mv => 11 no instance of `mv` is ready",
            "accept halt; t mv stop>pause::stop; accept mv pending; t mv stop>ether; start t mv",
            "accept halt pending => 6 a call of `halt` is accepted with no outcome",
        ],
    );
}

#[test]
fn abort_and_kill_then_shutdown() {
    let c = load(H);
    check(
        &c,
        "m - start>ether; accept servo",
        &[
            "abort servo; start t servo => 5 ready",
            "start t servo; t servo start>main; abort servo main; abort servo stop => 7 no instance of `servo` is running",
            // GenoM3 runs a new instance's first codel in the sweep that starts it.
            "start t servo; abort servo start => 5 did not run its `start` codel at once",
        ],
    );
    // Both instances stop, then the permanent `stop` codel of `m` runs
    // (re-created: it had ended), then the component has stopped.
    check(
        &c,
        "m - start>ether; accept servo; start t servo; t servo start>pause::main; \
          abort servo main; accept servo; start t servo; t servo start>pause::main; accept kill",
        &[
            "accept servo => 11 the component is shutting down",
            "t servo stop>ether; t servo stop>exception; m - stop>ether",
            "t servo stop>ether; t servo stop>exception; m - stop>ether; \
         m - stop>ether => 14 the component has stopped",
        ],
    );
}
