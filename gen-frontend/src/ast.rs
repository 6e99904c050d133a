//! The abstract syntax tree of `.gen` and IDL files. Every node and every
//! name carries a [`Span`] in the global offset space of the
//! [`SourceMap`](genom_model::SourceMap). The tree is purely syntactic:
//! names are not resolved and attributes are kept in a generic list, so
//! that the resolver can say *where* an attribute is not allowed.

use std::fmt;

pub use genom_model::kinds::{BaseType, CodelKind, DataKind, ServiceKind};
use genom_model::{FileId, Span};

/// A name as written, with its span.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Ident {
    /// The text.
    pub name: String,
    /// Where.
    pub span: Span,
}

impl Ident {
    /// A name with its span.
    pub fn new(name: impl Into<String>, span: Span) -> Self {
        Self {
            name: name.into(),
            span,
        }
    }
}

impl fmt::Display for Ident {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name)
    }
}

/// A string literal, with escapes resolved.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StrLit {
    /// The value.
    pub value: String,
    /// Where (including the quotes).
    pub span: Span,
}

/// A possibly scoped name: `NAME`, `m::NAME`, `::m::NAME`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScopedName {
    /// Written with a leading `::`.
    pub absolute: bool,
    /// The `::`-separated parts.
    pub parts: Vec<String>,
    /// Where.
    pub span: Span,
}

impl ScopedName {
    /// The last part (the unqualified name).
    pub fn last(&self) -> &str {
        self.parts.last().map_or("", String::as_str)
    }
}

impl fmt::Display for ScopedName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.absolute {
            f.write_str("::")?;
        }
        f.write_str(&self.parts.join("::"))
    }
}

/// A numeric literal.
#[derive(Debug, Clone, PartialEq)]
pub struct NumberLit {
    /// The value: integral literals keep full precision.
    pub value: Number,
    /// The literal as written.
    pub text: String,
    /// Where.
    pub span: Span,
}

/// The value of a numeric literal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Number {
    /// Written without fraction or exponent.
    Int(i128),
    /// Written with a fraction or exponent.
    Float(f64),
}

/// A duration literal.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DurationLit {
    /// Whole nanoseconds; `None` when the literal is not a whole number of
    /// nanoseconds or overflows (already diagnosed by the parser).
    pub ns: Option<i64>,
    /// The literal as written.
    pub text: String,
    /// Where.
    pub span: Span,
}

/// A size literal (thread stacks).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SizeLit {
    /// Bytes; `None` on overflow (already diagnosed).
    pub bytes: Option<u64>,
    /// The literal as written.
    pub text: String,
    /// Where.
    pub span: Span,
}

/// An integer literal.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IntLit {
    /// The value; `None` on overflow (already diagnosed).
    pub value: Option<i64>,
    /// Where.
    pub span: Span,
}

/// A whole parse: the checked file first, then every included file in the
/// order it was first included.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Ast {
    /// One unit per file.
    pub units: Vec<Unit>,
}

impl Ast {
    /// Every top-level item of every file (included files after the main
    /// one), depth-first into nothing: modules stay nested.
    pub fn items(&self) -> impl Iterator<Item = &Item> {
        self.units.iter().flat_map(|u| u.items.iter())
    }
}

/// The items of one file.
#[derive(Debug, Clone, PartialEq)]
pub struct Unit {
    /// The file.
    pub file: FileId,
    /// Parsed as an included IDL file.
    pub is_idl: bool,
    /// Its items in source order.
    pub items: Vec<Item>,
}

/// A top-level item (or, for IDL definitions, a module member).
#[derive(Debug, Clone, PartialEq)]
pub enum Item {
    /// `component`
    Component(Component),
    /// `include` / `#include`
    Include(Include),
    /// `ids`, `export` or `import` block.
    Data(DataBlock),
    /// `thread`
    Thread(Thread),
    /// `service`
    Service(Service),
    /// `typedef`
    Typedef(Typedef),
    /// `struct`
    Struct(StructDef),
    /// `enum`
    Enum(EnumDef),
    /// `const`
    Const(ConstDef),
    /// `module`
    Module(ModuleDef),
}

impl Item {
    /// The item's span.
    pub fn span(&self) -> Span {
        match self {
            Item::Component(x) => x.span,
            Item::Include(x) => x.span,
            Item::Data(x) => x.span,
            Item::Thread(x) => x.span,
            Item::Service(x) => x.span,
            Item::Typedef(x) => x.span,
            Item::Struct(x) => x.span,
            Item::Enum(x) => x.span,
            Item::Const(x) => x.span,
            Item::Module(x) => x.span,
        }
    }
}

/// `component NAME { ... }`
#[derive(Debug, Clone, PartialEq)]
pub struct Component {
    /// Its name.
    pub name: Ident,
    /// Its attributes in source order.
    pub attributes: Vec<Attribute>,
    /// Where.
    pub span: Span,
}

/// `include "path"` or `#include <path>`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Include {
    /// The path as written.
    pub path: StrLit,
    /// Written with `<...>`.
    pub angle: bool,
    /// The loaded file, when it could be loaded.
    pub file: Option<FileId>,
    /// Where.
    pub span: Span,
}

