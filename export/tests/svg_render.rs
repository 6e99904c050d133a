//! The `svg` export, rendered: the picture of every `specs/*.gen` is parsed
//! with `usvg` (text laid out with the system fonts) and rasterised with
//! `resvg`, then checked geometrically on the parsed tree:
//!
//! - no text straddles the border of a node (a service, codel, report,
//!   `end` or request shape) or of a thread cluster: each text is either
//!   outside it or strictly inside it, and every labelled node holds a
//!   text;
//! - every edge (and legend arrow) has an arrowhead filled with the colour
//!   of the edge's stroke;
//! - every service of the overview lies inside the cluster of the thread
//!   that runs it (the control thread's for services without start codel)
//!   and outside every other cluster;
//! - the raster shows each service box in its thread's colour.
//!
//! The same checks run on the GenoM3 pictures of
//! `common::GENOM3_DIAGRAM_FIXTURES` (and of `uavatt` when the corpus is
//! there), where the clusters are tasks (`cluster.task.T`, the control
//! task's `cluster.control`) holding each activity and permanent-codels
//! box, and the control task holds the functions' and attributes' table;
//! the event dots carry no text.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

mod common;

use common::export;

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

use common::CheckResult;
use genom_export::Format;
use resvg::tiny_skia;
use resvg::usvg;

/// The system fonts, with the generic `sans-serif` family mapped to an
/// installed sans-serif font.
fn fonts() -> Arc<usvg::fontdb::Database> {
    let mut db = usvg::fontdb::Database::new();
    db.load_system_fonts();
    let installed = |name: &str| {
        db.faces()
            .any(|f| f.families.iter().any(|(family, _)| family == name))
    };
    let sans = [
        "Helvetica",
        "Arial",
        "DejaVu Sans",
        "Liberation Sans",
        "Noto Sans",
    ]
    .into_iter()
    .find(|name| installed(name));
    if let Some(name) = sans {
        db.set_sans_serif_family(name);
    }
    Arc::new(db)
}

/// A shape of the parsed tree: its bounding box in canvas coordinates and
/// its fill and stroke colours.
#[derive(Debug, Clone, Copy)]
struct Shape {
    bbox: usvg::Rect,
    fill: Option<usvg::Color>,
    stroke: Option<usvg::Color>,
}

/// What the checks look at: the shapes with an `id`, and every text.
#[derive(Debug, Default)]
struct Scene {
    shapes: BTreeMap<String, Shape>,
    texts: Vec<(String, usvg::Rect)>,
}

fn color(paint: &usvg::Paint) -> Option<usvg::Color> {
    match paint {
        usvg::Paint::Color(c) => Some(*c),
        _ => None,
    }
}

fn collect(g: &usvg::Group, scene: &mut Scene) {
    for node in g.children() {
        match node {
            usvg::Node::Group(g) => collect(g, scene),
            usvg::Node::Path(p) if !p.id().is_empty() => {
                let shape = Shape {
                    bbox: p.abs_bounding_box(),
                    fill: p.fill().and_then(|f| color(f.paint())),
                    stroke: p.stroke().and_then(|s| color(s.paint())),
                };
                scene.shapes.insert(p.id().to_owned(), shape);
            }
            usvg::Node::Text(t) => {
                let s: String = t.chunks().iter().map(|c| c.text()).collect();
                scene.texts.push((s, t.abs_bounding_box()));
            }
            _ => {}
        }
    }
}

/// Node shapes: (id, round). GenoM3 pictures add the event dots and
/// `ether` (round), the states, `validate`, the permanent codels and the
/// control task's table (boxes).
fn is_node(id: &str) -> Option<bool> {
    if ["request.", "end.", "event.", "ether."]
        .iter()
        .any(|p| id.starts_with(p))
    {
        Some(true)
    } else if [
        "service.",
        "codel.",
        "report.",
        "state.",
        "validate.",
        "permanent.",
        "table.",
    ]
    .iter()
    .any(|p| id.starts_with(p))
    {
        Some(false)
    } else {
        None
    }
}

