//! Edge routing for the layered layout (`layout`) of the `svg` export:
//! ports spread along node sides, curves across the gaps between layers
//! and straight lines through dummy slots, self-loops on the right side of
//! their node, and label spots clear of each other.

use super::geometry::{Input, Point, Rect, Route, Vertex};

/// How far the first self-loop of a node reaches, and each next one more.
const LOOP: f64 = 20.0;
const LOOP_STEP: f64 = 10.0;
/// Space between ports on a node side.
const PORT_GAP: f64 = 12.0;

impl Route {
    /// The same path, walked the other way.
    pub(super) fn reversed(self) -> Route {
        let mut points = vec![self.start];
        for c in &self.curves {
            points.extend_from_slice(c);
        }
        points.reverse();
        let start = points.first().copied().unwrap_or(self.start);
        let curves = points
            .get(1..)
            .unwrap_or_default()
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        Route {
            start,
            curves,
            label: self.label,
        }
    }
}

/// Where to put a label wanted at `want` (just right of its edge): there,
/// else left of the edge, else further right, within `band` if any and
/// overlapping none of the labels already `placed` (else where wanted).
pub(super) fn free_spot(want: Rect, band: Option<(f64, f64)>, placed: &[Rect]) -> Rect {
    let clamp = |mut r: Rect| {
        if let Some((left, right)) = band {
            r.x = r.x.min(right - r.w).max(left);
        }
        r
    };
    let overlaps = |r: &Rect| {
        placed.iter().any(|p| {
            r.x < p.right() + 2.0 && p.x < r.right() + 2.0 && r.y < p.bottom() && p.y < r.bottom()
        })
    };
    let left = Rect {
        x: want.x - want.w - 10.0,
        ..want
    };
    let further = (1..=6).map(|k| Rect {
        x: want.x + k as f64 * (want.w + 6.0),
        ..want
    });
    [want, left]
        .into_iter()
        .chain(further)
        .map(clamp)
        .find(|r| !overlaps(r))
        .unwrap_or_else(|| clamp(want))
}

/// The room taken on the right of a node by its self-loops and labels.
pub(super) fn loop_room(loops: &[Option<(f64, f64)>]) -> f64 {
    if loops.is_empty() {
        return 0.0;
    }
    let label = loops
        .iter()
        .map(|l| l.map_or(0.0, |(w, _)| w))
        .fold(0.0, f64::max);
    loop_reach(loops.len() - 1) + 8.0 + label + 4.0
}

fn loop_reach(k: usize) -> f64 {
    LOOP + LOOP_STEP * k as f64
}

/// The `k`-th self-loop of the node `r`.
pub(super) fn loop_route(
    r: Rect,
    k: usize,
    loops: &[Option<(f64, f64)>],
    label: Option<(f64, f64)>,
) -> Route {
    let dy = (r.h / 4.0).min(10.0);
    let (y1, y2) = (r.cy() - dy, r.cy() + dy);
    // A cubic reaches 3/4 of its control points' offset.
    let out = loop_reach(k) * 4.0 / 3.0;
    let start = Point {
        x: r.right(),
        y: y1,
    };
    let curves = vec![[
        Point {
            x: r.right() + out,
            y: y1 - 2.0,
        },
        Point {
            x: r.right() + out,
            y: y2 + 2.0,
        },
        Point {
            x: r.right(),
            y: y2,
        },
    ]];
    let label = label.map(|(w, h)| {
        let labels: Vec<f64> = loops.iter().filter_map(|l| l.map(|l| l.1)).collect();
        let total: f64 = labels.iter().sum();
        let before: f64 = loops[..k.min(loops.len())]
            .iter()
            .filter_map(|l| l.map(|l| l.1))
            .sum();
        Rect {
            x: r.right() + loop_reach(loops.len().saturating_sub(1)) + 8.0,
            y: r.cy() - total / 2.0 + before,
            w,
            h,
        }
    });
    Route {
        start,
        curves,
        label,
    }
}

/// The ports of each segment: the rank of the segment among those leaving
/// the bottom of its upper vertex, and among those entering the top of its
/// lower vertex, with the counts.
pub(super) struct Ports {
    bottom: Vec<(usize, usize)>,
    top: Vec<(usize, usize)>,
}

