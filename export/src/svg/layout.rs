//! A small layered ("Sugiyama-style") layout for the `svg` export, written
//! for its pictures: a few dozen nodes at most, boxes of different sizes,
//! edge labels, self-loops and, for the overview, clusters.
//!
//! The steps, all deterministic (ties are broken by input order):
//!
//! 1. **Cycles** are broken by reversing the back edges of a depth-first
//!    search from the nodes in input order (self-loops are set aside and
//!    drawn as loops on the right side of their node);
//! 2. **Layers**: each node goes to the layer of its longest path from a
//!    source; an edge spanning several layers gets one *dummy* node per
//!    layer crossed, so that no edge goes through a node;
//! 3. **Order** in each layer: a few barycentre sweeps, down then up,
//!    keeping the order with the fewest crossings; nodes stay grouped by
//!    cluster, clusters in input order;
//! 4. **Coordinates**: in each cluster, each node is pulled towards the
//!    mean of its neighbours in the previous (then next) layer while nodes
//!    keep a fixed spacing (the positions minimising the squared distances,
//!    computed by merging blocks); clusters are then put side by side, as
//!    columns under a header row, so a cluster's rectangle holds exactly
//!    its nodes. Layers are stacked with a fixed gap, larger where an edge
//!    label sits;
//! 5. **Routes**: each edge leaves the bottom of its upper node and enters
//!    the top of its lower node (ports spread along the side), crosses each
//!    gap between layers with a cubic curve and each layer it passes by a
//!    straight line through its dummy's slot; its label sits in the first
//!    gap it crosses, where there is no node.
//!
//! The layout never fails and never panics on any graph.

use super::geometry::{Input, Layout, Point, Rect, Route, Vertex};
use super::route::{Geometry, free_spot, loop_room, loop_route, ports};

/// Horizontal space between two nodes of a layer.
const NODE_GAP: f64 = 28.0;
/// Vertical space between two layers.
const LAYER_GAP: f64 = 40.0;
/// The extra vertical space of a gap holding edge labels.
const LABEL_GAP: f64 = 16.0;
/// The width of a dummy node (an edge crossing a layer).
const DUMMY: f64 = 12.0;
/// Space between a cluster's border and its contents.
pub(crate) const CLUSTER_PAD: f64 = 10.0;
/// Space between two clusters.
const CLUSTER_GAP: f64 = 16.0;
/// Barycentre sweeps and coordinate passes.
const SWEEPS: usize = 8;
const PASSES: usize = 8;

