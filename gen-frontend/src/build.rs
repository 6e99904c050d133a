//! Turns pest pairs into the AST, one `build_<rule>` function per grammar
//! rule. Builders never fail: the grammar guarantees the shape of each pair,
//! and a missing child simply leaves a default. Literal problems that the
//! grammar cannot see (a duration that is not whole nanoseconds, an unknown
//! attribute name) are reported as diagnostics here.

use std::cell::RefCell;

use genom_model::{Diagnostic, Span};
use pest::iterators::Pair;

use crate::ast::*;
use crate::diagnostics;
use crate::grammar::Rule;
use crate::literal;

mod idl;

/// Builder state: where the parsed text starts in the global offset space,
/// and the diagnostics found so far.
pub(crate) struct Builder<'d> {
    base: u32,
    diagnostics: &'d mut Vec<Diagnostic>,
    /// Constant expressions with more than [`MAX_OPERATORS`] operators,
    /// found by the (`&self`) type builders, reported by `build_item`.
    too_long: RefCell<Vec<Span>>,
}

/// Most operators in one constant expression. A chain is built as a
/// left-nested tree, so `1 + 1 + ...` with a hundred thousand terms would
/// be a tree too deep to drop or evaluate recursively without exhausting
/// the stack. Real constants have a handful.
pub(crate) const MAX_OPERATORS: usize = 1024;

type P<'i> = Pair<'i, Rule>;

impl<'d> Builder<'d> {
    /// A builder for text starting at global offset `base`.
    pub(crate) fn new(base: u32, diagnostics: &'d mut Vec<Diagnostic>) -> Self {
        Self {
            base,
            diagnostics,
            too_long: RefCell::default(),
        }
    }

    /// The span of a pair, ending at its last token: pest consumes the
    /// blanks before an optional element even when the element is absent,
    /// and those trailing blanks and comments are not part of the node.
    /// The same holds for the pair's last child (`string` in `string x`,
    /// a codel without its optional `;`), so the end is that of the last
    /// token, found by descending into the last child.
    fn span(&self, p: &P<'_>) -> Span {
        Span::new(
            self.base + to_u32(p.as_span().start()),
            self.base + to_u32(last_token_end(p)),
        )
    }

    fn ident(&self, p: &P<'_>) -> Ident {
        Ident::new(p.as_str(), self.span(p))
    }

    fn first_ident(&self, p: &P<'_>) -> Ident {
        p.clone()
            .into_inner()
            .find(|c| c.as_rule() == Rule::ident)
            .map_or_else(|| Ident::new("", self.span(p)), |c| self.ident(&c))
    }

    fn idents(&self, p: &P<'_>) -> Vec<Ident> {
        p.clone()
            .into_inner()
            .filter(|c| c.as_rule() == Rule::ident)
            .map(|c| self.ident(&c))
            .collect()
    }

    fn attributes(&mut self, p: &P<'_>) -> Vec<Attribute> {
        p.clone()
            .into_inner()
            .filter(|c| c.as_rule() == Rule::attribute)
            .filter_map(|c| self.build_attribute(c))
            .collect()
    }

    fn doc(&self, p: &P<'_>) -> Option<StrLit> {
        p.clone()
            .into_inner()
            .find(|c| c.as_rule() == Rule::string)
            .map(|c| self.build_string(&c))
    }

    /// `item` and `idl_item`.
    pub(crate) fn build_item(&mut self, p: P<'_>) -> Option<Item> {
        let item = self.build_item_inner(p);
        for span in self.too_long.take() {
            self.diagnostics
                .push(diagnostics::expression_too_long(span, MAX_OPERATORS));
        }
        item
    }

    fn build_item_inner(&mut self, p: P<'_>) -> Option<Item> {
        let inner = p.into_inner().next()?;
        Some(match inner.as_rule() {
            Rule::component => Item::Component(self.build_component(&inner)),
            Rule::include => Item::Include(self.build_include(&inner)),
            Rule::ids_block => Item::Data(self.build_data_block(&inner, DataKind::Ids)),
            Rule::export_block => Item::Data(self.build_data_block(&inner, DataKind::Export)),
            Rule::import_block => Item::Data(self.build_data_block(&inner, DataKind::Import)),
            Rule::thread => Item::Thread(self.build_thread(&inner)),
            Rule::service => Item::Service(self.build_service(&inner)),
            Rule::idl_def => self.build_idl_def(inner)?,
            _ => return None,
        })
    }

