//! The Petri-net cross-check (see `petri_cross_check.rs`) on components of
//! the random generator (`genom_generate`), whose space
//! (up to six services, three threads, init, autos, setters, dense rules)
//! is wider than the small generator of the main cross-check.

use crate::petri_common;

use genom_generate::{GeneratorConfig, generate};
use petri_common::{cross_check, parse};

#[test]
fn components_of_the_crate_generator_agree() {
    let (mut checked, mut too_large, mut configs) = (0, 0, 0usize);
    for seed in 0..100u64 {
        let src = generate(&GeneratorConfig::small(seed));
        let c = parse(&src).unwrap_or_else(|e| panic!("seed {seed}: static errors {e:?}\n{src}"));
        match cross_check(&format!("generator seed {seed}"), &c, 4_000) {
            Some(sizes) => {
                checked += 1;
                configs += sizes.configs;
            }
            None => too_large += 1,
        }
    }
    println!(
        "crate generator: {checked} compared ({configs} configurations), {too_large} too large"
    );
    assert!(checked >= 70, "only {checked} components compared");
}
