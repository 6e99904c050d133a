//! The `svg` export: the pictures of the `dot` export ([`Diagrams`]),
//! laid out in-process with the `layout-rs` crate and written as one SVG
//! document, so that no Graphviz installation is needed.
//!
//! The document stacks, top to bottom: the component overview (services,
//! filled with the colour of the thread that runs them, and the `stops`,
//! `delays` and `forbids` edges: solid red, dashed orange, dotted blue), its
//! legend (threads and edge styles), then one codel state machine per
//! service (request dot, control/start/exec/inter codel boxes, `end` double
//! circle, report boxes; `next` edges solid, `on-inter` edges dashed and
//! labelled), then the legend of the machines. `layout-rs` has no clusters,
//! so each diagram is laid out on its own and placed in a `<g>` with a
//! title; thread groups are shown by colour and by the `thread` line of
//! each service.
//!
//! Drawing goes through [`Canvas`], this module's own rendering backend:
//! every node and edge carries a class (`node codel exec`, `edge on-inter`,
//! `edge rule delays`...), every text is escaped, numbers have one decimal,
//! and the output is deterministic.
//!
//! `layout-rs` asserts invariants of its placement and panics when one
//! fails (it does on a few graphs); each diagram is laid out inside
//! `catch_unwind`, and a failed layout is redone with the crate's simple
//! placement (see docs/exports/diagrams.md).

use std::fmt::Write as _;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Once;

use genom_model::kinds::CodelKind;
use layout::core::base::Orientation;
use layout::core::color::Color;
use layout::core::format::{ClipHandle, RenderBackend};
use layout::core::geometry::Point;
use layout::core::style::{LineStyleKind, StyleAttr};
use layout::std_shapes::render::get_shape_size;
use layout::std_shapes::shapes::{Arrow, Element, LineEndKind, ShapeKind};
use layout::topo::layout::VisualGraph;

use crate::dot::{Diagrams, EdgeKind, Machine, NodeKind, Overview, Rule};
use crate::pnml::{attr, comment, text, tool_version};
use crate::{ExportError, ExportInput, Exported};

/// The font size of node labels, in pixels.
const FONT: usize = 12;
/// Space between diagrams, and margins.
const GAP: f64 = 30.0;
/// The height of a diagram's title.
const TITLE: f64 = 36.0;

/// Exports the component's diagrams as one SVG document.
pub fn export(input: &ExportInput<'_>) -> Result<Exported, ExportError> {
    let d = Diagrams::build(input.component);
    let mut parts: Vec<Part> = Vec::new();
    parts.push(laid_out(
        "overview",
        &format!("{}: services by thread", d.component),
        &overview_graph(&d.overview),
    )?);
    parts.push(overview_legend(&d.overview));
    for m in &d.machines {
        let title = format!("{}: codels ({})", m.title, m.detail);
        let id = format!("machine.{}", m.service);
        parts.push(laid_out(&id, &title, &machine_graph(m))?);
    }
    parts.push(machine_legend());
    let text = document(&d.component, &tool_version(input), &parts);
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

/// A graph to lay out: elements and edges (indices into the elements).
struct Graph {
    nodes: Vec<Element>,
    edges: Vec<(Arrow, usize, usize)>,
}

/// Lays `g` out with `layout-rs` and draws it: with its full placement
/// (Brandes-Köpf and edge straightening), or, should that fail on this
/// graph, with its simple placement (rows laid out left to right).
fn laid_out(id: &str, title: &str, g: &Graph) -> Result<Part, ExportError> {
    let mut canvas = Canvas::default();
    if !g.nodes.is_empty() {
        canvas =
            draw(g, false)
                .or_else(|| draw(g, true))
                .ok_or_else(|| ExportError::Unsupported {
                    format: "svg",
                    reason: format!("the layout of diagram {id} failed"),
                })?;
    }
    Ok(Part {
        id: id.to_owned(),
        title: title.to_owned(),
        body: canvas.body,
        width: canvas.max.x,
        height: canvas.max.y,
    })
}

/// One layout attempt (`layout-rs` asserts its invariants: a failed one is
/// a panic, caught here).
fn draw(g: &Graph, simple: bool) -> Option<Canvas> {
    quiet_layout_panics();
    catch_unwind(AssertUnwindSafe(|| {
        let mut vg = VisualGraph::new(Orientation::TopToBottom);
        let handles: Vec<_> = g.nodes.iter().map(|n| vg.add_node(n.clone())).collect();
        for (arrow, from, to) in &g.edges {
            vg.add_edge(arrow.clone(), handles[*from], handles[*to]);
        }
        let mut c = Canvas::default();
        vg.do_it(false, false, simple, &mut c);
        c
    }))
    .ok()
}

/// Installs, once, a panic hook that stays silent for the assertion
/// failures of `layout-rs` (caught by [`draw`], which then falls back to
/// the simple placement) and passes every other panic to the previous
/// hook.
fn quiet_layout_panics() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let in_layout = info
                .location()
                .is_some_and(|l| l.file().contains("layout-rs"));
            if !in_layout {
                previous(info);
            }
        }));
    });
}