/// `ids|export|import NAME { members }`
#[derive(Debug, Clone, PartialEq)]
pub struct DataBlock {
    /// The kind.
    pub kind: DataKind,
    /// Its name.
    pub name: Ident,
    /// Its members.
    pub members: Vec<Member>,
    /// Where.
    pub span: Span,
}

/// `TYPE name [:= VALUE] ["doc"];` or `TYPE name { field := v; }`.
#[derive(Debug, Clone, PartialEq)]
pub struct Member {
    /// Declared type.
    pub ty: TypeSpec,
    /// Name and array dimensions.
    pub decl: Declarator,
    /// Initial value (a struct initialiser is a [`Value::Fields`]).
    pub init: Option<Value>,
    /// Documentation string.
    pub doc: Option<StrLit>,
    /// Where.
    pub span: Span,
}

/// `thread NAME { ... }`
#[derive(Debug, Clone, PartialEq)]
pub struct Thread {
    /// Its name.
    pub name: Ident,
    /// Its attributes.
    pub attributes: Vec<Attribute>,
    /// Where.
    pub span: Span,
}

/// `[init|auto] service NAME { ... }`
#[derive(Debug, Clone, PartialEq)]
pub struct Service {
    /// Its kind.
    pub kind: ServiceKind,
    /// Span of the `init`/`auto` keyword, if any.
    pub kind_span: Option<Span>,
    /// Its name.
    pub name: Ident,
    /// Its attributes.
    pub attributes: Vec<Attribute>,
    /// Its codels in source order.
    pub codels: Vec<Codel>,
    /// Where.
    pub span: Span,
}

/// A codel. Start and control codels are named `start` and `control`
/// (their name's span is the kind keyword).
#[derive(Debug, Clone, PartialEq)]
pub struct Codel {
    /// Its kind.
    pub kind: CodelKind,
    /// Its name.
    pub name: Ident,
    /// Its attributes.
    pub attributes: Vec<Attribute>,
    /// Where.
    pub span: Span,
}

/// `name: value;`
#[derive(Debug, Clone, PartialEq)]
pub struct Attribute {
    /// The attribute name as written (`max-time`).
    pub name: Ident,
    /// Its value.
    pub value: AttrValue,
    /// Where (the whole attribute, up to the `;`).
    pub span: Span,
}

/// The value of an attribute; its shape follows from the name.
#[derive(Debug, Clone, PartialEq)]
pub enum AttrValue {
    /// `doc`, `version`
    Str(StrLit),
    /// `category`, `lang`, `thread`, `credential`, `on-inter`, thread `start`/`stop`
    Ident(Ident),
    /// `report`, `stops`, `delays`, `forbids`, `next` (possibly empty)
    Idents(Vec<Ident>),
    /// `priority`
    Integer(IntLit),
    /// `period`, `max-time`
    Duration(DurationLit),
    /// `stack`
    Size(SizeLit),
    /// `credentials: a < b < c`
    Credentials(Vec<Ident>),
    /// `exec: f(...)`
    Call(Call),
    /// `input`, `output`
    Params(Vec<Param>),
    /// service `import`, `export`
    Typed(Vec<TypedName>),
    /// `update`
    DataRefs(Vec<DataRef>),
    /// An unknown attribute: its value text (already diagnosed).
    Unknown(String),
}

/// `f([const] a, ...)`
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Call {
    /// The codel function.
    pub function: Ident,
    /// Its arguments.
    pub args: Vec<Argument>,
    /// Where.
    pub span: Span,
}

/// One codel argument.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Argument {
    /// Passed read-only.
    pub is_const: bool,
    /// The data passed.
    pub data: DataRef,
    /// Where (including `const`).
    pub span: Span,
}

/// A data reference: `root.field[2].sub`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DataRef {
    /// The first name (IDS block, export/import block, or parameter).
    pub root: Ident,
    /// What follows.
    pub path: Vec<PathElem>,
    /// Where.
    pub span: Span,
}

impl fmt::Display for DataRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.root.name)?;
        for p in &self.path {
            match p {
                PathElem::Field(i) => write!(f, ".{}", i.name)?,
                PathElem::Index(n, _) => write!(f, "[{n}]")?,
            }
        }
        Ok(())
    }
}

/// One step of a data reference path.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PathElem {
    /// `.name`
    Field(Ident),
    /// `[n]`
    Index(u64, Span),
}

/// A service `input`/`output` parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    /// What it is.
    pub target: ParamTarget,
    /// Default value.
    pub default: Option<Value>,
    /// Documentation string.
    pub doc: Option<StrLit>,
    /// Where.
    pub span: Span,
}

/// Either a new typed parameter or a reference into an IDS.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamTarget {
    /// `TYPE name`
    Typed(TypeSpec, Declarator),
    /// `ids.member[.field...]`
    Data(DataRef),
}

/// `TYPE name` in a service `import:`/`export:` list.
#[derive(Debug, Clone, PartialEq)]
pub struct TypedName {
    /// The type.
    pub ty: TypeSpec,
    /// The name.
    pub name: Ident,
    /// Where.
    pub span: Span,
}