fn disjoint(a: &usvg::Rect, b: &usvg::Rect) -> bool {
    a.right() <= b.left() || b.right() <= a.left() || a.bottom() <= b.top() || b.bottom() <= a.top()
}

/// Whether `t` is strictly inside the shape of bounding box `b` (a box,
/// or the ellipse it bounds), with a margin for the stroke.
fn inside(t: &usvg::Rect, b: &usvg::Rect, round: bool) -> bool {
    const MARGIN: f32 = 1.0;
    if !round {
        return t.left() > b.left() + MARGIN
            && t.right() < b.right() - MARGIN
            && t.top() > b.top() + MARGIN
            && t.bottom() < b.bottom() - MARGIN;
    }
    let (cx, cy) = ((b.left() + b.right()) / 2.0, (b.top() + b.bottom()) / 2.0);
    let (rx, ry) = (b.width() / 2.0 - MARGIN, b.height() / 2.0 - MARGIN);
    [
        (t.left(), t.top()),
        (t.right(), t.top()),
        (t.left(), t.bottom()),
        (t.right(), t.bottom()),
    ]
    .iter()
    .all(|&(x, y)| ((x - cx) / rx).powi(2) + ((y - cy) / ry).powi(2) < 1.0)
}

/// A cluster: `thread.T` (the dialect), `cluster.task.T` or
/// `cluster.control` (GenoM3).
fn is_cluster(id: &str) -> bool {
    id.starts_with("thread.") || id.starts_with("cluster.")
}

/// The cluster expected to hold each box of a GenoM3 picture: each
/// activity (`service.A`) in its task's (`cluster.task.T`), each task's
/// permanent codels (`permanent.T`) in it, the functions and attributes'
/// table (`table.control`) in the control task's (`cluster.control`).
fn expected_genom3_clusters(result: &CheckResult) -> Vec<(String, String)> {
    let c = result.component.as_ref().expect("component");
    let g = c.genom3.as_ref().expect("a GenoM3 component");
    let task = |t: &str| format!("cluster.task.{t}");
    let mut out = Vec::new();
    for t in g.tasks.iter().filter(|t| !t.codels.is_empty()) {
        let name = &c.threads[t.thread].name.name;
        out.push((format!("permanent.{name}"), task(name)));
    }
    for i in &g.services {
        let s = &c.services[i.service];
        if i.kind != "activity" {
            continue;
        }
        let cluster = s.thread.map_or_else(
            || "cluster.control".to_owned(),
            |t| task(&c.threads[t.id].name.name),
        );
        out.push((format!("service.{}", s.name.name), cluster));
    }
    if g.services.iter().any(|i| i.kind != "activity") {
        out.push(("table.control".to_owned(), "cluster.control".to_owned()));
    }
    out
}

/// The cluster expected to hold each service: `service.S` -> `thread.T`.
fn expected_clusters(result: &CheckResult) -> Vec<(String, String)> {
    let c = result.component.as_ref().expect("component");
    c.services
        .iter()
        .map(|(_, s)| {
            let thread = match (s.runs_on_thread(), s.thread) {
                (true, Some(t)) => c.threads[t.id].name.name.clone(),
                _ => "control".to_owned(),
            };
            (
                format!("service.{}", s.name.name),
                format!("thread.{thread}"),
            )
        })
        .collect()
}

fn parse(svg: &str, fonts: &Arc<usvg::fontdb::Database>) -> usvg::Tree {
    let options = usvg::Options {
        fontdb: Arc::clone(fonts),
        ..usvg::Options::default()
    };
    usvg::Tree::from_str(svg, &options).expect("usvg parses the export")
}

