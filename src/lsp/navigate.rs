//! Document symbols, go-to-definition and hover, from the component model
//! of a document's last check: the word under the cursor is matched
//! against the names of services, threads (tasks), codels, data structures
//! and ports.

use genom_model::Span;
use genom_model::component::{Component, Named};
use lsp_types::{
    DocumentSymbol, DocumentSymbolResponse, GotoDefinitionResponse, Hover, HoverContents, Location,
    MarkupContent, MarkupKind, Position, Range, SymbolKind,
};

use super::check::Document;
use super::position;
use super::publish::Target;

mod facts;

/// A named thing of the component, for symbols and definitions.
struct Declared<'a> {
    /// What it is (`service`, `thread`, `codel`, ...).
    kind: Thing,
    name: &'a str,
    span: Span,
    /// Its container's name span, for codels (their service).
    parent: Option<Span>,
    detail: String,
}

/// The kinds of named things.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Thing {
    Service(genom_model::component::ServiceId),
    Thread(genom_model::component::ThreadId),
    Codel(genom_model::component::CodelId),
    Structure,
    Port,
    /// A named IDL type (`struct`, `enum`, `typedef`...).
    Type,
}

/// Everything named in `c`, services first.
fn declarations(c: &Component) -> Vec<Declared<'_>> {
    let mut out = Vec::new();
    for (id, s) in c.services.iter() {
        out.push(declared(
            Thing::Service(id),
            &s.name,
            facts::service_kind(c, id),
        ));
    }
    for (id, t) in c.threads.iter() {
        out.push(declared(Thing::Thread(id), &t.name, facts::thread_kind(c)));
    }
    for (id, k) in c.codels.iter() {
        let mut d = declared(
            Thing::Codel(id),
            &k.name,
            format!("{} codel", k.kind.keyword()),
        );
        d.parent = c.services.get(k.service).map(|s| s.name.span);
        out.push(d);
    }
    for (_, s) in c.structures.iter() {
        out.push(Declared {
            kind: Thing::Structure,
            name: &s.name,
            span: s.span,
            parent: None,
            detail: s.kind.keyword().to_owned(),
        });
    }
    for (_, t) in c.types.iter() {
        // An IDS block's anonymous struct is the block itself (above).
        let short = t.name.rsplit("::").next().unwrap_or(&t.name);
        if c.structures.values().any(|s| s.block == short) {
            continue;
        }
        out.push(Declared {
            kind: Thing::Type,
            // `geo::Pose` is named `Pose` where it is written.
            name: short,
            span: t.span,
            parent: None,
            detail: format!("type `{}`", t.name),
        });
    }
    for p in c.genom3.iter().flat_map(|g| g.ports.iter()) {
        let dir = if p.is_out { "port out" } else { "port in" };
        out.push(declared(Thing::Port, &p.name, dir.to_owned()));
    }
    out
}

fn declared(kind: Thing, name: &Named, detail: String) -> Declared<'_> {
    Declared {
        kind,
        name: &name.name,
        span: name.span,
        parent: None,
        detail,
    }
}

fn target(doc: &Document) -> Target<'_> {
    Target {
        document: &doc.uri,
        path: &doc.path,
        code_url: None,
    }
}

/// The symbols of the document: its component's services (with their
/// codels), threads, data structures and ports written in it.
pub fn symbols(doc: &Document) -> DocumentSymbolResponse {
    let Some((text, result, c)) = doc
        .result()
        .and_then(|(t, r)| Some((t, r, r.component.as_ref()?)))
    else {
        return DocumentSymbolResponse::Nested(Vec::new());
    };
    let target = target(doc);
    let here = |span: Span| {
        target
            .place(&result.sources, span)
            .filter(|(uri, _)| uri == &doc.uri)
            .map(|(_, range)| range)
    };
    let all = declarations(c);
    let mut top: Vec<DocumentSymbol> = Vec::new();
    for d in all.iter().filter(|d| d.parent.is_none()) {
        let Some(range) = here(d.span) else { continue };
        let children: Vec<DocumentSymbol> = all
            .iter()
            .filter(|k| k.parent == Some(d.span) && matches!(d.kind, Thing::Service(_)))
            .filter_map(|k| Some(symbol(k, here(k.span)?, None)))
            .collect();
        top.push(symbol(d, range, Some(children).filter(|c| !c.is_empty())));
    }
    let Some(name) = here(c.name.span) else {
        return DocumentSymbolResponse::Nested(top);
    };
    let whole = position::range(text, 0, text.len());
    let root = DocumentSymbol {
        range: Range::new(Position::new(0, 0), whole.end.max(name.end)),
        ..symbol_at(
            &c.name.name,
            SymbolKind::MODULE,
            "component",
            name,
            Some(top),
        )
    };
    DocumentSymbolResponse::Nested(vec![root])
}

