//! The GenoM3 syntax tree: one [`FileAst`] per loaded file (so spans stay in
//! their file), built from the pest parse in `build.rs`. Every node carries
//! its global [`Span`]. Nothing here is resolved: names are as written.

use genom_model::{FileId, Span};

/// A name with the span where it is written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Ident {
    /// The name (for a scoped name, as written: `m::t`, `::t`).
    pub name: String,
    /// Where it is written.
    pub span: Span,
}

/// The statements of one file, and where it includes other files.
#[derive(Debug, Clone, Default)]
pub struct FileAst {
    /// Its top-level statements in source order.
    pub statements: Vec<Statement>,
}

/// Every parsed file of one load, in load order.
#[derive(Debug, Clone, Default)]
pub struct Ast {
    /// Top-level statements of every file, in the order a C preprocessor
    /// would see them (an included file's statements at its `#include`).
    pub statements: Vec<(FileId, Statement)>,
}

/// A top-level statement.
#[derive(Debug, Clone)]
pub enum Statement {
    /// `component` or `interface`.
    Component(Component),
    /// An IDL definition.
    Idl(IdlDef),
}

/// A `component` or an `interface`.
#[derive(Debug, Clone)]
pub struct Component {
    /// True for `interface`.
    pub is_interface: bool,
    /// Its name.
    pub name: Ident,
    /// The whole statement.
    pub span: Span,
    /// Its body, in source order.
    pub body: Vec<Export>,
}

/// One element of a component or interface body.
#[derive(Debug, Clone)]
pub enum Export {
    /// `ids { ... };`
    Ids(Vec<Member>, Span),
    /// `task`.
    Task(Task),
    /// `port`.
    Port(Port),
    /// `attribute`, `function` or `activity`.
    Service(Service),
    /// A component property.
    Property(Property),
    /// An IDL definition scoped in the component.
    Idl(IdlDef),
}

/// `task NAME { ... };`
#[derive(Debug, Clone)]
pub struct Task {
    /// Its name.
    pub name: Ident,
    /// Its properties.
    pub properties: Vec<Property>,
}

/// `in` or `out`, of a port.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum PortDir {
    /// `in`
    In,
    /// `out`
    Out,
}

/// `port [multiple] in|out TYPE NAME;`
#[derive(Debug, Clone)]
pub struct Port {
    /// Its name.
    pub name: Ident,
    /// `multiple`.
    pub multiple: bool,
    /// Direction.
    pub dir: PortDir,
    /// Data type.
    pub ty: TypeSpec,
    /// Its properties (only `doc` is allowed; others are reported).
    pub properties: Vec<Property>,
}

/// The three kinds of services.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum ServiceKind {
    /// `attribute`
    Attribute,
    /// `function`
    Function,
    /// `activity`
    Activity,
}

/// `attribute|function|activity NAME(params) { ... };`
#[derive(Debug, Clone)]
pub struct Service {
    /// Which kind.
    pub kind: ServiceKind,
    /// Its name.
    pub name: Ident,
    /// Its parameters.
    pub params: Vec<ServiceParam>,
    /// Its properties.
    pub properties: Vec<Property>,
    /// The whole declaration.
    pub span: Span,
}

/// Direction of a parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Dir {
    /// `in`
    In,
    /// `out`
    Out,
    /// `inout`
    InOut,
}

/// A service or attribute parameter.
#[derive(Debug, Clone)]
pub struct ServiceParam {
    /// Direction.
    pub dir: Dir,
    /// The declared type (service parameters) or `None` (attribute
    /// parameters, typed by the ids member they name).
    pub ty: Option<TypeSpec>,
    /// The ids member path (attribute parameters) or the declared name
    /// (service parameters, as a one-element path).
    pub path: Option<MemberPath>,
    /// Array sizes of a service parameter's declarator.
    pub dims: Vec<Expr>,
    /// `::name` rename.
    pub rename: Option<Ident>,
    /// `= value : "doc"`.
    pub init: Option<Initializer>,
    /// The whole parameter.
    pub span: Span,
}

impl ServiceParam {
    /// The parameter's name: the rename, else the last element of its path.
    pub fn name(&self) -> Option<&Ident> {
        self.rename
            .as_ref()
            .or_else(|| self.path.as_ref().map(MemberPath::last))
    }
}

/// `a.b[2]`.
#[derive(Debug, Clone)]
pub struct MemberPath {
    /// The first name.
    pub root: Ident,
    /// Following steps.
    pub steps: Vec<PathStep>,
    /// The whole path.
    pub span: Span,
}

