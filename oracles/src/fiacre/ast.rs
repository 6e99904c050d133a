//! The abstract syntax of the Fiacre subset the parser reads (Fiacre 3:
//! declarations of processes and components, the statements of a
//! transition, boolean and integer expressions). Properties and
//! assertions are kept as text.

pub use genom_model::timed_automata::CmpOp;

/// A binary operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    /// `or`
    Or,
    /// `and`
    And,
    /// A comparison (`=`, `<>`, `<`, `<=`, `>`, `>=`).
    Cmp(CmpOp),
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `%`
    Mod,
}

/// An expression.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Expr {
    /// An integer literal.
    Int(i64),
    /// `true` or `false`.
    Bool(bool),
    /// A variable (a process parameter or local variable).
    Var(String),
    /// `not e`.
    Not(Box<Expr>),
    /// `- e`.
    Neg(Box<Expr>),
    /// `a op b`.
    Bin(BinOp, Box<Expr>, Box<Expr>),
}

/// A time interval of `wait`: bounds, and whether each is open (`]a` or
/// `b[`); `hi` `None` is `...[` (no upper bound).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Interval {
    /// Lower bound.
    pub lo: i64,
    /// `]lo`: strictly after.
    pub lo_open: bool,
    /// Upper bound (`None`: unbounded).
    pub hi: Option<i64>,
    /// `hi[`: strictly before.
    pub hi_open: bool,
}

/// A statement.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Stmt {
    /// `null`.
    Null,
    /// `x := e` (several targets: `x, y := a, b`).
    Assign(Vec<String>, Vec<Expr>),
    /// `on e`.
    On(Expr),
    /// `wait I`.
    Wait(Interval),
    /// `to s`.
    To(String),
    /// `loop`: back to the current state.
    Loop,
    /// `select s1 [] s2 ... end`.
    Select(Vec<Vec<Stmt>>),
    /// `if c then s elsif c then s else s end`.
    If(Vec<(Expr, Vec<Stmt>)>, Vec<Stmt>),
    /// `while c do s end`.
    While(Expr, Vec<Stmt>),
}

/// A parameter of a process: `&name : type` (by reference) or `name :
/// type` (by value).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Param {
    /// Its name.
    pub name: String,
    /// Passed by reference (`&`).
    pub by_ref: bool,
    /// Its type, as written.
    pub ty: String,
}

/// A process declaration.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Process {
    /// Its name.
    pub name: String,
    /// Its parameters.
    pub params: Vec<Param>,
    /// Its states; the first is the initial one unless `init` says.
    pub states: Vec<String>,
    /// Local variables with their initial values.
    pub vars: Vec<(String, Option<Expr>)>,
    /// `init to s`: the initial state.
    pub init: Option<String>,
    /// `from s stmt`, per state.
    pub froms: Vec<(String, Vec<Stmt>)>,
}

/// An argument of an instance: `&x` or an expression.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Arg {
    /// A shared variable, by reference.
    Ref(String),
    /// A value.
    Value(Expr),
}

/// A process (or component) instance in a `par`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Instance {
    /// What it instantiates.
    pub name: String,
    /// Its arguments.
    pub args: Vec<Arg>,
}

/// A component declaration.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Component {
    /// Its name.
    pub name: String,
    /// Its variables with their types and initial values.
    pub vars: Vec<(String, String, Option<Expr>)>,
    /// The instances of its `par`.
    pub par: Vec<Instance>,
}

/// A property declaration (its formula as text) and the assertions.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Property {
    /// Its name.
    pub name: String,
    /// Its formula, as written.
    pub formula: String,
}

/// A whole Fiacre program.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Program {
    /// `const NAME : T is e`.
    pub consts: Vec<(String, Expr)>,
    /// The processes.
    pub processes: Vec<Process>,
    /// The components.
    pub components: Vec<Component>,
    /// The root component's name (the line after the declarations).
    pub root: Option<String>,
    /// The properties.
    pub properties: Vec<Property>,
    /// The names the `assert` lines check.
    pub asserts: Vec<String>,
}