fn check_texts(name: &str, scene: &Scene) {
    let borders = scene
        .shapes
        .iter()
        .filter_map(|(id, s)| {
            let round = is_node(id).or_else(|| is_cluster(id).then_some(false))?;
            Some((id, s, round))
        })
        .collect::<Vec<_>>();
    assert!(
        borders
            .iter()
            .any(|(id, _, _)| id.starts_with("codel.") || id.starts_with("state.")),
        "{name}: no codel node"
    );
    for (id, shape, round) in &borders {
        for (text, tb) in &scene.texts {
            assert!(
                disjoint(tb, &shape.bbox) || inside(tb, &shape.bbox, *round),
                "{name}: text {text:?} {tb:?} straddles the border of {id} {:?}",
                shape.bbox
            );
        }
        if !id.starts_with("request.") && !id.starts_with("event.") {
            assert!(
                scene
                    .texts
                    .iter()
                    .any(|(_, tb)| inside(tb, &shape.bbox, *round)),
                "{name}: {id} holds no text"
            );
        }
    }
}

fn check_heads(name: &str, scene: &Scene) {
    let mut edges = 0;
    for (id, shape) in &scene.shapes {
        if id.ends_with(".head") || !(id.starts_with("edge.") || id.starts_with("legend.")) {
            continue;
        }
        edges += 1;
        let stroke = shape.stroke.expect("an edge has a stroke colour");
        let head = scene
            .shapes
            .get(&format!("{id}.head"))
            .unwrap_or_else(|| panic!("{name}: edge {id} has no arrowhead"));
        assert_eq!(
            head.fill,
            Some(stroke),
            "{name}: the arrowhead of {id} is not filled with its colour"
        );
    }
    assert!(edges > 0, "{name}: no edge");
}

fn check_clusters(name: &str, scene: &Scene, expected: &[(String, String)]) {
    for (service, thread) in expected {
        let s = scene
            .shapes
            .get(service)
            .unwrap_or_else(|| panic!("{name}: no node {service}"));
        for (id, cluster) in scene.shapes.iter().filter(|(id, _)| is_cluster(id)) {
            if id == thread {
                assert!(
                    inside(&s.bbox, &cluster.bbox, false),
                    "{name}: {service} is not inside its cluster {thread}"
                );
            } else {
                assert!(
                    disjoint(&s.bbox, &cluster.bbox),
                    "{name}: {service} overlaps the cluster {id}"
                );
            }
        }
        assert!(
            scene.shapes.contains_key(thread),
            "{name}: no cluster {thread}"
        );
    }
}

/// Rasterises the tree and checks that each service box shows its fill
/// colour just inside its left border (left of its centred label); the
/// GenoM3 table (white, ruled) is left out.
fn check_raster(name: &str, tree: &usvg::Tree, scene: &Scene, expected: &[(String, String)]) {
    let size = tree.size().to_int_size();
    let mut pixmap =
        tiny_skia::Pixmap::new(size.width(), size.height()).expect("a non-empty picture");
    resvg::render(tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
    let not_white = pixmap
        .pixels()
        .iter()
        .filter(|p| (p.red(), p.green(), p.blue()) != (255, 255, 255))
        .count();
    assert!(not_white > 1000, "{name}: the raster is blank");
    for (service, _) in expected.iter().filter(|(id, _)| !id.starts_with("table.")) {
        let s = scene.shapes[service];
        let fill = s.fill.expect("a service box is filled");
        let x = (s.bbox.left() + 4.0) as u32;
        let y = ((s.bbox.top() + s.bbox.bottom()) / 2.0) as u32;
        let p = pixmap.pixel(x, y).expect("inside the picture");
        let close = |a: u8, b: u8| a.abs_diff(b) <= 2;
        assert!(
            close(p.red(), fill.red) && close(p.green(), fill.green) && close(p.blue(), fill.blue),
            "{name}: {service} shows {p:?} at ({x}, {y}), not its colour {fill:?}"
        );
    }
}

#[test]
fn svg_pictures_render_with_coloured_heads_and_thread_clusters() {
    let fonts = fonts();
    for path in common::specs() {
        let name = path.display().to_string();
        let result = common::check(&path);
        let svg = export(&result, Format::Svg);
        let tree = parse(&svg, &fonts);
        let mut scene = Scene::default();
        collect(tree.root(), &mut scene);
        let expected = expected_clusters(&result);
        check_heads(&name, &scene);
        check_clusters(&name, &scene, &expected);
        check_raster(&name, &tree, &scene, &expected);
    }
}

/// Texts are laid out with the system fonts: without any font the test is
/// ignored, with its reason (`.ci/run` installs one and sets
/// `GENOM_REQUIRE_FONTS=1`, so CI always runs it).
#[test]
#[cfg_attr(
    not(genom_fonts),
    ignore = "no system font: install one (e.g. fonts-dejavu-core) to check the texts"
)]
fn svg_texts_stay_inside_their_boxes() {
    let fonts = fonts();
    assert!(
        !fonts.is_empty(),
        "no system font: install one (e.g. fonts-dejavu-core) to check the texts"
    );
    for path in common::specs() {
        let name = path.display().to_string();
        let result = common::check(&path);
        let svg = export(&result, Format::Svg);
        let mut scene = Scene::default();
        collect(parse(&svg, &fonts).root(), &mut scene);
        let written = svg.matches("<text ").count();
        assert_eq!(scene.texts.len(), written, "{name}: texts were dropped");
        check_texts(&name, &scene);
    }
}