/// Lays a graph out.
pub(crate) fn layout(input: &Input) -> Layout {
    let n = input.nodes.len();
    let clustered = !input.clusters.is_empty();
    let cluster_of = |v: usize| {
        if clustered {
            input.nodes[v].cluster.min(input.clusters.len() - 1)
        } else {
            0
        }
    };
    let loops = self_loops(input);
    // 1. Cycles.
    let reversed = back_edges(input);
    let oriented = |e: usize| {
        let edge = input.edges[e];
        if reversed[e] {
            (edge.to, edge.from)
        } else {
            (edge.from, edge.to)
        }
    };
    let proper: Vec<usize> = (0..input.edges.len())
        .filter(|&e| input.edges[e].from != input.edges[e].to)
        .filter(|&e| input.edges[e].from < n && input.edges[e].to < n)
        .collect();
    // 2. Layers and dummies.
    let layer_of = longest_paths(n, proper.iter().map(|&e| oriented(e)));
    let mut vertices: Vec<Vertex> = (0..n)
        .map(|v| Vertex {
            width: input.nodes[v].width + loop_room(&loops[v]),
            cluster: cluster_of(v),
            layer: layer_of[v],
            x: 0.0,
        })
        .collect();
    // For each edge, its chain of vertices from upper to lower.
    let mut chains: Vec<Vec<usize>> = vec![Vec::new(); input.edges.len()];
    for &e in &proper {
        let (u, v) = oriented(e);
        let mut chain = vec![u];
        for layer in layer_of[u] + 1..layer_of[v] {
            chain.push(vertices.len());
            vertices.push(Vertex {
                width: DUMMY,
                cluster: cluster_of(u),
                layer,
                x: 0.0,
            });
        }
        chain.push(v);
        chains[e] = chain;
    }
    let layers_n = vertices.iter().map(|v| v.layer + 1).max().unwrap_or(0);
    // Segments between consecutive layers: (upper, lower).
    let segments: Vec<(usize, usize)> = chains
        .iter()
        .flat_map(|c| c.windows(2).map(|w| (w[0], w[1])))
        .collect();
    // 3. Order.
    let mut layers: Vec<Vec<usize>> = vec![Vec::new(); layers_n];
    for (k, v) in vertices.iter().enumerate() {
        layers[v.layer].push(k);
    }
    for layer in &mut layers {
        layer.sort_by_key(|&k| vertices[k].cluster);
    }
    order(&mut layers, &vertices, &segments);
    // 4. Coordinates.
    let n_clusters = input.clusters.len().max(1);
    let mut band_x = vec![0.0; n_clusters];
    let mut band_w = vec![0.0; n_clusters];
    let mut x = if clustered { CLUSTER_PAD } else { 0.0 };
    for c in 0..n_clusters {
        let header = input.clusters.get(c).map_or(0.0, |h| h.header_width);
        let width = place_cluster(c, &layers, &mut vertices, &segments);
        let shift = ((header - width) / 2.0).max(0.0);
        for v in vertices.iter_mut().filter(|v| v.cluster == c) {
            v.x += x + shift;
        }
        band_x[c] = x;
        band_w[c] = width.max(header);
        x += band_w[c] + 2.0 * CLUSTER_PAD + CLUSTER_GAP;
    }
    let header = input
        .clusters
        .iter()
        .map(|c| c.header_height)
        .fold(0.0, f64::max);
    let mut top = vec![0.0; layers_n];
    let mut height = vec![0.0_f64; layers_n];
    for v in 0..n {
        height[layer_of[v]] = height[layer_of[v]].max(input.nodes[v].height);
    }
    let mut labelled = vec![false; layers_n];
    for (e, chain) in chains.iter().enumerate() {
        if input.edges[e].label.is_some() {
            if let Some(&u) = chain.first() {
                labelled[vertices[u].layer] = true;
            }
        }
    }
    let mut y = if clustered {
        2.0 * CLUSTER_PAD + header
    } else {
        0.0
    };
    for l in 0..layers_n {
        top[l] = y;
        y += height[l] + LAYER_GAP + if labelled[l] { LABEL_GAP } else { 0.0 };
    }
    let bottom = y - LAYER_GAP;
    let nodes: Vec<Rect> = (0..n)
        .map(|v| {
            let node = input.nodes[v];
            let l = layer_of[v];
            Rect {
                x: vertices[v].x - vertices[v].width / 2.0,
                y: top[l] + (height[l] - node.height) / 2.0,
                w: node.width,
                h: node.height,
            }
        })
        .collect();
    // 5. Routes.
    let geometry = Geometry {
        input,
        vertices: &vertices,
        nodes: &nodes,
        top: &top,
        height: &height,
        ports: ports(&vertices, &segments),
        first: chains
            .iter()
            .scan(0, |acc, c| {
                let first = *acc;
                *acc += c.len().saturating_sub(1);
                Some(first)
            })
            .collect(),
    };
    let mut edges: Vec<Route> = Vec::with_capacity(input.edges.len());
    let mut loop_rank = vec![0; n];
    let mut placed: Vec<Rect> = Vec::new();
    for (e, edge) in input.edges.iter().enumerate() {
        let route = if edge.from == edge.to && edge.from < n {
            let k = loop_rank[edge.from];
            loop_rank[edge.from] += 1;
            loop_route(nodes[edge.from], k, &loops[edge.from], edge.label)
        } else if chains[e].len() >= 2 {
            let mut r = geometry.route(e, &chains[e]);
            if let (Some(label), Some(&u)) = (&mut r.label, chains[e].first()) {
                // Keep the label in the column of its upper node, clear of
                // the labels already placed.
                let c = vertices[u].cluster;
                let band = clustered.then(|| (band_x[c], band_x[c] + band_w[c]));
                *label = free_spot(*label, band, &placed);
                placed.push(*label);
            }
            if reversed[e] { r.reversed() } else { r }
        } else {
            Route {
                start: Point { x: 0.0, y: 0.0 },
                curves: Vec::new(),
                label: None,
            }
        };
        edges.push(route);
    }
    let clusters: Vec<Rect> = if clustered {
        (0..n_clusters)
            .map(|c| Rect {
                x: band_x[c] - CLUSTER_PAD,
                y: 0.0,
                w: band_w[c] + 2.0 * CLUSTER_PAD,
                h: bottom.max(header + CLUSTER_PAD) + CLUSTER_PAD,
            })
            .collect()
    } else {
        Vec::new()
    };
    let mut out = Layout {
        nodes,
        edges,
        clusters,
        width: 0.0,
        height: 0.0,
    };
    out.measure();
    out
}

