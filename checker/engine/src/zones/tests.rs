//! Property tests of the DBM operations against a brute-force reference:
//! zones over two or three clocks represented as sets of points of a grid
//! inside a box, where every operation is computed exactly. With `n` clocks
//! and integer constants, every region has a point whose coordinates are
//! multiples of `1/(n+1)`, so that grid sees every non-empty zone.

use std::collections::BTreeSet;

use proptest::prelude::*;

use super::dbm::{Dbm, INF, le, lt};

/// The window compared, in whole units.
fn window(clocks: usize) -> i64 {
    if clocks == 2 { 3 } else { 2 }
}

/// The box the reference keeps points in, in whole units: much larger than
/// the window, so that points that leave the window and come back through a
/// reset are not lost.
fn big(clocks: usize) -> i64 {
    4 * window(clocks)
}

/// Grid steps per unit for `n` clocks.
fn steps(clocks: usize) -> i64 {
    i64::try_from(clocks).unwrap_or(3) + 1
}

type Point = Vec<i64>;

#[derive(Debug, Clone)]
enum Op {
    Up,
    Reset(usize),
    /// `xi - xj ≺ c` with `c` in whole units.
    Constrain(usize, usize, i64, bool),
}

fn op(clocks: usize) -> impl Strategy<Value = Op> {
    prop_oneof![
        Just(Op::Up),
        (1..=clocks).prop_map(Op::Reset),
        (0..=clocks, 0..=clocks, -3i64..=3, any::<bool>())
            .prop_filter("distinct clocks", |(i, j, _, _)| i != j)
            .prop_map(|(i, j, c, weak)| Op::Constrain(i, j, c, weak)),
    ]
}

/// The grid points of the window.
fn grid(clocks: usize) -> Vec<Point> {
    let max = window(clocks) * steps(clocks);
    let mut points = vec![Vec::new()];
    for _ in 0..clocks {
        points = points
            .into_iter()
            .flat_map(|p| (0..=max).map(move |v| [p.clone(), vec![v]].concat()))
            .collect();
    }
    points
}

fn value(p: &Point, i: usize) -> i64 {
    if i == 0 { 0 } else { p[i - 1] }
}

fn apply_set(set: &BTreeSet<Point>, op: &Op, k: i64, max: i64) -> BTreeSet<Point> {
    match *op {
        Op::Up => set
            .iter()
            .flat_map(|p| {
                (0..=max).filter_map(move |d| {
                    let q: Point = p.iter().map(|v| v + d).collect();
                    q.iter().all(|&v| v <= max).then_some(q)
                })
            })
            .collect(),
        Op::Reset(x) => set
            .iter()
            .map(|p| {
                let mut q = p.clone();
                q[x - 1] = 0;
                q
            })
            .collect(),
        Op::Constrain(i, j, c, weak) => set
            .iter()
            .filter(|p| {
                let diff = value(p, i) - value(p, j);
                if weak { diff <= k * c } else { diff < k * c }
            })
            .cloned()
            .collect(),
    }
}

fn apply_dbm(z: &mut Dbm, op: &Op) {
    match *op {
        Op::Up => z.up(),
        Op::Reset(x) => z.reset(x),
        Op::Constrain(i, j, c, weak) => {
            z.constrain(i, j, if weak { le(c) } else { lt(c) });
        }
    }
}

/// The DBM's points in the box, in grid steps.
fn members(z: &Dbm, clocks: usize) -> BTreeSet<Point> {
    grid(clocks)
        .into_iter()
        .filter(|p| z.contains(p, steps(clocks)))
        .collect()
}

/// The zone cut to the window.
fn boxed(z: &Dbm, clocks: usize) -> Dbm {
    let mut b = z.clone();
    for x in 1..=clocks {
        b.upper(x, window(clocks));
    }
    b
}

/// The reference points inside the window.
fn in_window(set: &BTreeSet<Point>, clocks: usize) -> BTreeSet<Point> {
    let max = window(clocks) * steps(clocks);
    set.iter()
        .filter(|p| p.iter().all(|&v| v <= max))
        .cloned()
        .collect()
}