    fn build_component(&mut self, p: &P<'_>) -> Component {
        Component {
            name: self.first_ident(p),
            attributes: self.attributes(p),
            span: self.span(p),
        }
    }

    fn build_include(&self, p: &P<'_>) -> Include {
        let mut path = StrLit {
            value: String::new(),
            span: self.span(p),
        };
        let mut angle = false;
        for c in p.clone().into_inner() {
            match c.as_rule() {
                Rule::string => path = self.build_string(&c),
                Rule::angle_path => {
                    angle = true;
                    path = self.build_angle_path(&c);
                }
                _ => {}
            }
        }
        Include {
            path,
            angle,
            file: None,
            span: self.span(p),
        }
    }

    fn build_angle_path(&self, p: &P<'_>) -> StrLit {
        let value = p
            .clone()
            .into_inner()
            .find(|c| c.as_rule() == Rule::angle_content)
            .map_or_else(String::new, |c| c.as_str().to_owned());
        StrLit {
            value,
            span: self.span(p),
        }
    }

    fn build_data_block(&mut self, p: &P<'_>, kind: DataKind) -> DataBlock {
        let members = p
            .clone()
            .into_inner()
            .filter(|c| c.as_rule() == Rule::member)
            .map(|c| self.build_member(&c))
            .collect();
        DataBlock {
            kind,
            name: self.first_ident(p),
            members,
            span: self.span(p),
        }
    }

    fn build_member(&mut self, p: &P<'_>) -> Member {
        let span = self.span(p);
        let mut ty = TypeSpec::Named(ScopedName {
            absolute: false,
            parts: vec![],
            span,
        });
        let mut decl = Declarator {
            name: Ident::new("", span),
            dims: vec![],
            span,
        };
        let mut init = None;
        for c in p.clone().into_inner() {
            match c.as_rule() {
                Rule::type_spec => ty = self.build_type_spec(&c),
                Rule::declarator => decl = self.build_declarator(&c),
                Rule::field_block => init = Some(self.build_field_block(&c)),
                Rule::value => init = Some(self.build_value(&c)),
                _ => {}
            }
        }
        Member {
            ty,
            decl,
            init,
            doc: self.doc(p),
            span,
        }
    }

    fn build_field_block(&mut self, p: &P<'_>) -> Value {
        let fields = p
            .clone()
            .into_inner()
            .filter(|c| c.as_rule() == Rule::field_init)
            .map(|c| self.build_field_init(&c))
            .collect();
        Value::Fields(fields, self.span(p))
    }

    fn build_field_init(&mut self, p: &P<'_>) -> FieldInit {
        let span = self.span(p);
        let mut value = Value::List(vec![], span);
        for c in p.clone().into_inner() {
            match c.as_rule() {
                Rule::field_block => value = self.build_field_block(&c),
                Rule::value => value = self.build_value(&c),
                _ => {}
            }
        }
        FieldInit {
            name: self.first_ident(p),
            value,
            doc: self.doc(p),
            span,
        }
    }

    fn build_value(&mut self, p: &P<'_>) -> Value {
        let span = self.span(p);
        let Some(c) = p.clone().into_inner().next() else {
            return Value::List(vec![], span);
        };
        match c.as_rule() {
            Rule::number => Value::Number(self.build_number(&c)),
            Rule::string => Value::Str(self.build_string(&c)),
            Rule::boolean => Value::Bool(build_boolean(&c), span),
            Rule::composite => self.build_composite(&c),
            _ => Value::Name(self.build_scoped_name(&c)),
        }
    }

    fn build_composite(&mut self, p: &P<'_>) -> Value {
        let span = self.span(p);
        for c in p.clone().into_inner() {
            match c.as_rule() {
                Rule::field_values => return Value::Fields(self.build_field_values(&c), span),
                Rule::value_list => return Value::List(self.build_value_list(&c), span),
                _ => {}
            }
        }
        Value::List(vec![], span)
    }

    fn build_field_values(&mut self, p: &P<'_>) -> Vec<FieldInit> {
        p.clone()
            .into_inner()
            .filter(|c| c.as_rule() == Rule::field_value)
            .map(|c| self.build_field_init(&c))
            .collect()
    }

    fn build_value_list(&mut self, p: &P<'_>) -> Vec<Value> {
        p.clone()
            .into_inner()
            .filter(|c| c.as_rule() == Rule::value)
            .map(|c| self.build_value(&c))
            .collect()
    }