fn symbol(d: &Declared<'_>, range: Range, children: Option<Vec<DocumentSymbol>>) -> DocumentSymbol {
    let kind = match d.kind {
        Thing::Service(_) => SymbolKind::METHOD,
        Thing::Thread(_) => SymbolKind::CLASS,
        Thing::Codel(_) => SymbolKind::FUNCTION,
        Thing::Structure => SymbolKind::STRUCT,
        Thing::Port => SymbolKind::INTERFACE,
        Thing::Type => SymbolKind::STRUCT,
    };
    symbol_at(d.name, kind, &d.detail, range, children)
}

#[allow(deprecated)] // `deprecated` is a required field of the struct.
fn symbol_at(
    name: &str,
    kind: SymbolKind,
    detail: &str,
    range: Range,
    children: Option<Vec<DocumentSymbol>>,
) -> DocumentSymbol {
    DocumentSymbol {
        name: name.to_owned(),
        detail: Some(detail.to_owned()).filter(|d| !d.is_empty()),
        kind,
        tags: None,
        deprecated: None,
        range,
        selection_range: range,
        children,
    }
}

/// The identifier at `at` in `text` and its byte range.
fn word_at(text: &str, at: usize) -> Option<(usize, &str)> {
    let is_word = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let start = text
        .get(..at)?
        .rfind(|c: char| !is_word(c))
        .map_or(0, |i| i + 1);
    let end = text
        .get(at..)?
        .find(|c: char| !is_word(c))
        .map_or(text.len(), |i| at + i);
    let word = text.get(start..end)?;
    (!word.is_empty()).then_some((start, word))
}

/// The declarations the word under `at` names, best first: for a codel
/// name shared by several services, the codels of the service written
/// last before the cursor come first. Positions are read in the text the
/// last check read (while a newer text is being checked, they may be off).
fn named_at<'a>(doc: &Document, c: &'a Component, at: Position) -> Vec<Declared<'a>> {
    let Some((text, result)) = doc.result() else {
        return Vec::new();
    };
    let local = position::offset(text, at);
    let Some((_, word)) = word_at(text, local) else {
        return Vec::new();
    };
    let base = result
        .sources
        .files()
        .find(|(_, f)| f.path == doc.path)
        .map_or(0, |(_, f)| f.base);
    let cursor = base.saturating_add(u32::try_from(local).unwrap_or(u32::MAX));
    let mut found: Vec<Declared<'a>> = declarations(c)
        .into_iter()
        .filter(|d| d.name == word)
        .collect();
    // The enclosing service: the last service name before the cursor.
    let enclosing = c
        .services
        .values()
        .map(|s| s.name.span)
        .filter(|s| s.start <= cursor)
        .max_by_key(|s| s.start);
    found.sort_by_key(|d| match d.parent {
        Some(p) => u8::from(Some(p) != enclosing),
        None => 0,
    });
    found
}

/// Where the service, thread, codel, structure or port named under `at`
/// is declared.
pub fn definition(doc: &Document, at: Position) -> Option<GotoDefinitionResponse> {
    let (_, result) = doc.result()?;
    let c = result.component.as_ref()?;
    let target = target(doc);
    let locations: Vec<Location> = named_at(doc, c, at)
        .iter()
        .filter_map(|d| target.place(&result.sources, d.span))
        .map(|(uri, range)| Location::new(uri, range))
        .collect();
    match locations.len() {
        0 => None,
        1 => locations
            .into_iter()
            .next()
            .map(GotoDefinitionResponse::Scalar),
        _ => Some(GotoDefinitionResponse::Array(locations)),
    }
}

/// The resolved facts of the service, thread or codel named under `at`.
pub fn hover(doc: &Document, at: Position) -> Option<Hover> {
    let result = doc.result()?.1;
    let c = result.component.as_ref()?;
    let d = named_at(doc, c, at).into_iter().next()?;
    let value = match d.kind {
        Thing::Service(id) => {
            let mut text = facts::service(c, id);
            // Computed by the last save check, when the component has WCETs.
            if let Some(r) = result.response_times.iter().find(|r| r.service == d.name) {
                let note = r
                    .note
                    .as_deref()
                    .map(|n| format!(" ({n})"))
                    .unwrap_or_default();
                text.push_str(&format!(
                    "\n\nworst-case response time: {}{note}",
                    r.worst.human()
                ));
            }
            text
        }
        Thing::Thread(id) => facts::thread(c, id),
        Thing::Codel(id) => facts::codel(c, id),
        Thing::Structure | Thing::Port => format!("**{}** `{}`", d.detail, d.name),
        Thing::Type => format!("**{}**", d.detail),
    };
    Some(Hover {
        contents: HoverContents::Markup(MarkupContent {
            kind: MarkupKind::Markdown,
            value,
        }),
        range: None,
    })
}