pub(super) fn ports(vertices: &[Vertex], segments: &[(usize, usize)]) -> Ports {
    let mut leaving: Vec<Vec<(f64, usize)>> = vec![Vec::new(); vertices.len()];
    let mut entering: Vec<Vec<(f64, usize)>> = vec![Vec::new(); vertices.len()];
    for (s, &(a, b)) in segments.iter().enumerate() {
        leaving[a].push((vertices[b].x, s));
        entering[b].push((vertices[a].x, s));
    }
    let mut bottom = vec![(0, 1); segments.len()];
    let mut top = vec![(0, 1); segments.len()];
    for (side, out) in [(&mut leaving, &mut bottom), (&mut entering, &mut top)] {
        for list in side.iter_mut() {
            list.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)));
            for (rank, &(_, s)) in list.iter().enumerate() {
                out[s] = (rank, list.len());
            }
        }
    }
    Ports { bottom, top }
}

/// What routing needs.
pub(super) struct Geometry<'a> {
    pub input: &'a Input,
    pub vertices: &'a [Vertex],
    pub nodes: &'a [Rect],
    pub top: &'a [f64],
    pub height: &'a [f64],
    pub ports: Ports,
    /// The index of each edge's first segment.
    pub first: Vec<usize>,
}

impl Geometry<'_> {
    /// Where a segment leaves (`bottom`) or enters a vertex, given its
    /// rank among the `count` segments on that side.
    fn port(&self, v: usize, (rank, count): (usize, usize), bottom: bool) -> Point {
        let Some(r) = self.nodes.get(v) else {
            let vx = self.vertices[v];
            let l = vx.layer;
            let y = if bottom {
                self.top[l] + self.height[l]
            } else {
                self.top[l]
            };
            return Point { x: vx.x, y };
        };
        let spacing = if count > 1 {
            PORT_GAP.min(r.w * 0.6 / (count - 1) as f64)
        } else {
            0.0
        };
        let dx = (rank as f64 - (count - 1) as f64 / 2.0) * spacing;
        let half = if self.input.nodes[v].round {
            let t = (dx / (r.w / 2.0)).clamp(-1.0, 1.0);
            r.h / 2.0 * (1.0 - t * t).sqrt()
        } else {
            r.h / 2.0
        };
        Point {
            x: r.cx() + dx,
            y: if bottom { r.cy() + half } else { r.cy() - half },
        }
    }

    /// The route of edge `e` along its chain, from upper to lower.
    pub(super) fn route(&self, e: usize, chain: &[usize]) -> Route {
        let mut start = None;
        let mut curves: Vec<[Point; 3]> = Vec::new();
        let mut label = None;
        let line = |curves: &mut Vec<[Point; 3]>, a: Point, b: Point| {
            if (b.y - a.y).abs() > 0.05 || (b.x - a.x).abs() > 0.05 {
                curves.push([a.lerp(b, 1.0 / 3.0), a.lerp(b, 2.0 / 3.0), b]);
            }
        };
        let mut at = Point { x: 0.0, y: 0.0 };
        for (k, w) in chain.windows(2).enumerate() {
            let (a, b) = (w[0], w[1]);
            let s = self.first[e] + k;
            let p = self.port(a, self.ports.bottom[s], true);
            if k == 0 {
                start = Some(p);
                at = p;
            }
            let l = self.vertices[a].layer;
            let p_out = Point {
                x: p.x,
                y: self.top[l] + self.height[l],
            };
            line(&mut curves, at, p_out);
            let q = self.port(b, self.ports.top[s], false);
            let q_in = Point {
                x: q.x,
                y: self.top[l + 1],
            };
            let mid = (p_out.y + q_in.y) / 2.0;
            curves.push([
                Point { x: p_out.x, y: mid },
                Point { x: q_in.x, y: mid },
                q_in,
            ]);
            if k == 0 {
                label = self.input.edges[e].label.map(|(w, h)| Rect {
                    x: (p_out.x + q_in.x) / 2.0 + 5.0,
                    y: mid - h / 2.0,
                    w,
                    h,
                });
            }
            at = q_in;
            if k + 2 == chain.len() {
                line(&mut curves, at, q);
            }
        }
        Route {
            start: start.unwrap_or(at),
            curves,
            label,
        }
    }
}