    fn build_thread(&mut self, p: &P<'_>) -> Thread {
        Thread {
            name: self.first_ident(p),
            attributes: self.attributes(p),
            span: self.span(p),
        }
    }

    fn build_service(&mut self, p: &P<'_>) -> Service {
        let mut service = Service {
            kind: ServiceKind::Plain,
            kind_span: None,
            name: self.first_ident(p),
            attributes: vec![],
            codels: vec![],
            span: self.span(p),
        };
        for c in p.clone().into_inner() {
            match c.as_rule() {
                Rule::service_kind => {
                    service.kind_span = Some(self.span(&c));
                    service.kind = if c.as_str() == "init" {
                        ServiceKind::Init
                    } else {
                        ServiceKind::Auto
                    };
                }
                Rule::codel => service.codels.extend(self.build_codel(&c)),
                Rule::attribute => service.attributes.extend(self.build_attribute(c)),
                _ => {}
            }
        }
        service
    }

    fn build_codel(&mut self, p: &P<'_>) -> Option<Codel> {
        let inner = p.clone().into_inner().next()?;
        let kw = inner.clone().into_inner().next()?;
        let kind = match kw.as_rule() {
            Rule::kw_start => CodelKind::Start,
            Rule::kw_control => CodelKind::Control,
            Rule::kw_exec => CodelKind::Exec,
            _ => CodelKind::Inter,
        };
        let name = match kind {
            CodelKind::Start | CodelKind::Control => self.ident(&kw),
            CodelKind::Exec | CodelKind::Inter => self.first_ident(&inner),
        };
        Some(Codel {
            kind,
            name,
            attributes: self.attributes(&inner),
            span: self.span(p),
        })
    }

    /// `attribute`: dispatches on the value shape.
    fn build_attribute(&mut self, p: P<'_>) -> Option<Attribute> {
        let span = self.span(&p);
        let inner = p.into_inner().next()?;
        let mut parts = inner.clone().into_inner();
        let name_pair = parts.next()?;
        let name = self.ident(&name_pair);
        let value = match inner.as_rule() {
            Rule::attr_string => AttrValue::Str(self.doc(&inner)?),
            Rule::attr_duration => {
                AttrValue::Duration(self.build_duration(&find(&inner, Rule::duration)?))
            }
            Rule::attr_size => AttrValue::Size(self.build_size(&find(&inner, Rule::size)?)),
            Rule::attr_integer => {
                AttrValue::Integer(self.build_integer(&find(&inner, Rule::integer)?))
            }
            Rule::attr_credentials => AttrValue::Credentials(self.idents(&inner)),
            Rule::attr_call => AttrValue::Call(self.build_call(&find(&inner, Rule::call)?)),
            Rule::attr_params => AttrValue::Params(self.build_params(&inner)),
            Rule::attr_typed => AttrValue::Typed(self.build_typed_names(&inner)),
            Rule::attr_datarefs => AttrValue::DataRefs(self.build_data_refs(&inner)),
            Rule::attr_idents => AttrValue::Idents(self.idents(&inner)),
            Rule::attr_ident => AttrValue::Ident(self.first_ident(&inner)),
            Rule::attr_word => match find(&inner, Rule::word) {
                Some(w) => AttrValue::Ident(self.ident(&w)),
                None => AttrValue::Unknown(String::new()),
            },
            _ => self.build_attr_unknown(&name, &inner),
        };
        Some(Attribute { name, value, span })
    }

    fn build_attr_unknown(&mut self, name: &Ident, p: &P<'_>) -> AttrValue {
        self.diagnostics.push(diagnostics::unknown_attribute(name));
        let text =
            find(p, Rule::unknown_value).map_or_else(String::new, |c| c.as_str().trim().to_owned());
        AttrValue::Unknown(text)
    }

    fn build_duration(&mut self, p: &P<'_>) -> DurationLit {
        let span = self.span(p);
        let text = p.as_str().to_owned();
        let ns = match literal::duration_ns(&text) {
            Ok(ns) if ns.unsigned_abs() > genom_model::limits::MAX_DURATION_NS => {
                self.diagnostics
                    .push(diagnostics::duration_too_long(span, &text));
                None
            }
            Ok(ns) => Some(ns),
            Err(e) => {
                self.diagnostics
                    .push(diagnostics::bad_duration(span, &text, e));
                None
            }
        };
        DurationLit { ns, text, span }
    }

