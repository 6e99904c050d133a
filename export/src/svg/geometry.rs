//! The shapes of the `svg` export's layout: points, rectangles, the graph
//! to lay out (`Input`), edge routes and the placement (`Layout`), shared
//! by the layout, the routing and the drawing.

/// A point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Point {
    pub x: f64,
    pub y: f64,
}

impl Point {
    pub(super) fn lerp(self, to: Point, t: f64) -> Point {
        Point {
            x: self.x + (to.x - self.x) * t,
            y: self.y + (to.y - self.y) * t,
        }
    }
}

/// A rectangle: its top-left corner and size.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct Rect {
    pub x: f64,
    pub y: f64,
    pub w: f64,
    pub h: f64,
}

impl Rect {
    pub fn right(&self) -> f64 {
        self.x + self.w
    }
    pub fn bottom(&self) -> f64 {
        self.y + self.h
    }
    pub fn cx(&self) -> f64 {
        self.x + self.w / 2.0
    }
    pub fn cy(&self) -> f64 {
        self.y + self.h / 2.0
    }
}

/// A node to place.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NodeIn {
    pub width: f64,
    pub height: f64,
    /// An ellipse (its ports are on its outline) rather than a box.
    pub round: bool,
    /// Its cluster (ignored when there are no clusters).
    pub cluster: usize,
}

/// An edge to route.
#[derive(Debug, Clone, Copy)]
pub(crate) struct EdgeIn {
    pub from: usize,
    pub to: usize,
    /// The size (width, height) of its label, if any.
    pub label: Option<(f64, f64)>,
}

/// A cluster: the size of its header (its title, drawn above its nodes).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ClusterIn {
    pub header_width: f64,
    pub header_height: f64,
}

/// A graph to lay out.
#[derive(Debug, Clone, Default)]
pub(crate) struct Input {
    pub nodes: Vec<NodeIn>,
    pub edges: Vec<EdgeIn>,
    /// Empty: no clusters.
    pub clusters: Vec<ClusterIn>,
}

/// An edge's path, from its source to its target: a start point and cubic
/// Bézier segments (two control points, then the end point).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Route {
    pub start: Point,
    pub curves: Vec<[Point; 3]>,
    /// Where the label goes.
    pub label: Option<Rect>,
}

impl Route {
    /// The end point and the unit direction of the path there.
    pub fn end(&self) -> (Point, Point) {
        let (from, to) = match self.curves.last() {
            Some([_, c2, end]) => (*c2, *end),
            None => (self.start, self.start),
        };
        let (dx, dy) = (to.x - from.x, to.y - from.y);
        let len = (dx * dx + dy * dy).sqrt();
        let dir = if len > 1e-9 {
            Point {
                x: dx / len,
                y: dy / len,
            }
        } else {
            Point { x: 0.0, y: 1.0 }
        };
        (to, dir)
    }
}

/// The placement: node boxes, edge routes, cluster rectangles (all with
/// non-negative coordinates) and the size of the whole.
#[derive(Debug, Clone, Default)]
pub(crate) struct Layout {
    pub nodes: Vec<Rect>,
    pub edges: Vec<Route>,
    pub clusters: Vec<Rect>,
    pub width: f64,
    pub height: f64,
}

/// A node of the layered graph: a real node or a dummy.
#[derive(Debug, Clone, Copy)]
pub(super) struct Vertex {
    /// The slot's width (a real node's width plus its self-loops).
    pub width: f64,
    pub cluster: usize,
    pub layer: usize,
    /// The slot's centre.
    pub x: f64,
}
