//! The `svg` pictures of a GenoM3 component ([`G3Diagrams`]), in GenoM3's
//! words: the overview (one cluster per task, the control task first,
//! holding the task's permanent codels and its activities, the control
//! task the table of the functions and attributes), then one machine per
//! task and per activity, then the legend.
//!
//! Ids: the clusters `cluster.control` and `cluster.task.T`, the boxes
//! `permanent.T`, `service.A`, `table.control`; in the machines
//! `event.M.request` (dots), `validate.A`, `state.M.S`, `ether.M`, and the
//! edges `edge.machine.M.k` (`M` is the activity, or `task-T`). `pause::`
//! edges are dashed and labelled `pause`, interrupts and `kill` dotted,
//! `async` states have a second border.

use std::fmt::Write as _;

use super::geometry::{ClusterIn, Input, NodeIn, Rect};
use super::layout;
use super::render::{Canvas, FONT, TextStyle, block_size, line_height, text_width};
use super::{
    CLUSTER_LINE, DOT, Legend, Part, SERVICE_LINE, box_node, circle_node, dash, label, label_size,
    lighter, part,
};
use crate::dot::genom3::{
    BoxKind, G3Diagrams, G3EdgeKind, G3Machine, G3NodeKind, TABLE_HEADER, TaskGroup,
};

/// Space between a table cell's border and its text.
const CELL_X: f64 = 6.0;
const CELL_Y: f64 = 4.0;
/// The header row's fill.
const HEADER_FILL: &str = "#d5d8dc";

/// The parts of the picture, top to bottom.
pub(super) fn parts(d: &G3Diagrams) -> Vec<Part> {
    let mut parts = vec![overview(d)];
    parts.extend(d.machines.iter().map(machine));
    parts.push(legend(d));
    parts
}

/// The table's geometry: column widths and the row height.
struct Table {
    columns: Vec<f64>,
    row: f64,
    rows: usize,
}

impl Table {
    fn new(d: &G3Diagrams) -> Table {
        let rows = &d.overview.table.rows;
        let columns = (0..TABLE_HEADER.len())
            .map(|k| {
                // Bold is wider than the estimate of plain text.
                let header = text_width(TABLE_HEADER[k], FONT) * 1.15;
                rows.iter()
                    .map(|r| text_width(&r[k], FONT))
                    .fold(header, f64::max)
                    + 2.0 * CELL_X
            })
            .collect();
        Table {
            columns,
            row: line_height(FONT) + 2.0 * CELL_Y,
            rows: rows.len() + 1,
        }
    }

    fn width(&self) -> f64 {
        self.columns.iter().sum()
    }

    fn height(&self) -> f64 {
        self.row * self.rows as f64
    }

    /// Draws the table in `r` (its size).
    fn draw(&self, c: &mut Canvas, r: Rect, d: &G3Diagrams) {
        c.rect(
            Some("table.control"),
            "node table",
            r,
            0.0,
            "#ffffff",
            SERVICE_LINE,
            "",
        );
        let header = Rect { h: self.row, ..r };
        c.rect(
            None,
            "table-header",
            header,
            0.0,
            HEADER_FILL,
            SERVICE_LINE,
            "",
        );
        let mut grid = String::new();
        let mut x = r.x;
        for w in &self.columns[..self.columns.len().saturating_sub(1)] {
            x += w;
            let _ = write!(grid, "M {x:.1} {:.1} V {:.1} ", r.y, r.bottom());
        }
        for k in 1..self.rows {
            let y = r.y + self.row * k as f64;
            let _ = write!(grid, "M {:.1} {y:.1} H {:.1} ", r.x, r.right());
        }
        let _ = writeln!(
            c.body,
            "<path class=\"grid\" d=\"{}\" fill=\"none\" stroke=\"{CLUSTER_LINE}\"/>",
            grid.trim_end()
        );
        let header: Vec<String> = TABLE_HEADER.iter().map(|h| (*h).to_owned()).collect();
        let rows = std::iter::once(header.as_slice())
            .chain(d.overview.table.rows.iter().map(|r| r.as_slice()));
        for (k, row) in rows.enumerate() {
            let top = r.y + self.row * k as f64 + CELL_Y;
            let mut x = r.x;
            for (cell, w) in row.iter().zip(&self.columns) {
                let style = TextStyle {
                    bold: k == 0,
                    ..TextStyle::start("table-cell")
                };
                if !cell.is_empty() {
                    c.text(x + CELL_X, top, std::slice::from_ref(cell), style);
                }
                x += w;
            }
        }
    }
}

