//! The `svg` export: the pictures of the `dot` export ([`Diagrams`]),
//! laid out in-process by this module's own layered layout
//! (`layout`, `route`) and written as one SVG document (`render`), so that no
//! Graphviz installation is needed.
//!
//! The document stacks, top to bottom: the component overview, its legend,
//! one codel state machine per service, and the legend of the machines.
//! The overview groups the services by thread as the DOT export does: one
//! labelled cluster rectangle per thread (the control thread first), side
//! by side, each holding the services whose codels the thread runs (a
//! cluster without service says so); `stops`, `delays` and `forbids` edges
//! are solid red, dashed orange and dotted blue, and labelled. Each machine
//! has its request dot, control/start/exec/inter codel boxes, `end` double
//! circle and report boxes; `next` edges are solid, `on-inter` edges dashed
//! and labelled.
//!
//! Every box is sized from its (multi-line) label with a per-character
//! width estimate on the wide side, and the label is centred in it; edges
//! never cross a node and their labels sit between layers or beside their
//! self-loop, away from any node; each arrowhead is a triangle filled with
//! the colour of its edge. Every node and edge carries a class (`node
//! codel exec`, `edge on-inter`, `edge rule delays`...) and the nodes, the
//! thread clusters and the edges an `id` (`codel.S.C`, `thread.T`,
//! `edge.machine.S.3`, whose arrowhead is `edge.machine.S.3.head`); every
//! text is escaped, numbers have one decimal, and the output is
//! deterministic. Laying out cannot fail (see docs/exports/diagrams.md).
//!
//! A GenoM3 component is drawn in GenoM3's words instead (tasks, permanent
//! codels, activities, `pause::`, `ether`, the control task's table): see
//! `genom3`.

mod genom3;
mod geometry;
mod layout;
mod render;
mod route;

use std::fmt::Write as _;

use genom_model::kinds::CodelKind;

use self::geometry::{ClusterIn, EdgeIn, Input, Layout, NodeIn, Rect};
use self::render::{Canvas, FONT, SMALL, TextStyle, block_size, line_height, text_width};
use crate::dot::{Diagrams, EdgeKind, Machine, NodeKind, Rule};
use crate::pnml::{comment, text, tool_version};
use crate::{ExportError, ExportInput, Exported};

/// Space between diagrams, and margins.
const GAP: f64 = 30.0;
/// The height of a diagram's title.
const TITLE: f64 = 36.0;
/// Space between a box's border and its label.
const PAD_X: f64 = 12.0;
const PAD_Y: f64 = 7.0;
/// The diameter of the request dot.
const DOT: f64 = 16.0;
/// The gap between the two circles of `end`.
const RING: f64 = 4.0;
/// The stroke of service boxes and thread clusters.
const SERVICE_LINE: &str = "#5d6d7e";
const CLUSTER_LINE: &str = "#85929e";

/// Exports the component's diagrams as one SVG document.
pub fn export(input: &ExportInput<'_>) -> Result<Exported, ExportError> {
    let c = input.component;
    let parts = match &c.genom3 {
        Some(g) => genom3::parts(&crate::dot::genom3::G3Diagrams::build(c, g)),
        None => {
            let d = Diagrams::build(c);
            let mut parts: Vec<Part> = vec![overview(&d), overview_legend(&d)];
            for m in &d.machines {
                parts.push(machine(m));
            }
            parts.push(machine_legend());
            parts
        }
    };
    let what = match c.genom3 {
        Some(_) => format!("GenoM3 component {}", c.name.name),
        None => format!("component {}", c.name.name),
    };
    let text = document(&what, &tool_version(input), &parts);
    let verified = input.verification.verified;
    Ok(Exported::single(crate::mark_unverified(
        text,
        verified,
        ("<!-- ", " -->"),
    )))
}

/// One drawn diagram: its SVG body (origin at its top-left corner) and
/// size.
#[derive(Debug, Clone)]
struct Part {
    id: String,
    title: String,
    body: String,
    width: f64,
    height: f64,
}

/// A name and the lines under it.
fn label(name: &str, details: &[String]) -> Vec<String> {
    let mut lines = vec![name.to_owned()];
    lines.extend(details.iter().cloned());
    lines
}

/// The layout node of a box holding `lines`.
fn box_node(lines: &[String], cluster: usize) -> NodeIn {
    let (w, h) = block_size(lines, FONT);
    NodeIn {
        width: w + 2.0 * PAD_X,
        height: h + 2.0 * PAD_Y,
        round: false,
        cluster,
    }
}

/// The layout node of a (double) circle holding `lines`: the text's
/// corners are inside the inner circle.
fn circle_node(lines: &[String]) -> NodeIn {
    let (w, h) = block_size(lines, FONT);
    let d = (w * w + h * h).sqrt() + 2.0 * PAD_Y + 2.0 * RING;
    NodeIn {
        width: d,
        height: d,
        round: true,
        cluster: 0,
    }
}