impl MemberPath {
    /// The last named element.
    pub fn last(&self) -> &Ident {
        self.steps
            .iter()
            .rev()
            .find_map(|s| match s {
                PathStep::Field(f) => Some(f),
                PathStep::Index(_) => None,
            })
            .unwrap_or(&self.root)
    }
}

/// One step of a member path.
#[derive(Debug, Clone)]
pub enum PathStep {
    /// `.field`
    Field(Ident),
    /// `[expr]`
    Index(Expr),
}

/// `= value : "doc"` (either part may be missing).
#[derive(Debug, Clone)]
pub struct Initializer {
    /// The value.
    pub value: Option<InitValue>,
    /// The documentation string.
    pub doc: Option<String>,
    /// Where it is written.
    pub span: Span,
}

/// An initializer value.
#[derive(Debug, Clone)]
pub enum InitValue {
    /// A constant expression.
    Expr(Expr),
    /// `{ a, b }`
    List(Vec<Initializer>),
    /// `[i] = v`
    Index(Expr, Option<Box<InitValue>>),
    /// `.f = v`
    Field(Ident, Option<Box<InitValue>>),
}

/// A property and where it is written.
#[derive(Debug, Clone)]
pub struct Property {
    /// What it says.
    pub kind: PropertyKind,
    /// The whole property.
    pub span: Span,
}

/// Time units of `period`, `delay` and `clock-rate`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimeUnit {
    /// `s`
    S,
    /// `ms`
    Ms,
    /// `us`
    Us,
}

/// The properties of GenoM3.
#[derive(Debug, Clone)]
pub enum PropertyKind {
    /// `doc`
    Doc(String),
    /// `version`
    Version(String),
    /// `lang`
    Lang(String),
    /// `email`
    Email(String),
    /// `require`
    Require(Vec<String>),
    /// `codels-require`
    CodelsRequire(Vec<String>),
    /// `clock-rate`
    ClockRate(Expr, Option<TimeUnit>),
    /// `provides`
    Provides(Vec<Ident>),
    /// `uses`
    Uses(Vec<Ident>),
    /// `extends`
    Extends(Vec<Ident>),
    /// `period`
    Period(Expr, Option<TimeUnit>),
    /// `delay`
    Delay(Expr, Option<TimeUnit>),
    /// `priority`
    Priority(Expr),
    /// `scheduling real-time`
    SchedulingRealTime,
    /// `stack N [k|M]` (multiplier 1, 1024 or 1024²)
    Stack(Expr, u64),
    /// `task` (of a service)
    Task(Ident),
    /// `interrupts`
    Interrupts(Vec<Ident>),
    /// `before`
    Before(Vec<Ident>),
    /// `after`
    After(Vec<Ident>),
    /// `validate`
    Validate(Codel),
    /// `local`
    Local(TypeSpec, Vec<Declarator>),
    /// `codel`
    Codel(Codel),
    /// `throws`
    Throws(Vec<Ident>),
}

impl PropertyKind {
    /// The keyword that introduces the property.
    pub fn keyword(&self) -> &'static str {
        match self {
            PropertyKind::Doc(_) => "doc",
            PropertyKind::Version(_) => "version",
            PropertyKind::Lang(_) => "lang",
            PropertyKind::Email(_) => "email",
            PropertyKind::Require(_) => "require",
            PropertyKind::CodelsRequire(_) => "codels-require",
            PropertyKind::ClockRate(..) => "clock-rate",
            PropertyKind::Provides(_) => "provides",
            PropertyKind::Uses(_) => "uses",
            PropertyKind::Extends(_) => "extends",
            PropertyKind::Period(..) => "period",
            PropertyKind::Delay(..) => "delay",
            PropertyKind::Priority(_) => "priority",
            PropertyKind::SchedulingRealTime => "scheduling",
            PropertyKind::Stack(..) => "stack",
            PropertyKind::Task(_) => "task",
            PropertyKind::Interrupts(_) => "interrupts",
            PropertyKind::Before(_) => "before",
            PropertyKind::After(_) => "after",
            PropertyKind::Validate(_) => "validate",
            PropertyKind::Local(..) => "local",
            PropertyKind::Codel(_) => "codel",
            PropertyKind::Throws(_) => "throws",
        }
    }
}

