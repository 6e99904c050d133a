//! SVG writing for the `svg` export: text measuring (a per-character width
//! estimate, on the wide side of common sans-serif fonts, so that boxes
//! sized from it hold their text), and [`Canvas`], which writes shapes,
//! multi-line texts and edges (path, coloured arrowhead, label) with every
//! text escaped and every number with one decimal.

use std::fmt::Write as _;

use super::geometry::{Point, Rect, Route};
use crate::pnml::{attr, text};

/// The font size of node labels, in pixels.
pub(crate) const FONT: f64 = 12.0;
/// The font size of edge labels.
pub(crate) const SMALL: f64 = 10.0;
/// Line height, as a multiple of the font size.
const LEADING: f64 = 1.25;
/// The arrowhead's length and half width.
const HEAD: f64 = 9.0;
const HEAD_HALF: f64 = 4.0;

/// The estimated width of one character, in font sizes: at least its
/// advance in DejaVu Sans, Helvetica or Arial.
fn char_width(c: char) -> f64 {
    match c {
        'm' | 'w' | 'M' | 'W' | '@' | '%' => 1.0,
        'i' | 'j' | 'l' | '.' | ',' | ':' | ';' | '\'' | '!' | '|' | ' ' => 0.36,
        'f' | 't' | 'r' | 'I' | '(' | ')' | '[' | ']' | '-' => 0.48,
        'A'..='Z' | '_' | '&' | '#' => 0.8,
        'a'..='z' | '0'..='9' | '<' | '>' | '=' | '+' | '~' | '?' | '$' => 0.66,
        '*' | '"' | '/' | '\\' | '^' | '{' | '}' => 0.55,
        _ => 1.0,
    }
}

/// The estimated width of a line of text at a font size.
pub(crate) fn text_width(s: &str, font: f64) -> f64 {
    s.chars().map(char_width).sum::<f64>() * font
}

/// The height of one line at a font size.
pub(crate) fn line_height(font: f64) -> f64 {
    LEADING * font
}

/// The size (width, height) of lines of text.
pub(crate) fn block_size(lines: &[String], font: f64) -> (f64, f64) {
    let w = lines
        .iter()
        .map(|l| text_width(l, font))
        .fold(0.0, f64::max);
    (w, line_height(font) * lines.len() as f64)
}

/// How a text is drawn.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TextStyle<'a> {
    pub class: &'a str,
    pub font: f64,
    /// Centred on `x` rather than starting there.
    pub centred: bool,
    pub bold: bool,
    /// The fill colour, if not black.
    pub color: Option<&'a str>,
}

impl<'a> TextStyle<'a> {
    pub fn centred(class: &'a str) -> Self {
        TextStyle {
            class,
            font: FONT,
            centred: true,
            bold: false,
            color: None,
        }
    }

    pub fn start(class: &'a str) -> Self {
        TextStyle {
            centred: false,
            ..Self::centred(class)
        }
    }
}

/// The SVG elements of one diagram, in drawing order.
#[derive(Debug, Default)]
pub(crate) struct Canvas {
    pub body: String,
}

impl Canvas {
    /// A rectangle (`rx` rounds its corners).
    #[allow(clippy::too_many_arguments)]
    pub fn rect(
        &mut self,
        id: Option<&str>,
        class: &str,
        r: Rect,
        rx: f64,
        fill: &str,
        stroke: &str,
        extra: &str,
    ) {
        let _ = writeln!(
            self.body,
            "<rect{} class=\"{}\" x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" rx=\"{rx:.1}\" fill=\"{}\" stroke=\"{}\"{extra}/>",
            id_attr(id),
            attr(class),
            r.x,
            r.y,
            r.w,
            r.h,
            attr(fill),
            attr(stroke)
        );
    }

    /// An ellipse filling the rectangle `r`.
    pub fn ellipse(
        &mut self,
        id: Option<&str>,
        class: &str,
        r: Rect,
        fill: &str,
        stroke: &str,
        extra: &str,
    ) {
        let _ = writeln!(
            self.body,
            "<ellipse{} class=\"{}\" cx=\"{:.1}\" cy=\"{:.1}\" rx=\"{:.1}\" ry=\"{:.1}\" fill=\"{}\" stroke=\"{}\"{extra}/>",
            id_attr(id),
            attr(class),
            r.cx(),
            r.cy(),
            r.w / 2.0,
            r.h / 2.0,
            attr(fill),
            attr(stroke)
        );
    }

