//! A random generator of valid component descriptions, for benchmarks,
//! property tests and differential testing of the engines.
//!
//! [`generate`] turns a [`GeneratorConfig`] into the *text* of a `.gen`
//! file that parses, resolves and passes every static check without an
//! error or a warning (advice may remain, e.g. `missing-on-inter` for a
//! one-codel interruptible service). Behavioural verdicts (starvation,
//! dead services, ...) are not excluded: finding them is the engine's job.
//!
//! The output depends on the configuration only: the random numbers come
//! from a splitmix64 generator written here (no `rand`, no hashing, no
//! floating-point function other than `+ - * /` and comparisons), so a
//! seed gives the same component on every platform and with every version
//! of the dependencies.
//!
//! What a component holds:
//!
//! - `ids` blocks (`d0`, `d1`, ...) whose members cycle through `double`,
//!   `long` and `boolean`, and an `export` block of `double` items;
//! - threads `t0`, `t1`, ... (periodic, with random periods; when not
//!   `timed`, some are aperiodic);
//! - services `S00`, `S01`, ...: first the `init` service if asked, then
//!   the `auto` services, then ordinary ones, some of which may be
//!   attribute setters (control codel only, no thread);
//! - `stops`/`delays`/`forbids`: every ordered pair of services (a service
//!   and itself included, for `stops` only) gets a rule with probability
//!   `rule_density / services`, so each service lists `rule_density`
//!   references on average; half are `stops`, a quarter `delays`, a quarter
//!   `forbids`. Unless [`GeneratorConfig::auto_rules`] is set, an `auto`
//!   service only lists `stops` (an `auto` instance never ends, so its
//!   `delays` or `forbids` would make their targets dead);
//! - codels: a threaded service has `codels_per_service` start, exec and
//!   inter codels. Inter codels exist only when something can interrupt the
//!   service (a `stops` naming it, or its own `max-time`); then every start
//!   and exec codel has an `on-inter`. The `next` graph of the start and
//!   exec codels is a random tree rooted at `start` (so every codel is
//!   reachable) plus random back edges (loops) and forward edges; in a
//!   non-`auto` service every leaf of the tree has an exit outcome (`end`
//!   or a report) and the first leaf has `end`, so every codel can end the
//!   service and the `init` service can succeed; in an `auto` service every
//!   leaf loops back instead and no outcome ends it. Inter codels form a
//!   forward-only tree (no loop, so interrupts are bounded) that ends;
//! - codel functions: a pool of functions whose prototypes are fixed at
//!   their first use; a later codel may call the same function again with
//!   other data of the same types and the same `const` flags. Arguments are
//!   `ids` members, export items and the service's own parameters;
//!   non-`const` `ids`/export arguments may be listed in `update`;
//! - with `timed`: every thread is periodic, every codel has a WCET
//!   (`max-time`) well below its thread's period divided among the services
//!   of the thread, and about half of the services have a generous
//!   `max-time` (several periods per codel).
//!
//! # GenoM3 components
//!
//! [`generate_genom3`] turns a [`Genom3Config`] into a [`Genom3Component`]:
//! the text of a GenoM3 `.gen` file (`r#gen`: `gen` is a reserved word of
//! Rust 2024) and, when `timed`, its WCET side file (`wcet`, the
//! `OWNER.STATE DURATION` lines of docs/genom3.md). The text is
//! self-contained (no `#include`) and loads with genom-check's GenoM3
//! front-end without an error or a warning (the model checks that follow
//! may warn `no-termination` for an endless activity); `genom3 -n` (2.99.39 and
//! 2.99.41) accepts it too. [`Genom3Config::small`] derives a small
//! configuration from a seed. A component `rnd` holds:
//!
//! - two exceptions (`e_fail`, `e_busy { long code; }`), the structs
//!   `g_pose` and `g_cmd` (which nests a `g_pose`), `ids` members `m0`,
//!   `m1`, ... (2 to 4 of `long`, `double`, `g_pose`, `g_cmd`) and, with
//!   `ports`, `port out g_pose p_out` (sometimes `port in g_pose p_in`);
//! - tasks `t0`, `t1`, ...: periodic (10, 20 or 50 ms, sometimes a
//!   `delay`) when `timed`, else each with probability 0.7; with
//!   `permanent`, `t0` and each other task with probability 1/2 have a
//!   permanent state machine (most never reach `ether` by themselves, most
//!   have a `stop` codel run at `kill`);
//! - activities `a0`, ... on random tasks, with `in`/`out` parameters
//!   (sometimes defaults), sometimes a `validate` codel and a `throw`;
//!   their state machine has `start` and `states - 1` other states (`main`,
//!   `wait`, `run`, ...) linked by a random tree of yields from `start`
//!   plus extra yields, `pause::` with probability `pauses` forward and
//!   always backward (unless `unpaused_cycles`, which gives `livelock` or
//!   `unpaused-loop`); the tree's leaves yield `ether` except in *endless*
//!   machines (1 in 7), which only end by `stop`, exception or `kill`; half
//!   have a `stop` codel (`yield [pause::stop,] ether`); states whose
//!   yields are all paused sometimes share a codel (`codel<main, wait>`);
//!   with `asyncs`, one codel in four (not `start` or `stop`) is `async`
//!   and takes no ids parameter (genom3 rejects `async` codels sharing ids
//!   data);
//! - functions `f0`, ... (typed parameters, sometimes `validate`, zero to
//!   two codels, `throws`) and attributes `attr0`, ... (one or two ids
//!   paths set with `in`, sometimes with a default, or read with `out`;
//!   sometimes a `validate` reading the new values as `local in NAME`);
//! - `interrupts`/`after`/`before`: each ordered pair of services gets a
//!   reference with probability `density / services` (half `interrupts`,
//!   which may name the service itself, a quarter each `after` and
//!   `before`), and now and then `interrupts all`; `after` an endless
//!   activity, or `after` cycles, give `dead-service`;
//! - codel parameters: 0 to 2 per codel among ids paths (whole members or
//!   nested members such as `m3.target.x`, `in`/`out`/`inout`, sometimes
//!   `ids`-qualified, rarely `::ids`), the service's parameters (sometimes
//!   `local`) and ports, with distinct names (genom3 names a parameter
//!   after its path's last component), so that codels of different tasks
//!   and the control thread contend for GenoM3's locks;
//! - with `timed`, the WCET file gives every activity state, permanent
//!   codel, `validate` and function codel a WCET: with `load` at most 1
//!   they sum to `load` times the shortest period (0.3 in `small`: no
//!   task overruns); above 1 each task's codels sum to about `load` times
//!   its period, each below it, so wake-ups that run several codels give
//!   `thread-overrun`.
//!
//! Every codel function is named `rnd_OWNER_STATE` (one prototype each),
//! service parameters `a_*`/`f_*`, ids members `m*` and ports `p_*`, so no
//! name is found in two sources (genom3's `missing-source`).
//!
//! For property tests, [`strategy`] (only under `#[cfg(test)]`, since
//! proptest is a dev-dependency of this crate) yields configurations of
//! small components; outside this crate's tests, [`GeneratorConfig::small`]
//! derives such a configuration from a single seed, which any proptest
//! `any::<u64>()` can feed.