impl Layout {
    /// Sets the size to the extent of everything.
    fn measure(&mut self) {
        let mut w: f64 = 0.0;
        let mut h: f64 = 0.0;
        let mut grow = |r: &Rect| {
            w = w.max(r.right());
            h = h.max(r.bottom());
        };
        self.nodes.iter().for_each(&mut grow);
        self.clusters.iter().for_each(&mut grow);
        for e in &self.edges {
            if let Some(l) = &e.label {
                grow(l);
            }
            for c in &e.curves {
                for p in c {
                    grow(&Rect {
                        x: p.x,
                        y: p.y,
                        w: 0.0,
                        h: 0.0,
                    });
                }
            }
        }
        self.width = w;
        self.height = h;
    }
}

/// The self-loops of each node: their label sizes.
fn self_loops(input: &Input) -> Vec<Vec<Option<(f64, f64)>>> {
    let mut loops = vec![Vec::new(); input.nodes.len()];
    for e in &input.edges {
        if e.from == e.to {
            if let Some(l) = loops.get_mut(e.from) {
                l.push(e.label);
            }
        }
    }
    loops
}

/// Which edges a depth-first search from the nodes in input order finds
/// going back to a node on its stack: reversing them breaks every cycle.
fn back_edges(input: &Input) -> Vec<bool> {
    let n = input.nodes.len();
    let mut out: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (e, edge) in input.edges.iter().enumerate() {
        if edge.from != edge.to && edge.from < n && edge.to < n {
            out[edge.from].push(e);
        }
    }
    let mut reversed = vec![false; input.edges.len()];
    // 0: not seen, 1: on the stack, 2: done.
    let mut state = vec![0_u8; n];
    for root in 0..n {
        if state[root] != 0 {
            continue;
        }
        state[root] = 1;
        let mut stack: Vec<(usize, usize)> = vec![(root, 0)];
        while let Some(top) = stack.last_mut() {
            let (v, next) = *top;
            if let Some(&e) = out[v].get(next) {
                top.1 += 1;
                let w = input.edges[e].to;
                match state[w] {
                    0 => {
                        state[w] = 1;
                        stack.push((w, 0));
                    }
                    1 => reversed[e] = true,
                    _ => {}
                }
            } else {
                state[v] = 2;
                stack.pop();
            }
        }
    }
    reversed
}

/// The layer of each node: the length of its longest path from a source
/// (the edges must be acyclic).
fn longest_paths(n: usize, edges: impl Iterator<Item = (usize, usize)>) -> Vec<usize> {
    let mut out: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut indegree = vec![0_usize; n];
    for (u, v) in edges {
        out[u].push(v);
        indegree[v] += 1;
    }
    let mut layer = vec![0; n];
    let mut ready: std::collections::VecDeque<usize> =
        (0..n).filter(|&v| indegree[v] == 0).collect();
    while let Some(u) = ready.pop_front() {
        for &v in &out[u] {
            layer[v] = layer[v].max(layer[u] + 1);
            indegree[v] -= 1;
            if indegree[v] == 0 {
                ready.push_back(v);
            }
        }
    }
    layer
}

/// Crossings between consecutive layers.
fn crossings(layers: &[Vec<usize>], vertices: &[Vertex], segments: &[(usize, usize)]) -> usize {
    let mut pos = vec![0; vertices.len()];
    for layer in layers {
        for (k, &v) in layer.iter().enumerate() {
            pos[v] = k;
        }
    }
    let mut by_layer: Vec<Vec<(usize, usize)>> = vec![Vec::new(); layers.len()];
    for &(a, b) in segments {
        by_layer[vertices[a].layer].push((pos[a], pos[b]));
    }
    let mut count = 0;
    for segs in &by_layer {
        for (i, s) in segs.iter().enumerate() {
            for t in &segs[i + 1..] {
                if (s.0 < t.0 && s.1 > t.1) || (s.0 > t.0 && s.1 < t.1) {
                    count += 1;
                }
            }
        }
    }
    count
}