/// An edge label's size.
fn label_size(s: &str) -> Option<(f64, f64)> {
    (!s.is_empty()).then(|| (text_width(s, SMALL), line_height(SMALL)))
}

/// A thread's (or task's) cluster: its rectangle (`id`, `class`), then
/// its title and detail lines in its top left corner.
pub(crate) fn draw_cluster(
    c: &mut Canvas,
    (id, class): (&str, &str),
    r: Rect,
    fill: &str,
    (title, detail): (&str, &str),
) {
    c.rect(Some(id), class, r, 8.0, fill, CLUSTER_LINE, "");
    let x = r.x + layout::CLUSTER_PAD;
    let y = r.y + layout::CLUSTER_PAD;
    let style = TextStyle {
        bold: true,
        ..TextStyle::start("cluster-title")
    };
    c.text(x, y, &[title.to_owned()], style);
    let style = TextStyle::start("cluster-detail");
    c.text(x, y + line_height(FONT), &[detail.to_owned()], style);
}

/// A terminal node (`end`, `ether`): a disc inside a ring, its label in
/// the middle.
pub(crate) fn draw_ring(
    c: &mut Canvas,
    (id, class): (&str, &str),
    r: Rect,
    fill: &str,
    lines: &[String],
) {
    let inner = Rect {
        x: r.x + RING,
        y: r.y + RING,
        w: r.w - 2.0 * RING,
        h: r.h - 2.0 * RING,
    };
    c.ellipse(Some(id), class, inner, fill, "#1c2833", "");
    c.ellipse(None, "ring", r, "none", "#1c2833", "");
    c.text_in(r, lines, TextStyle::centred("label"));
}

/// The dash pattern of an edge style.
fn dash(dashed: bool, dotted: bool) -> &'static str {
    if dotted {
        " stroke-dasharray=\"2,3\""
    } else if dashed {
        " stroke-dasharray=\"6,4\""
    } else {
        ""
    }
}

fn rule_dash(rule: Rule) -> &'static str {
    dash(rule == Rule::Delays, rule == Rule::Forbids)
}

/// The overview: one cluster per thread, holding its services.
fn overview(d: &Diagrams) -> Part {
    let o = &d.overview;
    let mut input = Input::default();
    // Layout nodes: the services, then a placeholder for each group
    // without service.
    let empty = vec!["(no service)".to_owned()];
    let mut placeholders = Vec::new();
    for s in &o.services {
        input
            .nodes
            .push(box_node(&label(&s.name, &s.details), s.group));
    }
    for (g, group) in o.groups.iter().enumerate() {
        let (w, h) = block_size(std::slice::from_ref(&group.title), FONT);
        let (dw, _) = block_size(std::slice::from_ref(&group.detail), FONT);
        input.clusters.push(ClusterIn {
            // Bold is wider than the estimate of plain text.
            header_width: (w * 1.15).max(dw),
            header_height: 2.0 * h,
        });
        if group.services.is_empty() {
            placeholders.push(input.nodes.len());
            input.nodes.push(box_node(&empty, g));
        }
    }
    for e in &o.edges {
        input.edges.push(EdgeIn {
            from: e.from,
            to: e.to,
            label: label_size(e.rule.keyword()),
        });
    }
    let placed = layout::layout(&input);
    let mut c = Canvas::default();
    for (g, group) in o.groups.iter().enumerate() {
        let Some(&r) = placed.clusters.get(g) else {
            continue;
        };
        let fill = lighter(group.color);
        let texts = (group.title.as_str(), group.detail.as_str());
        draw_cluster(&mut c, (&group.id, "cluster thread"), r, &fill, texts);
    }
    for (k, s) in o.services.iter().enumerate() {
        let color = o.groups.get(s.group).map_or("#ffffff", |g| g.color);
        let r = placed.nodes[k];
        c.rect(Some(&s.id), "node service", r, 8.0, color, SERVICE_LINE, "");
        c.text_in(r, &label(&s.name, &s.details), TextStyle::centred("label"));
    }
    for &k in &placeholders {
        let style = TextStyle {
            color: Some("#7f8c8d"),
            ..TextStyle::centred("empty")
        };
        c.text_in(placed.nodes[k], &empty, style);
    }
    for (k, e) in o.edges.iter().enumerate() {
        c.edge(
            &format!("edge.overview.{k}"),
            &format!("edge rule {}", e.rule.keyword()),
            &placed.edges[k],
            e.rule.color(),
            rule_dash(e.rule),
            e.rule.keyword(),
        );
    }
    part(
        "overview",
        &format!("{}: services by thread", d.component),
        c,
        &placed,
    )
}