/// The overview: one cluster per task, holding its boxes.
fn overview(d: &G3Diagrams) -> Part {
    let o = &d.overview;
    let table = Table::new(d);
    let mut input = Input::default();
    let empty = vec!["(no codel, no activity)".to_owned()];
    for b in &o.boxes {
        input.nodes.push(match b.kind {
            BoxKind::Table => NodeIn {
                width: table.width(),
                height: table.height(),
                round: false,
                cluster: b.group,
            },
            _ => box_node(&b.lines, b.group),
        });
    }
    let mut placeholders = Vec::new();
    for (g, group) in o.groups.iter().enumerate() {
        input.clusters.push(cluster_in(group));
        if group.boxes.is_empty() {
            placeholders.push(input.nodes.len());
            input.nodes.push(box_node(&empty, g));
        }
    }
    let placed = layout::layout(&input);
    let mut c = Canvas::default();
    for (group, &r) in o.groups.iter().zip(&placed.clusters) {
        cluster(&mut c, group, r);
    }
    for (b, &r) in o.boxes.iter().zip(&placed.nodes) {
        let color = o.groups.get(b.group).map_or("#ffffff", |g| g.color);
        match b.kind {
            BoxKind::Table => table.draw(&mut c, r, d),
            BoxKind::Permanent => {
                let extra = " stroke-width=\"2\"";
                c.rect(
                    Some(&b.id),
                    "node permanent",
                    r,
                    0.0,
                    color,
                    SERVICE_LINE,
                    extra,
                );
                c.text_in(r, &b.lines, TextStyle::centred("label"));
            }
            BoxKind::Activity => {
                c.rect(
                    Some(&b.id),
                    "node service activity",
                    r,
                    8.0,
                    color,
                    SERVICE_LINE,
                    "",
                );
                c.text_in(r, &b.lines, TextStyle::centred("label"));
            }
        }
    }
    for r in placeholders.iter().filter_map(|&k| placed.nodes.get(k)) {
        let style = TextStyle {
            color: Some("#7f8c8d"),
            ..TextStyle::centred("empty")
        };
        c.text_in(*r, &empty, style);
    }
    let title = format!("{}: tasks and what they run", d.component);
    part("overview", &title, c, &placed)
}

fn cluster_in(group: &TaskGroup) -> ClusterIn {
    let (w, h) = block_size(std::slice::from_ref(&group.title), FONT);
    let (dw, _) = block_size(std::slice::from_ref(&group.detail), FONT);
    ClusterIn {
        header_width: (w * 1.15).max(dw),
        header_height: 2.0 * h,
    }
}

fn cluster(c: &mut Canvas, group: &TaskGroup, r: Rect) {
    let fill = lighter(group.color);
    let texts = (group.title.as_str(), group.detail.as_str());
    super::draw_cluster(c, (&group.id, "cluster task"), r, &fill, texts);
}

/// The dash pattern of an edge kind.
fn edge_dash(kind: G3EdgeKind) -> &'static str {
    dash(kind.dashed(), kind.dotted())
}

