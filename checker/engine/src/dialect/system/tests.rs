//! The explorer's fast paths of the untimed system against their plain
//! definitions, on generated components: successors computed into a reused
//! (dirty) buffer are the fresh ones, the field layout decodes what it
//! encodes, and the codels' conflict sets agree with the structure accesses.

#![allow(clippy::expect_used, clippy::unwrap_used)]

use genom_model::behaviour::Behaviour;
use genom_model::component::{CodelId, Component, ServiceId};

use super::locks::Who;
use super::{Config, System, conflict};
use crate::kernel::explore::{Limits, Model, explore};
use crate::testing::generated;

/// Generated components with watchdogs, self-stops, dense rules and
/// several threads.
fn components() -> Vec<Component> {
    let configs = [(3, 5, 3, 2, 2.0), (11, 4, 3, 2, 1.0), (6, 8, 4, 2, 1.0)];
    configs
        .iter()
        .map(|&config| generated(config, 0.3))
        .collect()
}

/// Every state reached (at most `cap`) of the whole component, post init.
fn states(sys: &System<'_>, cap: usize) -> Vec<Config> {
    let mut out = Vec::new();
    let limits = Limits {
        max_states: cap,
        ..Limits::default()
    };
    explore(sys, limits, |_, cfg| out.push(cfg.clone()));
    out
}

#[test]
fn successors_into_a_reused_buffer_are_the_fresh_ones() {
    for c in components() {
        let b = Behaviour::new(&c);
        let all: Vec<ServiceId> = c.services.ids().collect();
        let sys = System::new(&c, &b, &all, false);
        let reached = states(&sys, 3000);
        assert!(reached.len() > 10, "{} states", reached.len());
        // The buffer starts as a state with other contents.
        let mut buffer = Some(reached[reached.len() / 2].clone());
        let mut compared = 0;
        for cfg in &reached {
            let mut actions = Vec::new();
            sys.actions(cfg, &mut actions);
            for &a in &actions {
                let fresh = sys.apply(cfg, a, &mut None);
                let stepped = sys.step_into(cfg, a, &mut buffer);
                assert_eq!(stepped, fresh.is_some(), "{a:?}");
                if let Some(fresh) = fresh {
                    assert_eq!(buffer.as_ref(), Some(&fresh), "{a:?}");
                    compared += 1;
                }
            }
        }
        assert!(compared > 10);
    }
}

#[test]
fn the_layout_decodes_what_it_encodes_into_a_dirty_buffer() {
    for c in components() {
        let b = Behaviour::new(&c);
        let all: Vec<ServiceId> = c.services.ids().collect();
        let sys = System::new(&c, &b, &all, false);
        let reached = states(&sys, 3000);
        let mut buffer = Some(reached[0].clone());
        let mut seen = std::collections::BTreeSet::new();
        let (plain, packed) = sys.layout.field_by_field();
        assert!(packed, "each member's fields share a word");
        for cfg in &reached {
            let mut words = Vec::new();
            sys.encode(cfg, &mut words);
            assert_eq!(words.len(), sys.width());
            let mut by_field = Vec::new();
            plain.encode(cfg, &mut by_field);
            assert_eq!(words, by_field);
            sys.decode_into(&words, &(), &mut buffer);
            assert_eq!(buffer.as_ref(), Some(cfg));
            assert_eq!(&sys.decode(&words, &()), cfg);
            // Distinct states, distinct words.
            assert!(seen.insert(words));
        }
    }
}

#[test]
fn conflict_sets_agree_with_the_structure_accesses() {
    for c in components() {
        let b = Behaviour::new(&c);
        let all: Vec<ServiceId> = c.services.ids().collect();
        let sys = System::new(&c, &b, &all, false);
        let locks = sys.locks.as_ref().expect("few codels: sets are built");
        let codels: Vec<CodelId> = c.codels.ids().collect();
        let mut conflicts = 0;
        for &x in &codels {
            for &y in &codels {
                let expected = conflict(sys.codel_uses(x), sys.codel_uses(y));
                assert_eq!(locks.conflicts(Who::Codel(x), y), expected);
                conflicts += usize::from(expected);
            }
            for i in 0..sys.len() {
                let expected = conflict(sys.control_uses(i), sys.codel_uses(x));
                assert_eq!(locks.conflicts(Who::Control(i), x), expected);
            }
        }
        assert!(conflicts > 0, "some codels conflict");
    }
}