    /// Lines of text in a block whose first line's top is `top`: centred
    /// on `x`, or starting at `x`. Each line is a `<tspan>` and its
    /// baseline is placed so that its letters stay inside its line.
    pub fn text(&mut self, x: f64, top: f64, lines: &[String], style: TextStyle<'_>) {
        if lines.is_empty() {
            return;
        }
        let step = line_height(style.font);
        let baseline = top + step / 2.0 + 0.35 * style.font;
        let anchor = if style.centred { "middle" } else { "start" };
        let weight = if style.bold {
            " font-weight=\"bold\""
        } else {
            ""
        };
        let fill = style
            .color
            .map(|c| format!(" fill=\"{}\"", attr(c)))
            .unwrap_or_default();
        let _ = write!(
            self.body,
            "<text class=\"{}\" x=\"{x:.1}\" y=\"{baseline:.1}\" font-size=\"{:.1}\" text-anchor=\"{anchor}\"{weight}{fill}>",
            attr(style.class),
            style.font
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
    }

    /// Lines of text centred in the rectangle `r`.
    pub fn text_in(&mut self, r: Rect, lines: &[String], style: TextStyle<'_>) {
        let h = line_height(style.font) * lines.len() as f64;
        self.text(r.cx(), r.cy() - h / 2.0, lines, style);
    }

    /// An edge: its path (`id`, `class`), its arrowhead (`id.head`, class
    /// `head`, filled with the edge's colour) at the end of the route, and
    /// its label in the colour of the edge.
    #[allow(clippy::too_many_arguments)]
    pub fn edge(
        &mut self,
        id: &str,
        class: &str,
        route: &Route,
        color: &str,
        dash: &str,
        label: &str,
    ) {
        if route.curves.is_empty() {
            return;
        }
        let (tip, dir) = route.end();
        // The line stops at the arrowhead's base.
        let base = Point {
            x: tip.x - dir.x * (HEAD - 1.0),
            y: tip.y - dir.y * (HEAD - 1.0),
        };
        let mut d = format!("M {:.1} {:.1}", route.start.x, route.start.y);
        let last = route.curves.len() - 1;
        for (k, c) in route.curves.iter().enumerate() {
            let end = if k == last { base } else { c[2] };
            let _ = write!(
                d,
                " C {:.1} {:.1}, {:.1} {:.1}, {:.1} {:.1}",
                c[0].x, c[0].y, c[1].x, c[1].y, end.x, end.y
            );
        }
        let _ = writeln!(
            self.body,
            "<path id=\"{}\" class=\"{}\" d=\"{d}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\"{dash}/>",
            attr(id),
            attr(class),
            attr(color)
        );
        self.head(&format!("{id}.head"), class, tip, dir, color);
        if let (Some(r), false) = (route.label, label.is_empty()) {
            let style = TextStyle {
                font: SMALL,
                color: Some(color),
                ..TextStyle::start("edge-label")
            };
            self.text(r.x, r.y, &[label.to_owned()], style);
        }
    }

    /// An arrowhead: a triangle with its tip at `tip`, pointing along
    /// `dir` (a unit vector), filled with `color`.
    pub fn head(&mut self, id: &str, class: &str, tip: Point, dir: Point, color: &str) {
        let base = Point {
            x: tip.x - dir.x * HEAD,
            y: tip.y - dir.y * HEAD,
        };
        let (nx, ny) = (-dir.y * HEAD_HALF, dir.x * HEAD_HALF);
        let class = class.replacen("edge", "head", 1);
        let _ = writeln!(
            self.body,
            "<path id=\"{}\" class=\"{}\" d=\"M {:.1} {:.1} L {:.1} {:.1} L {:.1} {:.1} Z\" fill=\"{}\" stroke=\"none\"/>",
            attr(id),
            attr(&class),
            tip.x,
            tip.y,
            base.x + nx,
            base.y + ny,
            base.x - nx,
            base.y - ny,
            attr(color)
        );
    }

    /// A straight legend arrow from `(x, y)`, `len` long, to the right.
    #[allow(clippy::too_many_arguments)]
    pub fn legend_arrow(
        &mut self,
        id: &str,
        class: &str,
        x: f64,
        y: f64,
        len: f64,
        color: &str,
        dash: &str,
    ) {
        let route = Route {
            start: Point { x, y },
            curves: vec![[
                Point {
                    x: x + len / 3.0,
                    y,
                },
                Point {
                    x: x + 2.0 * len / 3.0,
                    y,
                },
                Point { x: x + len, y },
            ]],
            label: None,
        };
        self.edge(id, class, &route, color, dash, "");
    }
}

fn id_attr(id: Option<&str>) -> String {
    id.map(|id| format!(" id=\"{}\"", attr(id)))
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wide_letters_are_wider() {
        assert!(text_width("WWW", FONT) > text_width("iii", FONT));
        assert_eq!(text_width("", FONT), 0.0);
        let (w, h) = block_size(&["ab".to_owned(), "abcd".to_owned()], 10.0);
        assert!((w - text_width("abcd", 10.0)).abs() < 1e-9);
        assert!((h - 25.0).abs() < 1e-9);
    }

    #[test]
    fn texts_are_escaped() {
        let mut c = Canvas::default();
        c.text(0.0, 0.0, &["a<b&c".to_owned()], TextStyle::centred("x\"y"));
        assert!(c.body.contains("a&lt;b&amp;c"), "{}", c.body);
        assert!(!c.body.contains("x\"y"), "{}", c.body);
    }
}