fn look(fill: &str, line: &str, width: usize) -> StyleAttr {
    StyleAttr::new(Color::fast(line), width, Some(Color::fast(fill)), 0, FONT)
}

fn element(shape: ShapeKind, look: StyleAttr, class: &str) -> Element {
    let square = matches!(shape, ShapeKind::Circle(_) | ShapeKind::DoubleCircle(_));
    let size = get_shape_size(Orientation::TopToBottom, &shape, FONT, square);
    Element::create_with_properties(shape, look, Orientation::TopToBottom, size, class)
}

fn arrow(style: LineStyleKind, label: &str, color: &str, class: &str) -> Arrow {
    let mut look = StyleAttr::simple();
    look.line_color = Color::fast(color);
    look.font_size = FONT - 2;
    let mut a = Arrow::new(
        LineEndKind::None,
        LineEndKind::Arrow,
        style,
        label,
        &look,
        &None,
        &None,
    );
    a.properties = Some(class.to_owned());
    a
}

fn overview_graph(o: &Overview) -> Graph {
    let mut nodes = Vec::new();
    for s in &o.services {
        let color = o.groups.get(s.group).map_or("#ffffff", |g| g.color);
        let mut label = vec![s.name.clone()];
        label.extend(s.details.iter().cloned());
        nodes.push(element(
            ShapeKind::new_box(&label.join("\n")),
            look(color, "#5d6d7e", 1),
            "node service",
        ));
    }
    let edges = o
        .edges
        .iter()
        .map(|e| {
            let style = match e.rule {
                Rule::Stops => LineStyleKind::Normal,
                Rule::Delays => LineStyleKind::Dashed,
                Rule::Forbids => LineStyleKind::Dotted,
            };
            let class = format!("edge rule {}", e.rule.keyword());
            (
                arrow(style, e.rule.keyword(), e.rule.color(), &class),
                e.from,
                e.to,
            )
        })
        .collect();
    Graph { nodes, edges }
}

fn machine_graph(m: &Machine) -> Graph {
    let nodes = m
        .nodes
        .iter()
        .map(|n| {
            let mut label = vec![n.name.clone()];
            label.extend(n.details.iter().cloned());
            let label = label.join("\n");
            let class = format!("node {}", n.kind.class());
            let class = match n.kind {
                NodeKind::Codel(_) => format!("{class} codel"),
                _ => class,
            };
            let (shape, line) = match n.kind {
                NodeKind::Request => (ShapeKind::new_circle(""), "#000000"),
                NodeKind::End => (ShapeKind::new_double_circle(&label), "#1c2833"),
                NodeKind::Report => (ShapeKind::new_box(&label), "#922b21"),
                NodeKind::Codel(_) => (ShapeKind::new_box(&label), "#1c2833"),
            };
            element(shape, look(n.kind.fill(), line, 1), &class)
        })
        .collect();
    let edges = m
        .edges
        .iter()
        .map(|e| {
            let (style, label) = match e.kind {
                EdgeKind::OnInter => (LineStyleKind::Dashed, "on-inter"),
                _ => (LineStyleKind::Normal, e.label.as_str()),
            };
            let class = format!("edge {}", e.kind.class());
            (arrow(style, label, e.kind.color(), &class), e.from, e.to)
        })
        .collect();
    Graph { nodes, edges }
}