/// Orders each layer by barycentre sweeps, keeping the best order seen.
fn order(layers: &mut [Vec<usize>], vertices: &[Vertex], segments: &[(usize, usize)]) {
    let mut up: Vec<Vec<usize>> = vec![Vec::new(); vertices.len()];
    let mut down: Vec<Vec<usize>> = vec![Vec::new(); vertices.len()];
    for &(a, b) in segments {
        down[a].push(b);
        up[b].push(a);
    }
    let mut best = layers.to_vec();
    let mut best_count = crossings(layers, vertices, segments);
    let mut pos = vec![0.0; vertices.len()];
    for sweep in 0..SWEEPS {
        let downwards = sweep % 2 == 0;
        let order: Vec<usize> = if downwards {
            (1..layers.len()).collect()
        } else {
            (0..layers.len().saturating_sub(1)).rev().collect()
        };
        for l in order {
            let adjacent = if downwards { l - 1 } else { l + 1 };
            for (k, &v) in layers[adjacent].iter().enumerate() {
                pos[v] = k as f64;
            }
            let neighbours = if downwards { &up } else { &down };
            let mut keyed: Vec<(usize, f64, usize)> = layers[l]
                .iter()
                .enumerate()
                .map(|(k, &v)| {
                    let ns = &neighbours[v];
                    let bary = if ns.is_empty() {
                        k as f64
                    } else {
                        ns.iter().map(|&w| pos[w]).sum::<f64>() / ns.len() as f64
                    };
                    (vertices[v].cluster, bary, v)
                })
                .collect();
            keyed.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
            layers[l] = keyed.into_iter().map(|k| k.2).collect();
        }
        let count = crossings(layers, vertices, segments);
        if count < best_count {
            best_count = count;
            best = layers.to_vec();
        }
    }
    layers.clone_from_slice(&best);
}

/// Places the vertices of cluster `c` (slot centres from 0); returns the
/// width they take.
fn place_cluster(
    c: usize,
    layers: &[Vec<usize>],
    vertices: &mut [Vertex],
    segments: &[(usize, usize)],
) -> f64 {
    let rows: Vec<Vec<usize>> = layers
        .iter()
        .map(|l| {
            l.iter()
                .copied()
                .filter(|&v| vertices[v].cluster == c)
                .collect()
        })
        .collect();
    for row in &rows {
        let mut x = 0.0;
        for &v in row {
            vertices[v].x = x + vertices[v].width / 2.0;
            x += vertices[v].width + NODE_GAP;
        }
    }
    let mut up: Vec<Vec<usize>> = vec![Vec::new(); vertices.len()];
    let mut down: Vec<Vec<usize>> = vec![Vec::new(); vertices.len()];
    for &(a, b) in segments {
        if vertices[a].cluster == c && vertices[b].cluster == c {
            down[a].push(b);
            up[b].push(a);
        }
    }
    for pass in 0..PASSES {
        let downwards = pass % 2 == 0;
        let order: Vec<usize> = if downwards {
            (0..rows.len()).collect()
        } else {
            (0..rows.len()).rev().collect()
        };
        let neighbours = if downwards { &up } else { &down };
        for l in order {
            let desired: Vec<f64> = rows[l]
                .iter()
                .map(|&v| {
                    let ns = &neighbours[v];
                    if ns.is_empty() {
                        vertices[v].x
                    } else {
                        ns.iter().map(|&w| vertices[w].x).sum::<f64>() / ns.len() as f64
                    }
                })
                .collect();
            let widths: Vec<f64> = rows[l].iter().map(|&v| vertices[v].width).collect();
            for (&v, x) in rows[l].iter().zip(spread(&desired, &widths)) {
                vertices[v].x = x;
            }
        }
    }
    let left = rows
        .iter()
        .flatten()
        .map(|&v| vertices[v].x - vertices[v].width / 2.0)
        .fold(f64::INFINITY, f64::min);
    if !left.is_finite() {
        return 0.0;
    }
    let mut right: f64 = 0.0;
    for &v in rows.iter().flatten() {
        vertices[v].x -= left;
        right = right.max(vertices[v].x + vertices[v].width / 2.0);
    }
    right
}