/// A codel: `[async] codel<s> f(params) yield e;`, `codel f(params);` or
/// `validate f(params);`.
#[derive(Debug, Clone)]
pub struct Codel {
    /// `async`.
    pub is_async: bool,
    /// The states it runs in (empty for a simple codel).
    pub states: Vec<Event>,
    /// The function.
    pub function: Ident,
    /// Its parameters.
    pub params: Vec<CodelParam>,
    /// The events it may yield.
    pub yields: Vec<Event>,
    /// The whole codel property.
    pub span: Span,
}

/// A state or a `pause::state` transition.
#[derive(Debug, Clone)]
pub struct Event {
    /// `pause::`.
    pub pause: bool,
    /// The state.
    pub name: Ident,
}

/// Where a codel parameter comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Source {
    /// `ids`
    Ids,
    /// `local`
    Local,
    /// `port`
    Port,
    /// `remote`
    Remote,
}

/// A codel parameter.
#[derive(Debug, Clone)]
pub struct CodelParam {
    /// The explicit source, if any.
    pub src: Option<Source>,
    /// Direction.
    pub dir: Dir,
    /// The member path (absent for `::name`).
    pub path: Option<MemberPath>,
    /// `::name`.
    pub rename: Option<Ident>,
    /// The whole parameter.
    pub span: Span,
}

// ---------------------------------------------------------------- IDL

/// An IDL definition.
#[derive(Debug, Clone)]
pub enum IdlDef {
    /// `module m { ... };`
    Module(Ident, Vec<IdlDef>),
    /// `const T n = e;`
    Const(TypeSpec, Ident, Expr),
    /// `typedef T a, b[2];`
    Typedef(TypeSpec, Vec<Declarator>),
    /// `native n;`
    Native(Ident),
    /// `exception e { members }, ...;`
    Exception(Vec<(Ident, Vec<Member>)>),
    /// `struct`, `union` or `enum` definition.
    Type(TypeSpec),
    /// `struct n;` or `union n;`.
    Forward(Ident),
}

/// `T a, b[3];`
#[derive(Debug, Clone)]
pub struct Member {
    /// The type.
    pub ty: TypeSpec,
    /// The declared names.
    pub decls: Vec<Declarator>,
}

/// `name[2][3]`
#[derive(Debug, Clone)]
pub struct Declarator {
    /// The name.
    pub name: Ident,
    /// Array sizes, outermost first.
    pub dims: Vec<Expr>,
}

/// A type specification.
#[derive(Debug, Clone)]
pub enum TypeSpec {
    /// A base type, as written with single blanks (`unsigned long`).
    Base(String, Span),
    /// A (scoped) type name.
    Named(Ident),
    /// `sequence<T[, n]>`
    Sequence(Box<TypeSpec>, Option<Expr>, Span),
    /// `optional<T>`
    Optional(Box<TypeSpec>, Span),
    /// `string[<n>]`
    String(Option<Expr>, Span),
    /// `fixed[<d, s>]`
    Fixed(Span),
    /// `struct n { members }`
    Struct(Ident, Vec<Member>),
    /// `union n switch (T) { cases }`
    Union(Ident, Box<TypeSpec>, Vec<(Vec<Option<Expr>>, Member)>),
    /// `enum n { a, b }`
    Enum(Ident, Vec<Ident>),
}

/// A constant expression.
#[derive(Debug, Clone)]
pub struct Expr {
    /// Its shape.
    pub kind: ExprKind,
    /// Where it is written.
    pub span: Span,
}

/// The shapes of constant expressions.
#[derive(Debug, Clone)]
pub enum ExprKind {
    /// An integer literal.
    Int(i128),
    /// A numeric literal no IDL type holds (as written): an error when
    /// evaluated.
    OutOfRange(String),
    /// An expression with more terms or deeper parentheses than
    /// genom-check evaluates (`MAX_TERMS`, `MAX_NESTING` of the builder):
    /// an error when evaluated; its parts are not kept (their depth would
    /// exhaust the stack).
    TooComplex,
    /// A floating-point literal.
    Float(f64),
    /// `TRUE` or `FALSE`.
    Bool(bool),
    /// A character literal.
    Char(char),
    /// String literals, concatenated.
    Str(String),
    /// A constant or enumerator name.
    Name(String),
    /// `-e`, `+e`, `~e`.
    Unary(char, Box<Expr>),
    /// `a op b` (operators: `| ^ & << >> + - * / %`).
    Binary(&'static str, Box<Expr>, Box<Expr>),
}