/// A task's permanent machine or an activity's.
fn machine(m: &G3Machine) -> Part {
    let mut input = Input::default();
    let labels: Vec<Vec<String>> = m.nodes.iter().map(|n| label(&n.name, &n.details)).collect();
    for (n, lines) in m.nodes.iter().zip(&labels) {
        input.nodes.push(match n.kind {
            G3NodeKind::Event => NodeIn {
                width: DOT,
                height: DOT,
                round: true,
                cluster: 0,
            },
            G3NodeKind::Ether => circle_node(lines),
            _ => box_node(lines, 0),
        });
    }
    for e in &m.edges {
        input.edges.push(super::geometry::EdgeIn {
            from: e.from,
            to: e.to,
            label: label_size(&e.label),
        });
    }
    let placed = layout::layout(&input);
    let mut c = Canvas::default();
    for ((n, lines), &r) in m.nodes.iter().zip(&labels).zip(&placed.nodes) {
        let class = format!("node {}", n.kind.class());
        let fill = n.kind.fill();
        match n.kind {
            G3NodeKind::Event => c.ellipse(Some(&n.id), &class, r, fill, "#000000", ""),
            G3NodeKind::Ether => super::draw_ring(&mut c, (&n.id, &class), r, fill, lines),
            kind => {
                let (rx, extra) = match kind {
                    G3NodeKind::Validate => (0.0, " stroke-dasharray=\"4,3\""),
                    G3NodeKind::Start => (8.0, " stroke-width=\"2\""),
                    _ => (8.0, ""),
                };
                c.rect(Some(&n.id), &class, r, rx, fill, "#1c2833", extra);
                if n.is_async {
                    let inner = Rect {
                        x: r.x + 3.0,
                        y: r.y + 3.0,
                        w: r.w - 6.0,
                        h: r.h - 6.0,
                    };
                    c.rect(None, "async", inner, 6.0, "none", "#1c2833", "");
                }
                c.text_in(r, lines, TextStyle::centred("label"));
            }
        }
    }
    for (k, (e, route)) in m.edges.iter().zip(&placed.edges).enumerate() {
        c.edge(
            &format!("edge.{}.{k}", m.id),
            &format!("edge {}", e.kind.class()),
            route,
            e.kind.color(),
            edge_dash(e.kind),
            &e.label,
        );
    }
    let title = format!("{} ({})", m.title, m.detail);
    part(&m.id, &title, c, &placed)
}

/// The legend: the task colours, the node kinds, the edge kinds.
fn legend(d: &G3Diagrams) -> Part {
    let mut l = Legend::new();
    for g in &d.overview.groups {
        l.swatch("legend task", g.color, SERVICE_LINE);
        l.text(&format!("{}: {}", g.title, g.detail));
    }
    let kinds = [
        (
            G3NodeKind::Event,
            "a request, an interrupt, the component's start, kill",
        ),
        (
            G3NodeKind::Validate,
            "validate: run by the control task, accepts or rejects",
        ),
        (G3NodeKind::Start, "start: the first state"),
        (
            G3NodeKind::State,
            "a state: its codel (async: a double border), its WCET",
        ),
        (
            G3NodeKind::Stop,
            "stop: after an interrupt (activity) or kill (task)",
        ),
        (G3NodeKind::Ether, "ether: the activity or task ends"),
    ];
    for (kind, what) in kinds {
        let class = format!("legend node {}", kind.class());
        l.swatch(&class, kind.fill(), "#1c2833");
        l.text(what);
    }
    let edges = [
        (
            G3EdgeKind::Event,
            "request, valid, component start: from an event",
        ),
        (G3EdgeKind::Yield, "yield: the next state runs at once"),
        (
            G3EdgeKind::Pause,
            "pause: yield pause::, the next state runs at the next period",
        ),
        (G3EdgeKind::Interrupt, "interrupt, kill: to the stop state"),
    ];
    for (kind, what) in edges {
        l.arrow(
            &format!("legend.genom3.{}", kind.class()),
            &format!("legend edge {}", kind.class()),
            kind.color(),
            edge_dash(kind),
        );
        l.text(what);
    }
    l.part("legend", "legend")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pauses_are_dashed_and_interrupts_dotted() {
        assert_eq!(edge_dash(G3EdgeKind::Yield), "");
        assert!(edge_dash(G3EdgeKind::Pause).contains("6,4"));
        assert!(edge_dash(G3EdgeKind::Interrupt).contains("2,3"));
    }
}