/// A type as written.
#[derive(Debug, Clone, PartialEq)]
pub enum TypeSpec {
    /// A base type.
    Base(BaseType, Span),
    /// `string` or `string<N>`.
    String(Option<Box<ConstExpr>>, Span),
    /// `sequence<T>` or `sequence<T, N>`.
    Sequence(Box<TypeSpec>, Option<Box<ConstExpr>>, Span),
    /// A named type.
    Named(ScopedName),
}

impl TypeSpec {
    /// Where.
    pub fn span(&self) -> Span {
        match self {
            TypeSpec::Base(_, s) | TypeSpec::String(_, s) | TypeSpec::Sequence(_, _, s) => *s,
            TypeSpec::Named(n) => n.span,
        }
    }
}

/// A name with array dimensions: `m[3][3]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Declarator {
    /// The name.
    pub name: Ident,
    /// Array dimensions, outermost first.
    pub dims: Vec<ConstExpr>,
    /// Where.
    pub span: Span,
}

/// A constant expression.
#[derive(Debug, Clone, PartialEq)]
pub enum ConstExpr {
    /// A number.
    Number(NumberLit),
    /// A string.
    Str(StrLit),
    /// A boolean.
    Bool(bool, Span),
    /// A constant or enumerator name.
    Name(ScopedName),
    /// `-e`
    Neg(Box<ConstExpr>, Span),
    /// `a op b`
    Binary(Box<ConstExpr>, BinOp, Box<ConstExpr>, Span),
}

impl ConstExpr {
    /// Where.
    pub fn span(&self) -> Span {
        match self {
            ConstExpr::Number(n) => n.span,
            ConstExpr::Str(s) => s.span,
            ConstExpr::Bool(_, s) | ConstExpr::Neg(_, s) | ConstExpr::Binary(_, _, _, s) => *s,
            ConstExpr::Name(n) => n.span,
        }
    }
}

/// A binary operator of constant expressions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `%`
    Rem,
}

/// A value in an initialiser or default.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A number.
    Number(NumberLit),
    /// A string.
    Str(StrLit),
    /// A boolean.
    Bool(bool, Span),
    /// An enumerator or constant name.
    Name(ScopedName),
    /// A struct initialiser by field.
    Fields(Vec<FieldInit>, Span),
    /// An array or sequence literal.
    List(Vec<Value>, Span),
}

impl Value {
    /// Where.
    pub fn span(&self) -> Span {
        match self {
            Value::Number(n) => n.span,
            Value::Str(s) => s.span,
            Value::Bool(_, s) | Value::Fields(_, s) | Value::List(_, s) => *s,
            Value::Name(n) => n.span,
        }
    }
}

/// `field := value ["doc"]` or `field { ... }`.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldInit {
    /// The field.
    pub name: Ident,
    /// Its value.
    pub value: Value,
    /// Documentation string.
    pub doc: Option<StrLit>,
    /// Where.
    pub span: Span,
}

/// `typedef ... NAME, OTHER[3];`
#[derive(Debug, Clone, PartialEq)]
pub struct Typedef {
    /// The aliased type.
    pub target: TypedefTarget,
    /// The declared names.
    pub declarators: Vec<Declarator>,
    /// Where.
    pub span: Span,
}

/// What a typedef aliases.
#[derive(Debug, Clone, PartialEq)]
pub enum TypedefTarget {
    /// `typedef struct [TAG] { ... }`
    Struct(Option<Ident>, Vec<StructMember>),
    /// `typedef enum [TAG] { ... }`
    Enum(Option<Ident>, Vec<Ident>),
    /// `typedef T`
    Type(TypeSpec),
}

/// `struct NAME { ... };`
#[derive(Debug, Clone, PartialEq)]
pub struct StructDef {
    /// Its name.
    pub name: Ident,
    /// Its member lines.
    pub members: Vec<StructMember>,
    /// Where.
    pub span: Span,
}

/// One struct member line: `double x, y[2];`
#[derive(Debug, Clone, PartialEq)]
pub struct StructMember {
    /// The type.
    pub ty: TypeSpec,
    /// The names.
    pub declarators: Vec<Declarator>,
    /// Where.
    pub span: Span,
}

/// `enum NAME { A, B };`
#[derive(Debug, Clone, PartialEq)]
pub struct EnumDef {
    /// Its name.
    pub name: Ident,
    /// Its values.
    pub enumerators: Vec<Ident>,
    /// Where.
    pub span: Span,
}

/// `const T NAME = expr;`
#[derive(Debug, Clone, PartialEq)]
pub struct ConstDef {
    /// The type.
    pub ty: TypeSpec,
    /// The name.
    pub name: Ident,
    /// The value.
    pub value: ConstExpr,
    /// Where.
    pub span: Span,
}

/// `module NAME { ... };`
#[derive(Debug, Clone, PartialEq)]
pub struct ModuleDef {
    /// Its name.
    pub name: Ident,
    /// Its definitions.
    pub items: Vec<Item>,
    /// Where.
    pub span: Span,
}