/// One service's codel machine.
fn machine(m: &Machine) -> Part {
    let mut input = Input::default();
    let labels: Vec<Vec<String>> = m.nodes.iter().map(|n| label(&n.name, &n.details)).collect();
    for (n, lines) in m.nodes.iter().zip(&labels) {
        input.nodes.push(match n.kind {
            NodeKind::Request => NodeIn {
                width: DOT,
                height: DOT,
                round: true,
                cluster: 0,
            },
            NodeKind::End => circle_node(lines),
            NodeKind::Report | NodeKind::Codel(_) => box_node(lines, 0),
        });
    }
    let edge_label = |e: &crate::dot::MachineEdge| match e.kind {
        EdgeKind::OnInter => "on-inter".to_owned(),
        _ => e.label.clone(),
    };
    for e in &m.edges {
        input.edges.push(EdgeIn {
            from: e.from,
            to: e.to,
            label: label_size(&edge_label(e)),
        });
    }
    let placed = layout::layout(&input);
    let mut c = Canvas::default();
    for ((n, lines), &r) in m.nodes.iter().zip(&labels).zip(&placed.nodes) {
        let class = match n.kind {
            NodeKind::Codel(_) => format!("node {} codel", n.kind.class()),
            _ => format!("node {}", n.kind.class()),
        };
        let fill = n.kind.fill();
        match n.kind {
            NodeKind::Request => c.ellipse(Some(&n.id), &class, r, fill, "#000000", ""),
            NodeKind::End => draw_ring(&mut c, (&n.id, &class), r, fill, lines),
            NodeKind::Report => {
                c.rect(Some(&n.id), &class, r, 2.0, fill, "#922b21", "");
                c.text_in(r, lines, TextStyle::centred("label"));
            }
            NodeKind::Codel(kind) => {
                let extra = match kind {
                    CodelKind::Control => " stroke-dasharray=\"4,3\"",
                    CodelKind::Start => " stroke-width=\"2\"",
                    _ => "",
                };
                c.rect(Some(&n.id), &class, r, 8.0, fill, "#1c2833", extra);
                c.text_in(r, lines, TextStyle::centred("label"));
            }
        }
    }
    for (k, e) in m.edges.iter().enumerate() {
        c.edge(
            &format!("edge.machine.{}.{k}", m.service),
            &format!("edge {}", e.kind.class()),
            &placed.edges[k],
            e.kind.color(),
            dash(e.kind == EdgeKind::OnInter, false),
            &edge_label(e),
        );
    }
    let title = format!("{}: codels ({})", m.title, m.detail);
    part(&format!("machine.{}", m.service), &title, c, &placed)
}

fn part(id: &str, title: &str, c: Canvas, placed: &Layout) -> Part {
    Part {
        id: id.to_owned(),
        title: title.to_owned(),
        body: c.body,
        width: placed.width,
        height: placed.height,
    }
}

/// Legend rows: a swatch or arrow at the left, then a text.
struct Legend {
    c: Canvas,
    y: f64,
    width: f64,
}

impl Legend {
    const ROW: f64 = 22.0;
    const TEXT_X: f64 = 34.0;

    fn new() -> Self {
        Legend {
            c: Canvas::default(),
            y: 0.0,
            width: 0.0,
        }
    }

    /// The vertical centre of the current row.
    fn mid(&self) -> f64 {
        self.y + Self::ROW / 2.0
    }

    fn swatch(&mut self, class: &str, fill: &str, stroke: &str) {
        let r = Rect {
            x: 0.0,
            y: self.mid() - 7.0,
            w: 24.0,
            h: 14.0,
        };
        self.c.rect(None, class, r, 0.0, fill, stroke, "");
    }

    /// A legend arrow (24 px, at the left of the current row).
    fn arrow(&mut self, id: &str, class: &str, color: &str, dash: &str) {
        let mid = self.mid();
        self.c.legend_arrow(id, class, 0.0, mid, 24.0, color, dash);
    }

    fn text(&mut self, what: &str) {
        let top = self.mid() - line_height(FONT) / 2.0;
        self.c.text(
            Self::TEXT_X,
            top,
            &[what.to_owned()],
            TextStyle::start("legend"),
        );
        self.width = self.width.max(Self::TEXT_X + text_width(what, FONT));
        self.y += Self::ROW;
    }

    fn part(self, id: &str, title: &str) -> Part {
        Part {
            id: id.to_owned(),
            title: title.to_owned(),
            body: self.c.body,
            width: self.width,
            height: self.y,
        }
    }
}

