//! Builds the [`crate::ast`] nodes from pest pairs. The grammar guarantees
//! the shape of each pair, so a missing child only happens on a grammar bug;
//! it then yields an empty name or a zero literal rather than a panic.

use genom_model::Span;
use pest::iterators::{Pair, Pairs};

use crate::ast::*;
use crate::grammar::Rule;

/// Converts pairs of one file: `base` is the global offset of the parsed
/// text's first byte.
pub(crate) struct Builder {
    pub(crate) base: u32,
}

type P<'i> = Pair<'i, Rule>;

fn u32_of(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

fn kids<'i>(p: &P<'i>) -> Pairs<'i, Rule> {
    p.clone().into_inner()
}

fn is_punct(r: Rule) -> bool {
    matches!(
        r,
        Rule::semi
            | Rule::comma
            | Rule::colon
            | Rule::coloncolon
            | Rule::lbrace
            | Rule::rbrace
            | Rule::lparen
            | Rule::rparen
            | Rule::lbracket
            | Rule::rbracket
            | Rule::langle
            | Rule::rangle
            | Rule::equals
            | Rule::dot
    )
}

/// The meaningful children (punctuation dropped).
fn parts<'i>(p: &P<'i>) -> Vec<P<'i>> {
    kids(p).filter(|c| !is_punct(c.as_rule())).collect()
}

/// Unescapes a C string or character literal body (quotes removed).
pub(crate) fn unescape(body: &str) -> String {
    let mut out = String::new();
    let mut chars = body.chars();
    while let Some(c) = chars.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        match chars.next() {
            Some('n') => out.push('\n'),
            Some('t') => out.push('\t'),
            Some('r') => out.push('\r'),
            Some('0') => out.push('\0'),
            Some(other) => out.push(other),
            None => {}
        }
    }
    out
}

impl Builder {
    fn span(&self, p: &P<'_>) -> Span {
        let s = p.as_span();
        Span::new(self.base + u32_of(s.start()), self.base + u32_of(s.end()))
    }

    fn ident(&self, p: &P<'_>) -> Ident {
        Ident {
            name: p.as_str().split_whitespace().collect::<Vec<_>>().join(""),
            span: self.span(p),
        }
    }

    /// A top-level statement.
    pub(crate) fn statement(&self, p: &P<'_>) -> Option<Statement> {
        let inner = kids(p).next()?;
        match inner.as_rule() {
            Rule::component | Rule::interface => Some(Statement::Component(self.component(&inner))),
            Rule::idl_statement => self.idl_statement(&inner).map(Statement::Idl),
            _ => None,
        }
    }

    fn component(&self, p: &P<'_>) -> Component {
        let mut name = None;
        let mut body = Vec::new();
        for c in parts(p) {
            match c.as_rule() {
                Rule::identifier => name = Some(self.ident(&c)),
                Rule::body => body = parts(&c).iter().filter_map(|e| self.export(e)).collect(),
                _ => {}
            }
        }
        Component {
            is_interface: p.as_rule() == Rule::interface,
            name: name.unwrap_or_else(|| self.ident(p)),
            span: self.span(p),
            body,
        }
    }

    fn export(&self, p: &P<'_>) -> Option<Export> {
        let inner = kids(p).next()?;
        Some(match inner.as_rule() {
            Rule::ids => {
                let members = parts(&inner)
                    .iter()
                    .find(|c| c.as_rule() == Rule::member_list)
                    .map(|m| self.members(m))
                    .unwrap_or_default();
                Export::Ids(members, self.span(&inner))
            }
            Rule::task => {
                let ps = parts(&inner);
                Export::Task(Task {
                    name: ps.get(1).map(|n| self.ident(n))?,
                    properties: self.properties_in(&ps),
                })
            }
            Rule::port => Export::Port(self.port(&inner)?),
            Rule::attribute | Rule::service => Export::Service(self.service(&inner)?),
            Rule::property => Export::Property(self.property(&inner)?),
            Rule::idl_statement => Export::Idl(self.idl_statement(&inner)?),
            _ => return None,
        })
    }

