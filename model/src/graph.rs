//! The heaviest path of a small directed graph whose nodes weigh something
//! (a codel's WCET): what a chain of codels can take at most, read by the
//! GenoM3 engine's static bound on a task's wake-up and by a service's own
//! time in the response-time report. A cycle has no heaviest path.

use petgraph::algo::toposort;
use petgraph::graph::{DiGraph, NodeIndex};

/// The heaviest path that starts at one of `roots`, over nodes `0..n` with
/// successors `next`, a path weighing the sum of its nodes' `cost`s
/// (saturating). Only the nodes reachable from `roots` count: `None` when
/// one of them is on a cycle or has no cost. `Some(0)` without roots.
pub fn heaviest_path<I: IntoIterator<Item = usize>>(
    n: usize,
    roots: impl IntoIterator<Item = usize>,
    next: impl Fn(usize) -> I,
    cost: impl Fn(usize) -> Option<u64>,
) -> Option<u64> {
    let roots: Vec<usize> = roots.into_iter().collect();
    // The nodes reachable from the roots, as nodes of a graph of their own.
    let mut g = DiGraph::<usize, ()>::new();
    let mut node: Vec<Option<NodeIndex>> = vec![None; n];
    let mut todo = roots.clone();
    while let Some(s) = todo.pop() {
        if node[s].is_none() {
            node[s] = Some(g.add_node(s));
            todo.extend(next(s));
        }
    }
    for v in g.node_indices().collect::<Vec<_>>() {
        for t in next(g[v]) {
            if let Some(w) = node[t] {
                g.add_edge(v, w, ());
            }
        }
    }
    let order = toposort(&g, None).ok()?;
    let mut best = vec![0u64; g.node_count()];
    for v in order.into_iter().rev() {
        let after = g.neighbors(v).map(|w| best[w.index()]).max().unwrap_or(0);
        best[v.index()] = cost(g[v])?.saturating_add(after);
    }
    Some(
        roots
            .iter()
            .filter_map(|&r| node[r].map(|v| best[v.index()]))
            .max()
            .unwrap_or(0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn edges(e: &'static [(usize, usize)]) -> impl Fn(usize) -> Vec<usize> {
        move |s| e.iter().filter(|x| x.0 == s).map(|x| x.1).collect()
    }

    #[test]
    fn the_heaviest_branch_of_a_diamond_wins() {
        // 0 -> 1 -> 3, 0 -> 2 -> 3: 1 + 5 + 4 against 1 + 2 + 4.
        let next = edges(&[(0, 1), (0, 2), (1, 3), (2, 3)]);
        let cost = |k: usize| Some([1, 5, 2, 4][k]);
        assert_eq!(heaviest_path(4, [0], &next, cost), Some(10));
        assert_eq!(heaviest_path(4, [2], &next, cost), Some(6));
        assert_eq!(heaviest_path(4, [], &next, cost), Some(0));
    }

    #[test]
    fn a_reachable_cycle_or_missing_cost_has_none_an_unreachable_one_does_not_count() {
        let next = edges(&[(0, 1), (2, 3), (3, 2), (4, 4)]);
        let cost = |k: usize| if k == 5 { None } else { Some(1) };
        assert_eq!(heaviest_path(6, [0], &next, cost), Some(2));
        assert_eq!(heaviest_path(6, [0, 2], &next, cost), None);
        assert_eq!(heaviest_path(6, [4], &next, cost), None, "a self-loop");
        assert_eq!(heaviest_path(6, [5], &next, cost), None);
    }

    #[test]
    fn a_long_ladder_is_linear_not_exponential() {
        // 2 × 40 nodes, each rung reaching both of the next: 2^40 paths.
        let n = 80;
        let next = |s: usize| {
            if s + 2 < n {
                vec![s + 2 - s % 2, s + 3 - s % 2]
            } else {
                vec![]
            }
        };
        assert_eq!(heaviest_path(n, [0], next, |_| Some(1)), Some(40));
    }
}
