//! What to generate: [`GeneratorConfig`] and its presets.

use crate::rng::SplitMix;

/// What to generate. Build with [`GeneratorConfig::new`] and adjust the
/// public fields.
#[derive(Debug, Clone, PartialEq)]
pub struct GeneratorConfig {
    /// The seed of the random choices.
    pub seed: u64,
    /// Number of services, `init`, `auto` and attribute setters included
    /// (at least 1).
    pub services: usize,
    /// Start, exec and inter codels of each threaded service (at least 1;
    /// an `auto` service gets at least 2 so that it can loop).
    pub codels_per_service: usize,
    /// Number of threads (at least 1).
    pub threads: usize,
    /// Expected number of `stops` + `delays` + `forbids` references listed
    /// by each service.
    pub rule_density: f64,
    /// Make the first service an `init` service.
    pub init: bool,
    /// Number of `auto` services (after the init service).
    pub autos: usize,
    /// Thread periods, codel WCETs and service `max-time`s.
    pub timed: bool,
    /// Let `auto` services list `delays` and `forbids` too (their targets
    /// may then be dead).
    pub auto_rules: bool,
    /// Probability that an ordinary service is an attribute setter
    /// (control codel only, no thread).
    pub setters: f64,
    /// Probability that a start or exec codel gets an extra back edge (a
    /// loop) in its `next`.
    pub loops: f64,
    /// Number of `ids` blocks (0: one per five services).
    pub ids_blocks: usize,
    /// Number of export items (0: none).
    pub exports: usize,
    /// Probability that an ordinary or `init` service also lists itself in
    /// `stops` (a new request replaces the running one, as in most motion
    /// services), on top of `rule_density`.
    pub self_stops: f64,
}

impl GeneratorConfig {
    /// `services` ordinary services of 3 codels on 1 thread, about one rule
    /// reference per service, untimed, no init, no autos.
    pub fn new(seed: u64, services: usize) -> Self {
        GeneratorConfig {
            seed,
            services,
            codels_per_service: 3,
            threads: 1,
            rule_density: 1.0,
            init: false,
            autos: 0,
            timed: false,
            auto_rules: false,
            setters: 0.0,
            loops: 0.3,
            ids_blocks: 0,
            exports: 1,
            self_stops: 0.0,
        }
    }

    /// A random small configuration derived from `seed` alone (1–6
    /// services, 1–4 codels, 1–3 threads, density 0–3, init, autos,
    /// setters, self-stops and timing at random): the same space as [`strategy`], for
    /// users outside this crate's tests.
    pub fn small(seed: u64) -> Self {
        let mut r = SplitMix::new(seed ^ 0x5EED_5EED_5EED_5EED);
        GeneratorConfig {
            seed,
            services: 1 + r.below(6),
            codels_per_service: 1 + r.below(4),
            threads: 1 + r.below(3),
            #[allow(clippy::cast_precision_loss)]
            rule_density: r.below(13) as f64 / 4.0,
            init: r.chance(0.5),
            autos: r.below(3),
            timed: r.chance(0.5),
            auto_rules: r.chance(0.2),
            setters: if r.chance(0.5) { 0.3 } else { 0.0 },
            loops: if r.chance(0.5) { 0.3 } else { 0.0 },
            ids_blocks: r.below(3),
            exports: r.below(3),
            self_stops: if r.chance(0.5) { 0.5 } else { 0.0 },
        }
    }
}