    fn properties_in(&self, ps: &[P<'_>]) -> Vec<Property> {
        ps.iter()
            .filter(|c| c.as_rule() == Rule::properties)
            .flat_map(|c| parts(c))
            .filter_map(|c| self.property(&c))
            .collect()
    }

    fn port(&self, p: &P<'_>) -> Option<Port> {
        let ps = parts(p);
        let multiple = ps.iter().any(|c| c.as_rule() == Rule::kw_multiple);
        let dir = ps.iter().find(|c| c.as_rule() == Rule::port_dir)?;
        let dir = if dir.as_str().trim() == "in" {
            PortDir::In
        } else {
            PortDir::Out
        };
        let ty = ps.iter().find(|c| c.as_rule() == Rule::type_spec)?;
        let name = ps.iter().find(|c| c.as_rule() == Rule::identifier)?;
        Some(Port {
            name: self.ident(name),
            multiple,
            dir,
            ty: self.type_spec(ty)?,
            properties: self.properties_in(&ps),
        })
    }

    fn service(&self, p: &P<'_>) -> Option<Service> {
        let ps = parts(p);
        let kind = match p.as_rule() {
            Rule::attribute => ServiceKind::Attribute,
            _ if p.as_str().starts_with("function") => ServiceKind::Function,
            _ => ServiceKind::Activity,
        };
        let name = ps.iter().find(|c| c.as_rule() == Rule::identifier)?;
        let params = ps
            .iter()
            .filter(|c| matches!(c.as_rule(), Rule::attribute_param | Rule::service_param))
            .filter_map(|c| self.service_param(c))
            .collect();
        Some(Service {
            kind,
            name: self.ident(name),
            params,
            properties: self.properties_in(&ps),
            span: self.span(p),
        })
    }

    fn dir(p: &P<'_>) -> Dir {
        match p.as_str().trim() {
            "out" => Dir::Out,
            "inout" => Dir::InOut,
            _ => Dir::In,
        }
    }

    fn service_param(&self, p: &P<'_>) -> Option<ServiceParam> {
        let mut out = ServiceParam {
            dir: Dir::In,
            ty: None,
            path: None,
            dims: Vec::new(),
            rename: None,
            init: None,
            span: self.span(p),
        };
        for c in parts(p) {
            match c.as_rule() {
                Rule::param_dir => out.dir = Self::dir(&c),
                Rule::type_spec => out.ty = self.type_spec(&c),
                Rule::declarator => {
                    let d = self.declarator(&c);
                    out.path = Some(MemberPath {
                        span: d.name.span,
                        root: d.name,
                        steps: Vec::new(),
                    });
                    out.dims = d.dims;
                }
                Rule::param_variable => out.path = Some(self.path(&c)),
                Rule::identifier => out.rename = Some(self.ident(&c)),
                Rule::opt_initializer => {
                    out.init = parts(&c).first().map(|i| self.initializer(i));
                }
                _ => {}
            }
        }
        Some(out)
    }

    fn path(&self, p: &P<'_>) -> MemberPath {
        let mut ps = parts(p).into_iter();
        let root = ps.next().map_or_else(|| self.ident(p), |r| self.ident(&r));
        let steps = ps
            .map(|c| match c.as_rule() {
                Rule::identifier => PathStep::Field(self.ident(&c)),
                _ => PathStep::Index(self.expr(&c)),
            })
            .collect();
        MemberPath {
            root,
            steps,
            span: self.span(p),
        }
    }

    fn initializer(&self, p: &P<'_>) -> Initializer {
        let mut out = Initializer {
            value: None,
            doc: None,
            span: self.span(p),
        };
        for c in parts(p) {
            match c.as_rule() {
                Rule::strings => out.doc = Some(self.strings(&c)),
                Rule::initializer_value => out.value = Some(self.init_value(&c)),
                _ => {}
            }
        }
        out
    }

    fn init_value(&self, p: &P<'_>) -> InitValue {
        let all: Vec<P<'_>> = kids(p).collect();
        let first = all.first().map(P::as_rule);
        let ps = parts(p);
        let rest = |from: usize| -> Option<Box<InitValue>> {
            let tail: Vec<&P<'_>> = ps.iter().skip(from).collect();
            match tail.first() {
                None => None,
                Some(c) if c.as_rule() == Rule::const_expr => {
                    Some(Box::new(InitValue::Expr(self.expr(c))))
                }
                Some(_) => Some(Box::new(InitValue::List(
                    tail.iter().map(|c| self.initializer(c)).collect(),
                ))),
            }
        };
        match first {
            Some(Rule::lbrace) => InitValue::List(ps.iter().map(|c| self.initializer(c)).collect()),
            Some(Rule::lbracket) => match ps.first() {
                Some(i) => InitValue::Index(self.expr(i), rest(1)),
                None => InitValue::List(Vec::new()),
            },
            Some(Rule::dot) => match ps.first() {
                Some(f) => InitValue::Field(self.ident(f), rest(1)),
                None => InitValue::List(Vec::new()),
            },
            _ => match ps.first() {
                Some(e) => InitValue::Expr(self.expr(e)),
                None => InitValue::List(Vec::new()),
            },
        }
    }

    fn strings(&self, p: &P<'_>) -> String {
        kids(p)
            .map(|s| {
                let t = s.as_str();
                unescape(t.get(1..t.len().saturating_sub(1)).unwrap_or(""))
            })
            .collect()
    }

    fn idents(&self, p: Option<&P<'_>>) -> Vec<Ident> {
        p.map(|l| parts(l).iter().map(|i| self.ident(i)).collect())
            .unwrap_or_default()
    }

    fn time_unit(ps: &[P<'_>]) -> Option<TimeUnit> {
        ps.iter()
            .find(|c| c.as_rule() == Rule::time_unit)
            .map(|u| match u.as_str() {
                "s" => TimeUnit::S,
                "ms" => TimeUnit::Ms,
                _ => TimeUnit::Us,
            })
    }

    fn property(&self, p: &P<'_>) -> Option<Property> {
        let inner = kids(p).next()?;
        let ps = parts(&inner);
        let arg = ps.get(1);
        let string = || arg.map(|s| self.strings(s)).unwrap_or_default();
        let list = || {
            arg.map(|l| parts(l).iter().map(|s| self.strings(s)).collect())
                .unwrap_or_default()
        };
        let expr = || arg.map(|e| self.expr(e));
        let kind = match inner.as_rule() {
            Rule::prop_doc => PropertyKind::Doc(string()),
            Rule::prop_version => PropertyKind::Version(string()),
            Rule::prop_lang => PropertyKind::Lang(string()),
            Rule::prop_email => PropertyKind::Email(string()),
            Rule::prop_require => PropertyKind::Require(list()),
            Rule::prop_codels_require => PropertyKind::CodelsRequire(list()),
            Rule::prop_clock_rate => PropertyKind::ClockRate(expr()?, Self::time_unit(&ps)),
            Rule::prop_provides => PropertyKind::Provides(self.idents(arg)),
            Rule::prop_uses => PropertyKind::Uses(self.idents(arg)),
            Rule::prop_extends => PropertyKind::Extends(self.idents(arg)),
            Rule::prop_period => PropertyKind::Period(expr()?, Self::time_unit(&ps)),
            Rule::prop_delay => PropertyKind::Delay(expr()?, Self::time_unit(&ps)),
            Rule::prop_priority => PropertyKind::Priority(expr()?),
            Rule::prop_scheduling => PropertyKind::SchedulingRealTime,
            Rule::prop_stack => {
                let mult = match ps.iter().find(|c| c.as_rule() == Rule::size_unit) {
                    Some(u) if u.as_str() == "k" => 1024,
                    Some(_) => 1024 * 1024,
                    None => 1,
                };
                PropertyKind::Stack(expr()?, mult)
            }
            Rule::prop_task => PropertyKind::Task(self.ident(arg?)),
            Rule::prop_interrupts => PropertyKind::Interrupts(self.idents(arg)),
            Rule::prop_before => PropertyKind::Before(self.idents(arg)),
            Rule::prop_after => PropertyKind::After(self.idents(arg)),
            Rule::prop_throws => {
                PropertyKind::Throws(ps.iter().skip(1).map(|n| self.ident(n)).collect())
            }
            Rule::prop_validate => {
                PropertyKind::Validate(self.codel(false, &[], arg?, None, self.span(&inner)))
            }
            Rule::prop_local => {
                let ty = self.type_spec(arg?)?;
                let decls = ps.iter().skip(2).map(|d| self.declarator(d)).collect();
                PropertyKind::Local(ty, decls)
            }
            Rule::prop_codel => {
                let is_async = ps.iter().any(|c| c.as_rule() == Rule::kw_async);
                let body = ps
                    .iter()
                    .find(|c| matches!(c.as_rule(), Rule::fsm_codel | Rule::codel_call))?;
                let span = self.span(&inner);
                if body.as_rule() == Rule::codel_call {
                    PropertyKind::Codel(self.codel(is_async, &[], body, None, span))
                } else {
                    let fs = parts(body);
                    let states = self.events(fs.first());
                    let call = fs.iter().find(|c| c.as_rule() == Rule::codel_call)?;
                    let yields = self.events(fs.last());
                    PropertyKind::Codel(self.codel(is_async, &states, call, Some(yields), span))
                }
            }
            _ => return None,
        };
        Some(Property {
            kind,
            span: self.span(&inner),
        })
    }

    fn events(&self, p: Option<&P<'_>>) -> Vec<Event> {
        let Some(p) = p.filter(|p| p.as_rule() == Rule::event_list) else {
            return Vec::new();
        };
        parts(p)
            .iter()
            .map(|e| {
                let ps = parts(e);
                Event {
                    pause: ps.iter().any(|c| c.as_rule() == Rule::kw_pause),
                    name: ps.last().map_or_else(|| self.ident(e), |n| self.ident(n)),
                }
            })
            .collect()
    }

    fn codel(
        &self,
        is_async: bool,
        states: &[Event],
        call: &P<'_>,
        yields: Option<Vec<Event>>,
        span: Span,
    ) -> Codel {
        let ps = parts(call);
        let function = ps
            .first()
            .map_or_else(|| self.ident(call), |f| self.ident(f));
        let params = ps.iter().skip(1).map(|c| self.codel_param(c)).collect();
        Codel {
            is_async,
            states: states.to_vec(),
            function,
            params,
            yields: yields.unwrap_or_default(),
            span,
        }
    }

    fn codel_param(&self, p: &P<'_>) -> CodelParam {
        let mut out = CodelParam {
            src: None,
            dir: Dir::In,
            path: None,
            rename: None,
            span: self.span(p),
        };
        for c in parts(p) {
            match c.as_rule() {
                Rule::param_src => {
                    out.src = Some(match c.as_str() {
                        "ids" => Source::Ids,
                        "local" => Source::Local,
                        "port" => Source::Port,
                        _ => Source::Remote,
                    });
                }
                Rule::param_dir => out.dir = Self::dir(&c),
                Rule::param_variable => out.path = Some(self.path(&c)),
                Rule::identifier => out.rename = Some(self.ident(&c)),
                _ => {}
            }
        }
        out
    }

    // ------------------------------------------------------------ IDL

    pub(crate) fn idl_statement(&self, p: &P<'_>) -> Option<IdlDef> {
        let inner = kids(p).next()?;
        let ps = parts(&inner);
        match inner.as_rule() {
            Rule::module => {
                let name = self.ident(ps.get(1)?);
                let defs = ps
                    .iter()
                    .filter(|c| c.as_rule() == Rule::idl_statement)
                    .filter_map(|c| self.idl_statement(c))
                    .collect();
                Some(IdlDef::Module(name, defs))
            }
            Rule::const_dcl => Some(IdlDef::Const(
                self.type_spec(ps.get(1)?)?,
                self.ident(ps.get(2)?),
                self.expr(ps.get(3)?),
            )),
            Rule::type_dcl => self.type_dcl(ps.first()?),
            _ => None,
        }
    }

    fn type_dcl(&self, p: &P<'_>) -> Option<IdlDef> {
        let ps = parts(p);
        match p.as_rule() {
            Rule::typedef_dcl => Some(IdlDef::Typedef(
                self.type_spec(ps.get(1)?)?,
                ps.iter().skip(2).map(|d| self.declarator(d)).collect(),
            )),
            Rule::native_dcl => Some(IdlDef::Native(self.ident(ps.get(1)?))),
            Rule::exception_dcl => Some(IdlDef::Exception(
                ps.iter()
                    .skip(1)
                    .filter_map(|e| {
                        let es = parts(e);
                        let members = es.get(1).map(|m| self.members(m)).unwrap_or_default();
                        Some((self.ident(es.first()?), members))
                    })
                    .collect(),
            )),
            Rule::constructed_type => Some(IdlDef::Type(self.constructed(p)?)),
            Rule::forward_dcl => Some(IdlDef::Forward(self.ident(ps.get(1)?))),
            _ => None,
        }
    }

    fn members(&self, p: &P<'_>) -> Vec<Member> {
        parts(p).iter().filter_map(|m| self.member(m)).collect()
    }

    fn member(&self, p: &P<'_>) -> Option<Member> {
        let ps = parts(p);
        Some(Member {
            ty: self.type_spec(ps.first()?)?,
            decls: ps.iter().skip(1).map(|d| self.declarator(d)).collect(),
        })
    }

    fn declarator(&self, p: &P<'_>) -> Declarator {
        let ps = parts(p);
        Declarator {
            name: ps.first().map_or_else(|| self.ident(p), |n| self.ident(n)),
            dims: ps.iter().skip(1).map(|e| self.expr(e)).collect(),
        }
    }

    pub(crate) fn type_spec(&self, p: &P<'_>) -> Option<TypeSpec> {
        let inner = kids(p).next()?;
        let span = self.span(&inner);
        match inner.as_rule() {
            Rule::base_type => Some(TypeSpec::Base(
                inner
                    .as_str()
                    .split_whitespace()
                    .collect::<Vec<_>>()
                    .join(" "),
                span,
            )),
            Rule::scoped_name => Some(TypeSpec::Named(self.ident(&inner))),
            Rule::constructed_type => self.constructed(&inner),
            Rule::template_type => {
                let ps = parts(&inner);
                let head = ps.first()?;
                Some(match head.as_rule() {
                    Rule::kw_sequence => TypeSpec::Sequence(
                        Box::new(self.type_spec(ps.get(1)?)?),
                        ps.get(2).map(|e| self.expr(e)),
                        span,
                    ),
                    Rule::kw_optional => {
                        TypeSpec::Optional(Box::new(self.type_spec(ps.get(1)?)?), span)
                    }
                    Rule::kw_string => TypeSpec::String(ps.get(1).map(|e| self.expr(e)), span),
                    _ => TypeSpec::Fixed(span),
                })
            }
            _ => None,
        }
    }

    fn constructed(&self, p: &P<'_>) -> Option<TypeSpec> {
        let inner = kids(p).next()?;
        let ps = parts(&inner);
        let name = self.ident(ps.get(1)?);
        match inner.as_rule() {
            Rule::struct_type => Some(TypeSpec::Struct(name, self.members(ps.get(2)?))),
            Rule::enum_type => Some(TypeSpec::Enum(
                name,
                ps.iter().skip(2).map(|e| self.ident(e)).collect(),
            )),
            Rule::union_type => {
                let switch = self.type_spec(ps.get(3)?)?;
                let cases = ps
                    .iter()
                    .skip(4)
                    .filter(|c| c.as_rule() == Rule::union_case)
                    .filter_map(|c| {
                        let cs = parts(c);
                        let labels = cs
                            .iter()
                            .filter(|l| l.as_rule() == Rule::case_label)
                            .map(|l| parts(l).get(1).map(|e| self.expr(e)))
                            .collect();
                        let ty = cs.iter().find(|t| t.as_rule() == Rule::type_spec)?;
                        let decl = cs.iter().find(|t| t.as_rule() == Rule::declarator)?;
                        Some((
                            labels,
                            Member {
                                ty: self.type_spec(ty)?,
                                decls: vec![self.declarator(decl)],
                            },
                        ))
                    })
                    .collect();
                Some(TypeSpec::Union(name, Box::new(switch), cases))
            }
            _ => None,
        }
    }

    // ------------------------------------------------------------ expressions

    pub(crate) fn expr(&self, p: &P<'_>) -> Expr {
        self.expr_at(p, 0)
    }

    /// [`Builder::expr`] at `depth` parentheses: an expression of more than
    /// [`MAX_TERMS`] terms or [`MAX_NESTING`] levels is `TooComplex`, so
    /// that building, evaluating and dropping it never recurse deeply.
    fn expr_at(&self, p: &P<'_>, depth: usize) -> Expr {
        // const_expr = unary (binop unary)*: precedence climbing.
        let items: Vec<P<'_>> = kids(p).collect();
        if depth > MAX_NESTING || items.len() > 2 * MAX_TERMS {
            return Expr {
                kind: ExprKind::TooComplex,
                span: self.span(p),
            };
        }
        let mut operands = Vec::new();
        let mut ops = Vec::new();
        for it in &items {
            match it.as_rule() {
                Rule::binop => ops.push(binop(it.as_str())),
                _ => operands.push(self.unary(it, depth)),
            }
        }
        let mut operands = operands.into_iter();
        let Some(first) = operands.next() else {
            return Expr {
                kind: ExprKind::Int(0),
                span: self.span(p),
            };
        };
        let rest: Vec<(&'static str, Expr)> = ops.into_iter().zip(operands).collect();
        let mut rest = rest.into_iter().peekable();
        climb(first, &mut rest, 0)
    }

    fn unary(&self, p: &P<'_>, depth: usize) -> Expr {
        let span = self.span(p);
        let ps: Vec<P<'_>> = kids(p).collect();
        let (op, prim) = match ps.as_slice() {
            [op, prim] => (op.as_str().chars().next(), prim),
            [prim] => (None, prim),
            _ => {
                return Expr {
                    kind: ExprKind::Int(0),
                    span,
                };
            }
        };
        let e = self.primary(prim, depth);
        match op {
            Some(op) => Expr {
                kind: ExprKind::Unary(op, Box::new(e)),
                span,
            },
            None => e,
        }
    }

    fn primary(&self, p: &P<'_>, depth: usize) -> Expr {
        let span = self.span(p);
        let ps = parts(p);
        let kind = match ps.first() {
            Some(c) if c.as_rule() == Rule::const_expr => return self.expr_at(c, depth + 1),
            Some(c) if c.as_rule() == Rule::scoped_name => ExprKind::Name(self.ident(c).name),
            Some(lit) => match kids(lit).next() {
                Some(l) => literal(&l, self),
                None => ExprKind::Int(0),
            },
            None => ExprKind::Int(0),
        };
        Expr { kind, span }
    }
}

fn literal(l: &P<'_>, b: &Builder) -> ExprKind {
    let t = l.as_str();
    match l.as_rule() {
        Rule::kw_true => ExprKind::Bool(true),
        Rule::kw_false => ExprKind::Bool(false),
        Rule::integer_lit => {
            let digits = t.trim_end_matches(['u', 'U', 'l', 'L']);
            let v = if let Some(h) = digits
                .strip_prefix("0x")
                .or_else(|| digits.strip_prefix("0X"))
            {
                i128::from_str_radix(h, 16)
            } else if digits.len() > 1 && digits.starts_with('0') {
                i128::from_str_radix(&digits[1..], 8)
            } else {
                digits.parse()
            };
            v.map_or_else(|_| ExprKind::OutOfRange(t.to_owned()), ExprKind::Int)
        }
        Rule::float_lit => {
            let v: Option<f64> = t
                .trim_end_matches(['f', 'F', 'l', 'L', 'd', 'D'])
                .parse()
                .ok()
                .filter(|f: &f64| f.is_finite());
            v.map_or_else(|| ExprKind::OutOfRange(t.to_owned()), ExprKind::Float)
        }
        Rule::char_lit => {
            let body = unescape(t.get(1..t.len().saturating_sub(1)).unwrap_or(""));
            ExprKind::Char(body.chars().next().unwrap_or('\0'))
        }
        _ => ExprKind::Str(b.strings(l)),
    }
}

fn binop(s: &str) -> &'static str {
    match s {
        "<<" => "<<",
        ">>" => ">>",
        "|" => "|",
        "^" => "^",
        "&" => "&",
        "+" => "+",
        "-" => "-",
        "*" => "*",
        "/" => "/",
        _ => "%",
    }
}

fn precedence(op: &str) -> u8 {
    match op {
        "|" => 1,
        "^" => 2,
        "&" => 3,
        "<<" | ">>" => 4,
        "+" | "-" => 5,
        _ => 6,
    }
}

/// The most terms of one constant expression.
const MAX_TERMS: usize = 4096;

/// The most nested parentheses of one constant expression.
const MAX_NESTING: usize = 256;

fn climb(
    mut lhs: Expr,
    rest: &mut std::iter::Peekable<std::vec::IntoIter<(&'static str, Expr)>>,
    min: u8,
) -> Expr {
    while let Some((op, _)) = rest.peek() {
        let prec = precedence(op);
        if prec < min {
            break;
        }
        let Some((op, mut rhs)) = rest.next() else {
            break;
        };
        while let Some((next, _)) = rest.peek() {
            if precedence(next) > prec {
                rhs = climb(rhs, rest, prec + 1);
            } else {
                break;
            }
        }
        let span = lhs.span.to(rhs.span);
        lhs = Expr {
            kind: ExprKind::Binary(op, Box::new(lhs), Box::new(rhs)),
            span,
        };
    }
    lhs
}