mod config;
mod generator;
pub mod genom3;
mod plan;
mod rng;

pub use config::GeneratorConfig;
pub use genom3::{Genom3Component, Genom3Config, generate_genom3};
pub use rng::SplitMix;

/// Generates the text of a component. Deterministic: the same
/// configuration always gives the same text.
pub fn generate(config: &GeneratorConfig) -> String {
    generator::Generator::new(config).run()
}

/// Configurations of small components for property tests: 1–6 services,
/// 1–4 codels, 1–3 threads, density 0–3, and every option at random.
/// Only in this crate's tests (proptest is a dev-dependency); elsewhere use
/// `any::<u64>().prop_map(GeneratorConfig::small)`.
#[cfg(test)]
pub fn strategy() -> impl proptest::strategy::Strategy<Value = GeneratorConfig> {
    use proptest::prelude::*;
    (
        any::<u64>(),
        1usize..=6,
        1usize..=4,
        1usize..=3,
        0u32..=12,
        any::<bool>(),
        0usize..=2,
        any::<bool>(),
        prop::bool::weighted(0.2),
        prop_oneof![Just(0.0), Just(0.3)],
        prop_oneof![Just(0.0), Just(0.3), Just(0.6)],
        (0usize..=2, 0usize..=2, prop_oneof![Just(0.0), Just(0.5)]),
    )
        .prop_map(
            |(
                seed,
                services,
                codels,
                threads,
                quarter,
                init,
                autos,
                timed,
                auto_rules,
                setters,
                loops,
                (ids, exports, self_stops),
            )| {
                GeneratorConfig {
                    seed,
                    services,
                    codels_per_service: codels,
                    threads,
                    rule_density: f64::from(quarter) / 4.0,
                    init,
                    autos,
                    timed,
                    auto_rules,
                    setters,
                    loops,
                    ids_blocks: ids,
                    exports,
                    self_stops,
                }
            },
        )
}

#[cfg(test)]
mod tests {
    use std::path::Path;
    use std::time::{Duration, Instant};

    use gen_frontend::{GenFrontend, MemoryLoader};
    use genom_checker::{CheckOptions, Checked};
    use genom_model::Severity;
    use genom_model::frontend::{Frontend as _, Input};
    use proptest::prelude::*;

    use super::*;

    /// The whole check of `text` (the front-end, then the checker), as the
    /// product runs it.
    fn check(text: &str, behaviour: bool) -> Checked {
        let options = CheckOptions::new()
            .behaviour(behaviour)
            .max_states(20_000)
            .timeout(Some(Duration::from_secs(2)));
        let started = Instant::now();
        let loader = MemoryLoader::new();
        let input = Input {
            watch: options.watch(started),
            ..Input::new(Path::new("gen.gen"), &loader)
        };
        let loaded = GenFrontend
            .load(input, text.to_owned())
            .unwrap_or_else(|e| panic!("{e:?}"));
        genom_checker::check(loaded, &options, started)
    }