/// The legend of the overview: thread colours and edge styles.
fn overview_legend(o: &Overview) -> Part {
    let mut c = Canvas::default();
    let mut y = 10.0;
    for g in &o.groups {
        let fill = g.color.to_owned();
        let _ = writeln!(
            c.body,
            "<rect class=\"legend thread\" x=\"0.0\" y=\"{:.1}\" width=\"24.0\" height=\"14.0\" fill=\"{}\" stroke=\"#5d6d7e\"/>",
            y - 7.0,
            attr(&fill)
        );
        c.text_at(
            34.0,
            y,
            &format!("{}: {}", g.title, g.detail),
            "legend",
            "start",
        );
        y += 22.0;
    }
    for rule in Rule::ALL {
        let _ = writeln!(
            c.body,
            "<path class=\"legend edge rule {}\" d=\"M 0.0 {y:.1} L 24.0 {y:.1}\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\"{} marker-end=\"url(#arrow)\"/>",
            rule.keyword(),
            rule.color(),
            rule_dash(rule)
        );
        c.text_at(
            34.0,
            y,
            &format!("A {} B: {}", rule.keyword(), rule.meaning()),
            "legend",
            "start",
        );
        y += 22.0;
    }
    Part {
        id: "overview.legend".to_owned(),
        title: "legend of the overview".to_owned(),
        body: c.body,
        width: 560.0,
        height: y,
    }
}

/// The legend of the machines: node kinds and edge styles.
fn machine_legend() -> Part {
    let mut c = Canvas::default();
    let mut y = 10.0;
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
        let _ = writeln!(
            c.body,
            "<rect class=\"legend node {}\" x=\"0.0\" y=\"{:.1}\" width=\"24.0\" height=\"14.0\" fill=\"{}\" stroke=\"#1c2833\"/>",
            kind.class(),
            y - 7.0,
            kind.fill()
        );
        c.text_at(34.0, y, what, "legend", "start");
        y += 22.0;
    }
    for kind in [EdgeKind::Request, EdgeKind::Next, EdgeKind::OnInter] {
        let dash = if kind == EdgeKind::OnInter {
            " stroke-dasharray=\"6,4\""
        } else {
            ""
        };
        let _ = writeln!(
            c.body,
            "<path class=\"legend edge {}\" d=\"M 0.0 {y:.1} L 24.0 {y:.1}\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\"{dash} marker-end=\"url(#arrow)\"/>",
            kind.class(),
            kind.color()
        );
        let what = match kind {
            EdgeKind::Request => "the request path (accept, completes at once)",
            EdgeKind::Next => "next: an outcome of the codel",
            EdgeKind::OnInter => "on-inter: where an interrupt leads from this codel",
        };
        c.text_at(34.0, y, what, "legend", "start");
        y += 22.0;
    }
    Part {
        id: "machine.legend".to_owned(),
        title: "legend of the codel machines".to_owned(),
        body: c.body,
        width: 560.0,
        height: y,
    }
}

fn rule_dash(rule: Rule) -> &'static str {
    match rule {
        Rule::Stops => "",
        Rule::Delays => " stroke-dasharray=\"6,4\"",
        Rule::Forbids => " stroke-dasharray=\"2,3\"",
    }
}