/// The GenoM3 pictures to check: the diagram fixtures, and `uavatt` when
/// the corpus is there.
fn genom3_pictures() -> Vec<(String, CheckResult)> {
    let mut out: Vec<(String, CheckResult)> = common::GENOM3_DIAGRAM_FIXTURES
        .iter()
        .map(|p| ((*p).to_owned(), common::check_genom3_fixture(Path::new(p))))
        .collect();
    if let Some(uavatt) = common::check_uavatt() {
        out.push((common::UAVATT.to_owned(), uavatt));
    }
    out
}

#[test]
fn genom3_svg_pictures_render_with_coloured_heads_and_task_clusters() {
    let fonts = fonts();
    for (name, result) in genom3_pictures() {
        let svg = export(&result, Format::Svg);
        let tree = parse(&svg, &fonts);
        let mut scene = Scene::default();
        collect(tree.root(), &mut scene);
        let expected = expected_genom3_clusters(&result);
        check_heads(&name, &scene);
        check_clusters(&name, &scene, &expected);
        check_raster(&name, &tree, &scene, &expected);
    }
}

/// As `svg_texts_stay_inside_their_boxes`, on the GenoM3 pictures (the
/// table's cells included).
#[test]
#[cfg_attr(
    not(genom_fonts),
    ignore = "no system font: install one (e.g. fonts-dejavu-core) to check the texts"
)]
fn genom3_svg_texts_stay_inside_their_boxes() {
    let fonts = fonts();
    assert!(
        !fonts.is_empty(),
        "no system font: install one (e.g. fonts-dejavu-core) to check the texts"
    );
    for (name, result) in genom3_pictures() {
        let svg = export(&result, Format::Svg);
        let mut scene = Scene::default();
        collect(parse(&svg, &fonts).root(), &mut scene);
        let written = svg.matches("<text ").count();
        assert_eq!(scene.texts.len(), written, "{name}: texts were dropped");
        check_texts(&name, &scene);
    }
}