    /// Errors and warnings of the static checks, rendered for a failure
    /// message (empty when clean).
    fn problems(text: &str) -> String {
        let result = check(text, false);
        assert!(result.component.is_some(), "no component:\n{text}");
        result
            .diagnostics
            .iter()
            .filter(|d| d.severity >= Severity::Warning)
            .map(|d| format!("{:?} {}\n", d.code, d.message))
            .collect()
    }

    fn assert_clean(cfg: &GeneratorConfig) {
        let text = generate(cfg);
        let p = problems(&text);
        assert!(p.is_empty(), "{cfg:?}\n{p}\n{text}");
    }

    #[test]
    fn small_components_of_200_seeds_check_clean() {
        for seed in 0..200 {
            assert_clean(&GeneratorConfig::small(seed));
        }
    }

    #[test]
    fn benchmark_sizes_check_clean() {
        for seed in 0..10 {
            for (services, codels, threads, density) in [
                (5, 3, 1, 1.0),
                (10, 5, 2, 1.0),
                (30, 5, 4, 1.0),
                (30, 5, 4, 3.0),
                (40, 8, 6, 0.5),
            ] {
                let mut cfg = GeneratorConfig::new(seed, services);
                (cfg.codels_per_service, cfg.threads, cfg.rule_density) =
                    (codels, threads, density);
                (cfg.init, cfg.autos, cfg.timed, cfg.setters) =
                    (seed % 2 == 0, usize::from(seed % 3 == 0), seed % 4 < 2, 0.1);
                assert_clean(&cfg);
            }
        }
    }

    #[test]
    fn generation_is_deterministic() {
        for seed in [0, 1, 42, u64::MAX] {
            let mut cfg = GeneratorConfig::small(seed);
            assert_eq!(generate(&cfg), generate(&cfg.clone()));
            cfg.services = 12;
            assert_eq!(generate(&cfg), generate(&cfg));
        }
        assert_ne!(
            generate(&GeneratorConfig::new(1, 5)),
            generate(&GeneratorConfig::new(2, 5))
        );
    }

    /// The generator's output is fixed by its definition: this digest
    /// changes only when the generator itself changes.
    #[test]
    fn output_is_stable() {
        let mut cfg = GeneratorConfig::new(7, 4);
        (cfg.init, cfg.autos, cfg.timed) = (true, 1, true);
        let text = generate(&cfg);
        let digest = text.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
        });
        assert_eq!(digest, STABLE_DIGEST, "{text}");
    }

    const STABLE_DIGEST: u64 = 12_496_380_282_404_570_434;

    #[test]
    fn the_prng_is_splitmix64() {
        // Reference values of splitmix64 seeded with 1234567.
        let mut r = SplitMix::new(1_234_567);
        assert_eq!(r.next_u64(), 6_457_827_717_110_365_317);
        assert_eq!(r.next_u64(), 3_203_168_211_198_807_973);
    }

    #[test]
    fn the_requested_structure_is_there() {
        let mut cfg = GeneratorConfig::new(3, 8);
        (cfg.init, cfg.autos, cfg.threads, cfg.codels_per_service) = (true, 2, 3, 4);
        let result = check(&generate(&cfg), false);
        let c = result.component.expect("a component");
        assert_eq!(c.services.len(), 8);
        assert_eq!(c.threads.len(), 3);
        assert!(c.init_service().is_some());
        let autos = c
            .services
            .values()
            .filter(|s| s.kind == genom_model::kinds::ServiceKind::Auto)
            .count();
        assert_eq!(autos, 2);
        for s in c.services.values() {
            let threaded = s
                .codels
                .iter()
                .filter(|&&k| c.codels[k].kind != genom_model::kinds::CodelKind::Control);
            assert_eq!(threaded.count(), 4, "{}", s.name.name);
        }
    }

    #[test]
    fn timed_components_have_wcets_below_the_period() {
        for seed in 0..20 {
            let mut cfg = GeneratorConfig::new(seed, 10);
            (cfg.timed, cfg.threads, cfg.codels_per_service) = (true, 3, 4);
            let c = check(&generate(&cfg), false)
                .component
                .expect("a component");
            for s in c.services.values() {
                let Some(t) = s.thread else { continue };
                let period = c.threads[t.id].period.map(|p| p.ns).expect("periodic");
                for &k in &s.codels {
                    let wcet = c.codels[k].wcet.map(|m| m.ns).expect("a WCET");
                    assert!(wcet <= period, "{} {wcet} > {period}", s.name.name);
                }
            }
        }
    }

    /// The engine runs on generated components without panicking.
    #[test]
    fn the_engine_runs_on_small_components() {
        for seed in 0..40 {
            let result = check(&generate(&GeneratorConfig::small(seed)), true);
            assert!(result.statistics.is_some(), "seed {seed}");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn generated_components_check_clean(cfg in strategy()) {
            let text = generate(&cfg);
            prop_assert_eq!(problems(&text), "");
        }
    }
}