/// The centres, in this order and [`NODE_GAP`] apart at least, closest to
/// the `desired` ones (least squares): blocks of touching slots are placed
/// at the mean of what their members want, merging while they overlap.
fn spread(desired: &[f64], widths: &[f64]) -> Vec<f64> {
    // A block: first member, members, sum of wanted left ends, its width.
    struct Block {
        first: usize,
        len: usize,
        sum: f64,
        width: f64,
    }
    impl Block {
        fn left(&self) -> f64 {
            self.sum / self.len as f64
        }
    }
    let mut blocks: Vec<Block> = Vec::new();
    for (k, (&d, &w)) in desired.iter().zip(widths).enumerate() {
        let mut b = Block {
            first: k,
            len: 1,
            sum: d - w / 2.0,
            width: w,
        };
        while let Some(prev) = blocks.last() {
            if prev.left() + prev.width + NODE_GAP <= b.left() {
                break;
            }
            let offset = prev.width + NODE_GAP;
            b = Block {
                first: prev.first,
                len: prev.len + b.len,
                sum: prev.sum + b.sum - offset * b.len as f64,
                width: offset + b.width,
            };
            blocks.pop();
        }
        blocks.push(b);
    }
    let mut out = Vec::with_capacity(desired.len());
    for b in &blocks {
        let mut x = b.left();
        for w in &widths[b.first..b.first + b.len] {
            out.push(x + w / 2.0);
            x += w + NODE_GAP;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::svg::geometry::{ClusterIn, EdgeIn, NodeIn};

    fn node(cluster: usize) -> NodeIn {
        NodeIn {
            width: 60.0,
            height: 30.0,
            round: false,
            cluster,
        }
    }

    fn edge(from: usize, to: usize) -> EdgeIn {
        EdgeIn {
            from,
            to,
            label: Some((30.0, 12.0)),
        }
    }

    fn overlap(a: &Rect, b: &Rect) -> bool {
        a.x < b.right() && b.x < a.right() && a.y < b.bottom() && b.y < a.bottom()
    }

    #[test]
    fn empty_graphs_lay_out() {
        let l = layout(&Input::default());
        assert!(l.nodes.is_empty() && l.width == 0.0 && l.height == 0.0);
    }

    #[test]
    fn cycles_loops_and_long_edges_are_routed_clear_of_nodes() {
        // A cycle, a self-loop, parallel and opposite edges, a long edge.
        let input = Input {
            nodes: (0..5).map(|_| node(0)).collect(),
            edges: vec![
                edge(0, 1),
                edge(1, 2),
                edge(2, 0),
                edge(1, 1),
                edge(1, 2),
                edge(2, 1),
                edge(0, 4),
                edge(3, 4),
                edge(4, 3),
            ],
            clusters: Vec::new(),
        };
        let l = layout(&input);
        assert_eq!(layout(&input).nodes, l.nodes, "deterministic");
        for (i, a) in l.nodes.iter().enumerate() {
            assert!(a.x >= 0.0 && a.y >= 0.0);
            for b in &l.nodes[i + 1..] {
                assert!(!overlap(a, b), "{a:?} {b:?}");
            }
        }
        for (e, r) in input.edges.iter().zip(&l.edges) {
            assert!(!r.curves.is_empty());
            // The route goes from the source's border to the target's.
            let (end, _) = r.end();
            let near = |p: Point, n: &Rect| {
                p.x >= n.x - 0.1
                    && p.x <= n.right() + 0.1
                    && p.y >= n.y - 0.1
                    && p.y <= n.bottom() + 0.1
            };
            assert!(near(r.start, &l.nodes[e.from]), "{e:?} {r:?}");
            assert!(near(end, &l.nodes[e.to]), "{e:?} {r:?}");
            let label = r.label.expect("labelled");
            for n in &l.nodes {
                assert!(!overlap(&label, n), "label {label:?} on {n:?}");
            }
        }
    }

    #[test]
    fn clusters_hold_their_nodes_only() {
        let input = Input {
            nodes: vec![node(0), node(1), node(1), node(2), node(0)],
            edges: vec![edge(0, 1), edge(1, 2), edge(3, 4), edge(2, 0)],
            clusters: (0..3)
                .map(|_| ClusterIn {
                    header_width: 100.0,
                    header_height: 30.0,
                })
                .collect(),
        };
        let l = layout(&input);
        assert_eq!(l.clusters.len(), 3);
        for (n, r) in input.nodes.iter().zip(&l.nodes) {
            for (c, cr) in l.clusters.iter().enumerate() {
                let inside =
                    r.x > cr.x && r.right() < cr.right() && r.y > cr.y && r.bottom() < cr.bottom();
                assert_eq!(inside, c == n.cluster, "{r:?} {cr:?}");
                if c != n.cluster {
                    assert!(!overlap(r, cr));
                }
            }
        }
        for r in l.edges.iter().filter_map(|r| r.label) {
            assert!(
                l.clusters
                    .iter()
                    .any(|c| r.x >= c.x && r.right() <= c.right())
            );
        }
    }

    #[test]
    fn spread_keeps_order_and_spacing() {
        let xs = spread(&[10.0, 10.0, 10.0, 200.0], &[20.0, 20.0, 20.0, 20.0]);
        for w in xs.windows(2) {
            assert!(w[1] - w[0] >= 20.0 + NODE_GAP - 1e-9, "{xs:?}");
        }
        // The three wanting 10 are centred on it; the last is free.
        assert!((xs[1] - 10.0).abs() < 1e-9, "{xs:?}");
        assert!((xs[3] - 200.0).abs() < 1e-9, "{xs:?}");
    }
}