/// The legend of the overview: thread colours and edge styles.
fn overview_legend(d: &Diagrams) -> Part {
    let mut l = Legend::new();
    for g in &d.overview.groups {
        l.swatch("legend thread", g.color, SERVICE_LINE);
        l.text(&format!("{}: {}", g.title, g.detail));
    }
    for rule in Rule::ALL {
        l.arrow(
            &format!("legend.overview.{}", rule.keyword()),
            &format!("legend edge rule {}", rule.keyword()),
            rule.color(),
            rule_dash(rule),
        );
        l.text(&format!("A {} B: {}", rule.keyword(), rule.meaning()));
    }
    l.part("overview.legend", "legend of the overview")
}

/// The legend of the machines: node kinds and edge styles.
fn machine_legend() -> Part {
    let mut l = Legend::new();
    let kinds = [
        (NodeKind::Request, "request: a client asks for the service"),
        (
            NodeKind::Codel(CodelKind::Control),
            "control codel: accepts or rejects the request",
        ),
        (NodeKind::Codel(CodelKind::Start), "start codel"),
        (
            NodeKind::Codel(CodelKind::Exec),
            "exec codel (with its WCET)",
        ),
        (
            NodeKind::Codel(CodelKind::Inter),
            "inter codel (after an interrupt)",
        ),
        (
            NodeKind::End,
            "end: success, or INTERRUPTED/TIMEOUT after an interrupt",
        ),
        (NodeKind::Report, "report: the service ends with it"),
    ];
    for (kind, what) in kinds {
        l.swatch(
            &format!("legend node {}", kind.class()),
            kind.fill(),
            "#1c2833",
        );
        l.text(what);
    }
    for kind in [EdgeKind::Request, EdgeKind::Next, EdgeKind::OnInter] {
        l.arrow(
            &format!("legend.machine.{}", kind.class()),
            &format!("legend edge {}", kind.class()),
            kind.color(),
            dash(kind == EdgeKind::OnInter, false),
        );
        l.text(match kind {
            EdgeKind::Request => "the request path (accept, completes at once)",
            EdgeKind::Next => "next: an outcome of the codel",
            EdgeKind::OnInter => "on-inter: where an interrupt leads from this codel",
        });
    }
    l.part("machine.legend", "legend of the codel machines")
}

/// A lighter version of a `#rrggbb` colour (for cluster backgrounds, as in
/// the DOT export).
fn lighter(color: &str) -> String {
    let hex = color.trim_start_matches('#');
    let channel = |k: usize| {
        hex.get(2 * k..2 * k + 2)
            .and_then(|h| u8::from_str_radix(h, 16).ok())
    };
    match (hex.len(), channel(0), channel(1), channel(2)) {
        (6, Some(r), Some(g), Some(b)) => {
            let up = |v: u8| u16::from(v) + (255 - u16::from(v)) / 2;
            format!("#{:02x}{:02x}{:02x}", up(r), up(g), up(b))
        }
        _ => color.to_owned(),
    }
}

/// The whole document: the parts stacked top to bottom; `what` is
/// `component NAME` (or `GenoM3 component NAME`).
fn document(what: &str, version: &str, parts: &[Part]) -> String {
    let width = parts
        .iter()
        .map(|p| p.width.max(text_width(&p.title, 15.0) * 1.15))
        .fold(600.0_f64, f64::max)
        .ceil()
        + 2.0 * GAP;
    let height: f64 = parts.iter().map(|p| p.height + TITLE + GAP).sum::<f64>() + GAP;
    let mut out = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        out,
        "<!-- Diagrams of {}, generated by genom-check {}. -->",
        comment(what),
        comment(version)
    );
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.1}\" height=\"{height:.1}\" viewBox=\"0 0 {width:.1} {height:.1}\" font-family=\"Helvetica, Arial, sans-serif\">"
    );
    let _ = writeln!(out, "<title>{}</title>", text(what));
    let _ = writeln!(
        out,
        "<rect x=\"0\" y=\"0\" width=\"{width:.1}\" height=\"{height:.1}\" fill=\"#ffffff\"/>"
    );
    let mut y = GAP;
    for p in parts {
        let _ = writeln!(
            out,
            "<g id=\"{}\" class=\"diagram\" transform=\"translate({GAP:.1},{y:.1})\">",
            crate::pnml::attr(&p.id)
        );
        let _ = writeln!(
            out,
            "<text class=\"title\" x=\"0.0\" y=\"16.0\" font-size=\"15\" font-weight=\"bold\">{}</text>",
            text(&p.title)
        );
        let _ = writeln!(out, "<g transform=\"translate(0.0,{TITLE:.1})\">");
        out.push_str(&p.body);
        out.push_str("</g>\n</g>\n");
        y += p.height + TITLE + GAP;
    }
    out.push_str("</svg>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lighter_colours() {
        assert_eq!(lighter("#000000"), "#7f7f7f");
        assert_eq!(lighter("#ffffff"), "#ffffff");
        assert_eq!(lighter("red"), "red");
    }
}