/// The checks catch what they are for: a label moved onto its box's
/// border, a black arrowhead on a red edge, a service outside its cluster.
#[test]
fn the_checks_catch_broken_pictures() {
    let fonts = fonts();
    let result = common::check(Path::new("../specs/mobileBase.gen"));
    let svg = export(&result, Format::Svg);
    let expected = expected_clusters(&result);
    let scene_of = |svg: &str| {
        let mut scene = Scene::default();
        collect(parse(svg, &fonts).root(), &mut scene);
        scene
    };
    let fails = |f: &dyn Fn()| std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).is_err();
    // The first label of a service, moved up by 12 px: onto the border.
    let at = svg.find("class=\"label\" x=\"").expect("a label");
    let y_at = at + svg[at..].find(" y=\"").expect("its y") + 4;
    let y_end = y_at + svg[y_at..].find('"').expect("its end");
    let y: f64 = svg[y_at..y_end].parse().expect("a number");
    let moved = format!("{}{:.1}{}", &svg[..y_at], y - 12.0, &svg[y_end..]);
    if !fonts.is_empty() {
        check_texts("intact", &scene_of(&svg));
        assert!(fails(&|| check_texts("moved", &scene_of(&moved))));
    }
    // A black arrowhead on a red edge.
    let black = svg.replacen(
        "fill=\"#c0392b\" stroke=\"none\"",
        "fill=\"#1c2833\" stroke=\"none\"",
        1,
    );
    assert_ne!(black, svg, "mobileBase has a stops edge");
    assert!(fails(&|| check_heads("black", &scene_of(&black))));
    // A thread cluster shrunk to nothing.
    let at = svg.find("id=\"thread.motionTask\"").expect("a cluster");
    let w_at = at + svg[at..].find(" width=\"").expect("its width") + 8;
    let w_end = w_at + svg[w_at..].find('"').expect("its end");
    let shrunk = format!("{}1.0{}", &svg[..w_at], &svg[w_end..]);
    assert!(fails(&|| check_clusters(
        "shrunk",
        &scene_of(&shrunk),
        &expected
    )));
}

/// The checks catch a broken GenoM3 picture: a state's label moved onto
/// its border, an activity's task cluster shrunk to nothing, a black
/// arrowhead on a blue `pause` edge.
#[test]
fn the_checks_catch_broken_genom3_pictures() {
    let fonts = fonts();
    let path = Path::new(common::GENOM3_DIAGRAM_FIXTURES[3]);
    let result = common::check_genom3_fixture(path);
    let svg = export(&result, Format::Svg);
    let expected = expected_genom3_clusters(&result);
    let scene_of = |svg: &str| {
        let mut scene = Scene::default();
        collect(parse(svg, &fonts).root(), &mut scene);
        scene
    };
    let fails = |f: &dyn Fn()| std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).is_err();
    check_clusters("intact", &scene_of(&svg), &expected);
    check_heads("intact", &scene_of(&svg));
    if !fonts.is_empty() {
        check_texts("intact", &scene_of(&svg));
        let at = svg.find("id=\"state.servo.main\"").expect("a state");
        let label = at + svg[at..].find("class=\"label\" x=\"").expect("its label");
        let y_at = label + svg[label..].find(" y=\"").expect("its y") + 4;
        let y_end = y_at + svg[y_at..].find('"').expect("its end");
        let y: f64 = svg[y_at..y_end].parse().expect("a number");
        let moved = format!("{}{:.1}{}", &svg[..y_at], y - 14.0, &svg[y_end..]);
        assert!(fails(&|| check_texts("moved", &scene_of(&moved))));
    }
    let at = svg.find("id=\"cluster.task.t\"").expect("a task cluster");
    let w_at = at + svg[at..].find(" width=\"").expect("its width") + 8;
    let w_end = w_at + svg[w_at..].find('"').expect("its end");
    let shrunk = format!("{}1.0{}", &svg[..w_at], &svg[w_end..]);
    assert!(fails(&|| check_clusters(
        "shrunk",
        &scene_of(&shrunk),
        &expected
    )));
    let black = svg.replacen(
        "fill=\"#2874a6\" stroke=\"none\"",
        "fill=\"#1c2833\" stroke=\"none\"",
        1,
    );
    assert_ne!(black, svg, "f6 has a pause edge");
    assert!(fails(&|| check_heads("black", &scene_of(&black))));
}