/// The whole document: the parts stacked top to bottom.
fn document(component: &str, version: &str, parts: &[Part]) -> String {
    let width = parts
        .iter()
        .map(|p| p.width)
        .fold(600.0_f64, f64::max)
        .ceil()
        + 2.0 * GAP;
    let height: f64 = parts.iter().map(|p| p.height + TITLE + GAP).sum::<f64>() + GAP;
    let mut out = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        out,
        "<!-- Diagrams of component {}, generated by genom-check {}. -->",
        comment(component),
        comment(version)
    );
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.1}\" height=\"{height:.1}\" viewBox=\"0 0 {width:.1} {height:.1}\" font-family=\"Helvetica, Arial, sans-serif\">"
    );
    let _ = writeln!(out, "<title>component {}</title>", text(component));
    out.push_str(
        "<defs>\n<marker id=\"arrow\" viewBox=\"0 0 10 10\" refX=\"10\" refY=\"5\" markerWidth=\"8\" markerHeight=\"8\" orient=\"auto-start-reverse\">\n<path d=\"M 0 0 L 10 5 L 0 10 z\" fill=\"#1c2833\"/>\n</marker>\n</defs>\n",
    );
    let _ = writeln!(
        out,
        "<rect x=\"0\" y=\"0\" width=\"{width:.1}\" height=\"{height:.1}\" fill=\"#ffffff\"/>"
    );
    let mut y = GAP;
    for p in parts {
        let _ = writeln!(
            out,
            "<g id=\"{}\" class=\"diagram\" transform=\"translate({GAP:.1},{y:.1})\">",
            attr(&p.id)
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

/// A `layout-rs` rendering backend that writes deterministic SVG elements.
#[derive(Debug)]
struct Canvas {
    body: String,
    max: Point,
    paths: usize,
}

impl Default for Canvas {
    fn default() -> Self {
        Canvas {
            body: String::new(),
            max: Point::zero(),
            paths: 0,
        }
    }
}

impl Canvas {
    fn grow(&mut self, x: f64, y: f64) {
        self.max.x = self.max.x.max(x);
        self.max.y = self.max.y.max(y);
    }

    /// Multi-line text centred (or starting) at `(x, y)`.
    fn text_at(&mut self, x: f64, y: f64, s: &str, class: &str, anchor: &str) {
        let lines: Vec<&str> = s.lines().collect();
        if lines.is_empty() {
            return;
        }
        let step = 1.25 * FONT as f64;
        let first = y - step * (lines.len() - 1) as f64 / 2.0;
        let _ = write!(
            self.body,
            "<text class=\"{}\" x=\"{x:.1}\" y=\"{first:.1}\" font-size=\"{FONT}\" text-anchor=\"{anchor}\" dominant-baseline=\"central\">",
            attr(class)
        );
        for (k, line) in lines.iter().enumerate() {
            let dy = if k == 0 { 0.0 } else { step };
            let _ = write!(
                self.body,
                "<tspan x=\"{x:.1}\" dy=\"{dy:.1}\">{}</tspan>",
                text(line)
            );
        }
        self.body.push_str("</text>\n");
        let width = lines.iter().map(|l| l.chars().count()).max().unwrap_or(0) as f64;
        self.grow(
            x + width * FONT as f64 * 0.6,
            first + step * lines.len() as f64,
        );
    }
}

/// `#rrggbb` of a layout colour (its alpha dropped).
fn web(c: Color) -> String {
    let s = c.to_web_color();
    s.get(..7).map_or(s.clone(), str::to_owned)
}

impl RenderBackend for Canvas {
    fn draw_rect(
        &mut self,
        xy: Point,
        size: Point,
        look: &StyleAttr,
        properties: Option<String>,
        _clip: Option<ClipHandle>,
    ) {
        let fill = look.fill_color.map_or_else(|| "none".to_owned(), web);
        let class = properties.unwrap_or_default();
        let rx = if class.contains("service") || class.contains("codel") {
            8.0
        } else {
            2.0
        };
        let dash = if class.contains("control") {
            " stroke-dasharray=\"4,3\""
        } else {
            ""
        };
        let _ = writeln!(
            self.body,
            "<rect class=\"{}\" x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" rx=\"{rx:.1}\" fill=\"{fill}\" stroke=\"{}\" stroke-width=\"{}\"{dash}/>",
            attr(&class),
            xy.x,
            xy.y,
            size.x,
            size.y,
            web(look.line_color),
            look.line_width
        );
        self.grow(xy.x + size.x, xy.y + size.y);
    }

    fn draw_line(
        &mut self,
        start: Point,
        stop: Point,
        look: &StyleAttr,
        _properties: Option<String>,
    ) {
        let _ = writeln!(
            self.body,
            "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"{}\"/>",
            start.x,
            start.y,
            stop.x,
            stop.y,
            web(look.line_color)
        );
        self.grow(start.x.max(stop.x), start.y.max(stop.y));
    }

    fn draw_circle(
        &mut self,
        xy: Point,
        size: Point,
        look: &StyleAttr,
        properties: Option<String>,
    ) {
        let fill = look.fill_color.map_or_else(|| "none".to_owned(), web);
        let class = properties.unwrap_or_else(|| "ring".to_owned());
        let _ = writeln!(
            self.body,
            "<ellipse class=\"{}\" cx=\"{:.1}\" cy=\"{:.1}\" rx=\"{:.1}\" ry=\"{:.1}\" fill=\"{fill}\" stroke=\"{}\" stroke-width=\"{}\"/>",
            attr(&class),
            xy.x,
            xy.y,
            size.x / 2.0,
            size.y / 2.0,
            web(look.line_color),
            look.line_width
        );
        self.grow(xy.x + size.x / 2.0, xy.y + size.y / 2.0);
    }

    fn draw_text(&mut self, xy: Point, s: &str, _look: &StyleAttr) {
        self.text_at(xy.x, xy.y, s, "label", "middle");
    }

    fn draw_arrow(
        &mut self,
        path: &[(Point, Point)],
        _dashed: bool,
        head: (bool, bool),
        look: &StyleAttr,
        properties: Option<String>,
        label: &str,
    ) {
        let (Some(first), Some(second)) = (path.first(), path.get(1)) else {
            return;
        };
        let mut d = format!(
            "M {:.1} {:.1} C {:.1} {:.1}, {:.1} {:.1}, {:.1} {:.1}",
            first.0.x,
            first.0.y,
            first.1.x,
            first.1.y,
            second.0.x,
            second.0.y,
            second.1.x,
            second.1.y
        );
        for p in path.iter().skip(2) {
            let _ = write!(d, " S {:.1} {:.1}, {:.1} {:.1}", p.0.x, p.0.y, p.1.x, p.1.y);
        }
        for p in path {
            self.grow(p.0.x.max(p.1.x), p.0.y.max(p.1.y));
        }
        let class = properties.unwrap_or_else(|| "edge".to_owned());
        let dash = if class.contains("on-inter") || class.contains("delays") {
            " stroke-dasharray=\"6,4\""
        } else if class.contains("forbids") {
            " stroke-dasharray=\"2,3\""
        } else {
            ""
        };
        let start = if head.0 {
            " marker-start=\"url(#arrow)\""
        } else {
            ""
        };
        let end = if head.1 {
            " marker-end=\"url(#arrow)\""
        } else {
            ""
        };
        self.paths += 1;
        let _ = writeln!(
            self.body,
            "<path class=\"{}\" d=\"{d}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\"{dash}{start}{end}/>",
            attr(&class),
            web(look.line_color)
        );
        if !label.is_empty() {
            let mid = path[path.len() / 2].1;
            self.text_at(mid.x, mid.y, label, "edge-label", "middle");
        }
    }

    fn create_clip(&mut self, _xy: Point, _size: Point, _rounded_px: usize) -> ClipHandle {
        self.paths
    }
}