    fn build_size(&mut self, p: &P<'_>) -> SizeLit {
        let span = self.span(p);
        let text = p.as_str().to_owned();
        let bytes = match literal::size_bytes(&text) {
            Ok(b) => Some(b),
            Err(_) => {
                self.diagnostics
                    .push(diagnostics::literal_overflow(span, &text));
                None
            }
        };
        SizeLit { bytes, text, span }
    }

    fn build_integer(&mut self, p: &P<'_>) -> IntLit {
        let span = self.span(p);
        let value = p.as_str().parse::<i64>().ok();
        if value.is_none() {
            self.diagnostics
                .push(diagnostics::literal_overflow(span, p.as_str()));
        }
        IntLit { value, span }
    }

    fn build_call(&self, p: &P<'_>) -> Call {
        let args = p
            .clone()
            .into_inner()
            .filter(|c| c.as_rule() == Rule::argument)
            .map(|c| self.build_argument(&c))
            .collect();
        Call {
            function: self.first_ident(p),
            args,
            span: self.span(p),
        }
    }

    fn build_argument(&self, p: &P<'_>) -> Argument {
        let is_const = p
            .clone()
            .into_inner()
            .any(|c| c.as_rule() == Rule::kw_const);
        let data =
            find(p, Rule::data_ref).map_or_else(|| self.empty_ref(p), |c| self.build_data_ref(&c));
        Argument {
            is_const,
            data,
            span: self.span(p),
        }
    }

    fn empty_ref(&self, p: &P<'_>) -> DataRef {
        DataRef {
            root: Ident::new("", self.span(p)),
            path: vec![],
            span: self.span(p),
        }
    }

    fn build_data_ref(&self, p: &P<'_>) -> DataRef {
        let mut data = self.empty_ref(p);
        let mut first = true;
        for c in p.clone().into_inner() {
            match c.as_rule() {
                Rule::ident if first => {
                    data.root = self.ident(&c);
                    first = false;
                }
                Rule::ident => data.path.push(PathElem::Field(self.ident(&c))),
                Rule::integer => {
                    let n = c.as_str().parse::<u64>().unwrap_or(u64::MAX);
                    data.path.push(PathElem::Index(n, self.span(&c)));
                }
                _ => {}
            }
        }
        data
    }

    fn build_data_refs(&self, p: &P<'_>) -> Vec<DataRef> {
        p.clone()
            .into_inner()
            .filter(|c| c.as_rule() == Rule::data_ref)
            .map(|c| self.build_data_ref(&c))
            .collect()
    }

    fn build_params(&mut self, p: &P<'_>) -> Vec<Param> {
        p.clone()
            .into_inner()
            .filter(|c| c.as_rule() == Rule::param)
            .map(|c| self.build_param(&c))
            .collect()
    }

    fn build_param(&mut self, p: &P<'_>) -> Param {
        let span = self.span(p);
        let mut target = ParamTarget::Data(self.empty_ref(p));
        let mut default = None;
        for c in p.clone().into_inner() {
            match c.as_rule() {
                Rule::typed_param => target = self.build_typed_param(&c),
                Rule::data_ref => target = ParamTarget::Data(self.build_data_ref(&c)),
                Rule::value => default = Some(self.build_value(&c)),
                _ => {}
            }
        }
        Param {
            target,
            default,
            doc: self.doc(p),
            span,
        }
    }

    fn build_string(&self, p: &P<'_>) -> StrLit {
        let raw = find(p, Rule::string_content).map_or("", |c| c.as_str());
        StrLit {
            value: literal::unescape(raw),
            span: self.span(p),
        }
    }

    fn build_number(&self, p: &P<'_>) -> NumberLit {
        NumberLit {
            value: literal::number(p.as_str()),
            text: p.as_str().to_owned(),
            span: self.span(p),
        }
    }
}

/// The local end of the last token of a pair (atomic pairs have no
/// children and no trailing blanks).
fn last_token_end(p: &P<'_>) -> usize {
    let mut last = p.clone();
    while let Some(child) = last.clone().into_inner().last() {
        last = child;
    }
    last.as_span().end()
}

fn find<'i>(p: &P<'i>, rule: Rule) -> Option<P<'i>> {
    p.clone().into_inner().find(|c| c.as_rule() == rule)
}

fn build_boolean(p: &P<'_>) -> bool {
    p.as_str().eq_ignore_ascii_case("true")
}

/// Converts a byte offset to `u32` (files over 4 GiB are refused earlier).
pub(crate) fn to_u32(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}
