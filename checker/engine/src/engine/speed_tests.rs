//! The analysis's fast paths against their plain definitions: the
//! bit-mask search for a cycle of pending instances finds what the general
//! one finds, on every reached state of generated components.

#![allow(clippy::expect_used, clippy::unwrap_used)]

use genom_generate::{GeneratorConfig, generate};
use genom_model::behaviour::Behaviour;
use genom_model::component::ServiceId;

use super::explore::{Limits, explore};
use super::pending::{pending_cycle_any, pending_cycle_small};
use super::system::System;
use crate::testing::check;

#[test]
fn the_bit_mask_cycle_search_agrees_with_the_general_one() {
    let mut cycles = 0;
    let mut compared = 0;
    for seed in 1..=12 {
        let text = generate(&GeneratorConfig {
            codels_per_service: 2,
            threads: 2,
            rule_density: 3.0,
            init: true,
            autos: 1,
            ..GeneratorConfig::new(seed, 6)
        });
        let c = check(&text).component.expect("a generated component");
        let b = Behaviour::new(&c);
        let all: Vec<ServiceId> = c.services.ids().collect();
        let sys = System::new(&c, &b, &all, false);
        let limits = Limits {
            max_states: 20_000,
            ..Limits::default()
        };
        explore(&sys, limits, |_, cfg| {
            let small = pending_cycle_small(&sys, cfg);
            assert_eq!(small, pending_cycle_any(&sys, cfg));
            cycles += usize::from(small.is_some());
            compared += 1;
        });
    }
    assert!(compared > 1000, "{compared} states");
    assert!(cycles > 0, "some state has a cycle of pending instances");
}