fn run(clocks: usize, ops: &[Op]) -> (Dbm, BTreeSet<Point>) {
    let mut z = Dbm::zero(clocks);
    let mut set: BTreeSet<Point> = [vec![0; clocks]].into_iter().collect();
    for o in ops {
        apply_dbm(&mut z, o);
        set = apply_set(&set, o, steps(clocks), big(clocks) * steps(clocks));
        if set.is_empty() {
            break;
        }
    }
    (z, in_window(&set, clocks))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn operations_match_the_brute_force_reference(
        clocks in 2usize..=3,
        ops in prop::collection::vec(op(3), 0..8),
    ) {
        let ops: Vec<Op> = ops.into_iter().filter(|o| match o {
            Op::Reset(x) => *x <= clocks,
            Op::Constrain(i, j, _, _) => *i <= clocks && *j <= clocks,
            Op::Up => true,
        }).collect();
        let (z, set) = run(clocks, &ops);
        let integer = set.iter().any(|q| q.iter().all(|v| v % steps(clocks) == 0));
        let mut inside = boxed(&z, clocks);
        let nonempty = inside.canonicalize();
        prop_assert_eq!(nonempty, !set.is_empty(), "emptiness differs for {:?}\n{:?}", ops, z);
        prop_assert_eq!(members(&z, clocks), set, "points differ for {:?}", ops);
        let mut canon = z.clone();
        if canon.canonicalize() {
            // Canonical form keeps the same points.
            prop_assert_eq!(members(&canon, clocks), members(&z, clocks));
            // A picked point is in the zone.
            let (p, scale) = canon.pick().expect("non-empty zone has a point");
            prop_assert!(canon.contains(&p, scale), "picked {:?}/{} outside\n{:?}", p, scale, canon);
            // An integer point whenever the zone (in the window) has one.
            if integer {
                prop_assert_eq!(scale, 1, "an integer point exists in\n{:?}", canon);
            }
        }
    }

    #[test]
    fn inclusion_matches_subset(
        a in prop::collection::vec(op(2), 0..8),
        b in prop::collection::vec(op(2), 0..8),
    ) {
        let (za, sa) = run(2, &a);
        let (zb, sb) = run(2, &b);
        let (mut za, mut zb) = (boxed(&za, 2), boxed(&zb, 2));
        if za.canonicalize() && zb.canonicalize() {
            // Within the box, DBM inclusion is exactly point-set inclusion.
            prop_assert_eq!(za.included_in(&zb), sa.is_subset(&sb), "{:?}\n{:?}", za, zb);
        }
    }

    #[test]
    fn extrapolation_only_grows_and_keeps_small_zones(
        ops in prop::collection::vec(op(2), 0..10),
        l in prop::collection::vec(prop::option::of(0i64..4), 2),
        u in prop::collection::vec(prop::option::of(0i64..4), 2),
    ) {
        let (mut z, _) = run(2, &ops);
        if z.canonicalize() {
            let mut x = z.clone();
            x.extrapolate(&l, &u);
            prop_assert!(z.included_in(&x), "extrapolation lost points:\n{:?}\n{:?}", z, x);
            // With bounds above every constant, nothing changes.
            let mut same = z.clone();
            same.extrapolate(&[Some(100), Some(100)], &[Some(100), Some(100)]);
            prop_assert_eq!(same, z);
        }
    }
}

#[test]
fn delay_reset_and_guards_on_a_worked_example() {
    // x, y start at 0; let time pass; x ≤ 3; reset y; let time pass; y ≥ 2.
    let mut z = Dbm::zero(2);
    z.up();
    assert!(z.upper(1, 3));
    z.reset(2);
    z.up();
    assert!(z.lower(2, 2));
    // Then x - y ≤ 3 and x ≥ 2.
    assert_eq!(z.get(1, 2), le(3));
    assert_eq!(z.get(0, 1), le(-2));
    assert_eq!(z.get(1, 0), INF);
    assert!(!z.clone().constrain(1, 0, lt(2)));
}

#[test]
fn freeing_a_clock_forgets_its_relations() {
    let mut z = Dbm::zero(2);
    z.up();
    assert!(z.upper(1, 5));
    z.free(2);
    assert_eq!(z.get(1, 2), le(5));
    assert_eq!(z.get(2, 1), INF);
    assert_eq!(z.get(0, 2), le(0));
}

#[test]
fn a_strict_lower_bound_picks_the_next_integer() {
    // x > 11999999 (a deadline passed), y = x: the lowest integer point is
    // 12000000, not a fraction just above the deadline.
    let mut z = Dbm::zero(2);
    z.up();
    assert!(z.constrain(0, 1, lt(-11_999_999)));
    assert_eq!(z.pick(), Some((vec![12_000_000, 12_000_000], 1)));
    assert_eq!(z.pick_integer(), Some(vec![12_000_000, 12_000_000]));
}

#[test]
fn a_zone_without_integer_point_picks_a_fraction() {
    // 0 < x < 1 and y = x: no integer point; a point of the finer grid.
    let mut z = Dbm::zero(2);
    z.up();
    assert!(z.constrain(0, 1, lt(0)));
    assert!(z.constrain(1, 0, lt(1)));
    assert_eq!(z.pick_integer(), None);
    let (p, scale) = z.pick().expect("not empty");
    assert!(scale > 1);
    assert!(z.contains(&p, scale));
    assert!(p[0] > 0 && p[0] < scale, "{p:?}/{scale}");
}
