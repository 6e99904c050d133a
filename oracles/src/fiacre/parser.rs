//! A recursive-descent parser of Fiacre programs, written from the Fiacre
//! language's reference (docs/exports/fiacre.md, "Reference"), not from
//! genom-check's emitter: declarations (`type`, `const`, `process`,
//! `component`), the root component's name, and frac's `property` and
//! `assert` lines. Ports, `function`s and priorities are not read (an
//! error says so).

use super::ast::{
    Arg, BinOp, CmpOp, Component, Expr, Instance, Interval, Param, Process, Program, Property, Stmt,
};
use super::lexer::{Kind, Tok, lex};

/// Parses a whole program.
pub fn parse(text: &str) -> Result<Program, String> {
    let toks = lex(text)?;
    let mut p = Parser { toks, i: 0 };
    p.program()
}

struct Parser {
    toks: Vec<Tok>,
    i: usize,
}

type R<T> = Result<T, String>;

impl Parser {
    fn peek(&self) -> Option<&Kind> {
        self.toks.get(self.i).map(|t| &t.kind)
    }

    fn line(&self) -> usize {
        self.toks
            .get(self.i)
            .or(self.toks.last())
            .map_or(0, |t| t.line)
    }

    fn err<T>(&self, what: &str) -> R<T> {
        Err(format!(
            "line {}: {what}, found {:?}",
            self.line(),
            self.peek()
        ))
    }

    fn is_kw(&self, kw: &str) -> bool {
        matches!(self.peek(), Some(Kind::Ident(s)) if s == kw)
    }

    fn is_sym(&self, s: &str) -> bool {
        matches!(self.peek(), Some(Kind::Sym(x)) if *x == s)
    }

    fn eat_kw(&mut self, kw: &str) -> bool {
        let yes = self.is_kw(kw);
        if yes {
            self.i += 1;
        }
        yes
    }

    fn eat_sym(&mut self, s: &str) -> bool {
        let yes = self.is_sym(s);
        if yes {
            self.i += 1;
        }
        yes
    }

    fn kw(&mut self, kw: &str) -> R<()> {
        if self.eat_kw(kw) {
            Ok(())
        } else {
            self.err(&format!("expected `{kw}`"))
        }
    }

    fn sym(&mut self, s: &str) -> R<()> {
        if self.eat_sym(s) {
            Ok(())
        } else {
            self.err(&format!("expected `{s}`"))
        }
    }

    fn ident(&mut self) -> R<String> {
        match self.peek() {
            Some(Kind::Ident(s)) if !KEYWORDS.contains(&s.as_str()) => {
                let s = s.clone();
                self.i += 1;
                Ok(s)
            }
            _ => self.err("expected an identifier"),
        }
    }

    fn int(&mut self) -> R<i64> {
        let neg = self.eat_sym("-");
        match self.peek() {
            Some(Kind::Int(v)) => {
                let v = *v;
                self.i += 1;
                Ok(if neg { -v } else { v })
            }
            _ => self.err("expected an integer"),
        }
    }

    fn program(&mut self) -> R<Program> {
        let mut prog = Program::default();
        while self.peek().is_some() {
            if self.eat_kw("process") {
                prog.processes.push(self.process()?);
            } else if self.eat_kw("component") {
                prog.components.push(self.component()?);
            } else if self.eat_kw("const") {
                let name = self.ident()?;
                self.sym(":")?;
                self.ty()?;
                self.kw("is")?;
                prog.consts.push((name, self.expr()?));
            } else if self.eat_kw("type") {
                self.ident()?;
                self.kw("is")?;
                self.ty()?;
            } else if self.eat_kw("property") {
                prog.properties.push(self.property()?);
            } else if self.eat_kw("assert") {
                prog.asserts.push(self.ident()?);
                self.skip_clause();
            } else if prog.root.is_none() {
                prog.root = Some(self.ident()?);
            } else {
                return self.err("expected a declaration");
            }
        }
        Ok(prog)
    }

    /// Skips to the next `property` or `assert` (or the end).
    fn skip_clause(&mut self) -> String {
        let mut words = Vec::new();
        while self.peek().is_some() && !self.is_kw("property") && !self.is_kw("assert") {
            words.push(match &self.toks[self.i].kind {
                Kind::Ident(s) | Kind::Str(s) => s.clone(),
                Kind::Int(v) => v.to_string(),
                Kind::Sym(s) => (*s).to_owned(),
            });
            self.i += 1;
        }
        words.join(" ")
    }

    fn property(&mut self) -> R<Property> {
        let name = self.ident()?;
        self.kw("is")?;
        Ok(Property {
            name,
            formula: self.skip_clause(),
        })
    }

    /// A type: a type name (`bool`, `nat`, `int`, or declared).
    fn ty(&mut self) -> R<String> {
        let name = match self.peek() {
            Some(Kind::Ident(s)) => s.clone(),
            _ => return self.err("expected a type name"),
        };
        self.i += 1;
        Ok(name)
    }

    fn params(&mut self) -> R<Vec<Param>> {
        let mut out = Vec::new();
        if !self.eat_sym("(") {
            return Ok(out);
        }
        if self.eat_sym(")") {
            return Ok(out);
        }
        loop {
            let by_ref = self.eat_sym("&");
            let name = self.ident()?;
            self.sym(":")?;
            let ty = self.ty()?;
            out.push(Param { name, by_ref, ty });
            if !self.eat_sym(",") {
                break;
            }
        }
        self.sym(")")?;
        Ok(out)
    }

    fn process(&mut self) -> R<Process> {
        let name = self.ident()?;
        if self.is_sym("[") {
            return self.err("ports are not read");
        }
        let params = self.params()?;
        self.kw("is")?;
        self.kw("states")?;
        let mut states = vec![self.ident()?];
        while self.eat_sym(",") {
            states.push(self.ident()?);
        }
        let mut vars = Vec::new();
        if self.eat_kw("var") {
            vars = self
                .var_decls()?
                .into_iter()
                .map(|(n, _, e)| (n, e))
                .collect();
        }
        let mut init = None;
        if self.eat_kw("init") {
            self.kw("to")?;
            init = Some(self.ident()?);
        }
        let mut froms = Vec::new();
        while self.eat_kw("from") {
            let s = self.ident()?;
            froms.push((s, self.block()?));
        }
        Ok(Process {
            name,
            params,
            states,
            vars,
            init,
            froms,
        })
    }

    /// `x, y : T := e, z : U` (the initial value optional).
    fn var_decls(&mut self) -> R<Vec<(String, String, Option<Expr>)>> {
        let mut out = Vec::new();
        loop {
            let mut names = vec![self.ident()?];
            while self.eat_sym(",") {
                names.push(self.ident()?);
            }
            self.sym(":")?;
            let ty = self.ty()?;
            let init = if self.eat_sym(":=") {
                Some(self.expr()?)
            } else {
                None
            };
            out.extend(names.into_iter().map(|n| (n, ty.clone(), init.clone())));
            if !self.eat_sym(",") {
                return Ok(out);
            }
        }
    }

    fn component(&mut self) -> R<Component> {
        let name = self.ident()?;
        self.kw("is")?;
        let mut vars = Vec::new();
        if self.eat_kw("var") {
            vars = self.var_decls()?;
        }
        if self.is_kw("port") || self.is_kw("priority") {
            return self.err("ports and priorities are not read");
        }
        self.kw("par")?;
        self.eat_sym("*");
        self.kw("in")?;
        let mut par = vec![self.instance()?];
        while self.eat_sym("||") {
            par.push(self.instance()?);
        }
        self.kw("end")?;
        self.eat_kw("par");
        Ok(Component { name, vars, par })
    }

    fn instance(&mut self) -> R<Instance> {
        let name = self.ident()?;
        let mut args = Vec::new();
        if self.eat_sym("(") && !self.eat_sym(")") {
            loop {
                args.push(if self.eat_sym("&") {
                    Arg::Ref(self.ident()?)
                } else {
                    Arg::Value(self.expr()?)
                });
                if !self.eat_sym(",") {
                    break;
                }
            }
            self.sym(")")?;
        }
        Ok(Instance { name, args })
    }

    /// Statements separated by `;`.
    fn block(&mut self) -> R<Vec<Stmt>> {
        let mut out = vec![self.stmt()?];
        while self.eat_sym(";") {
            out.push(self.stmt()?);
        }
        Ok(out)
    }

    fn stmt(&mut self) -> R<Stmt> {
        if self.eat_kw("null") {
            return Ok(Stmt::Null);
        }
        if self.eat_kw("loop") {
            return Ok(Stmt::Loop);
        }
        if self.eat_kw("to") {
            return Ok(Stmt::To(self.ident()?));
        }
        if self.eat_kw("on") {
            return Ok(Stmt::On(self.expr()?));
        }
        if self.eat_kw("wait") {
            return Ok(Stmt::Wait(self.interval()?));
        }
        if self.eat_kw("select") {
            let mut alts = vec![self.block()?];
            while self.eat_sym("[]") {
                alts.push(self.block()?);
            }
            self.end("select")?;
            return Ok(Stmt::Select(alts));
        }
        if self.eat_kw("if") {
            return self.if_stmt();
        }
        if self.eat_kw("while") {
            let c = self.expr()?;
            self.kw("do")?;
            let body = self.block()?;
            self.end("while")?;
            return Ok(Stmt::While(c, body));
        }
        self.assign()
    }

    /// `end`, optionally followed by the construct's keyword.
    fn end(&mut self, what: &str) -> R<()> {
        self.kw("end")?;
        self.eat_kw(what);
        Ok(())
    }

    fn if_stmt(&mut self) -> R<Stmt> {
        let mut arms = Vec::new();
        loop {
            let c = self.expr()?;
            self.kw("then")?;
            arms.push((c, self.block()?));
            if !self.eat_kw("elsif") {
                break;
            }
        }
        let other = if self.eat_kw("else") {
            self.block()?
        } else {
            Vec::new()
        };
        self.end("if")?;
        Ok(Stmt::If(arms, other))
    }

    fn assign(&mut self) -> R<Stmt> {
        let mut lhs = vec![self.ident()?];
        while self.eat_sym(",") {
            lhs.push(self.ident()?);
        }
        self.sym(":=")?;
        let mut rhs = vec![self.expr()?];
        while self.eat_sym(",") {
            rhs.push(self.expr()?);
        }
        if lhs.len() != rhs.len() {
            return self.err("as many values as variables");
        }
        Ok(Stmt::Assign(lhs, rhs))
    }

    /// `[a,b]`, `]a,b]`, `[a,b[`, `]a,b[`, `[a,...[`.
    fn interval(&mut self) -> R<Interval> {
        let lo_open = if self.eat_sym("]") {
            true
        } else {
            self.sym("[")?;
            false
        };
        let lo = self.int()?;
        self.sym(",")?;
        if self.eat_sym("...") {
            self.sym("[")?;
            return Ok(Interval {
                lo,
                lo_open,
                hi: None,
                hi_open: true,
            });
        }
        let hi = self.int()?;
        let hi_open = if self.eat_sym("[") {
            true
        } else {
            self.sym("]")?;
            false
        };
        Ok(Interval {
            lo,
            lo_open,
            hi: Some(hi),
            hi_open,
        })
    }

    fn expr(&mut self) -> R<Expr> {
        let mut e = self.conj()?;
        while self.eat_kw("or") {
            e = Expr::Bin(BinOp::Or, Box::new(e), Box::new(self.conj()?));
        }
        Ok(e)
    }

    fn conj(&mut self) -> R<Expr> {
        let mut e = self.negation()?;
        while self.eat_kw("and") {
            e = Expr::Bin(BinOp::And, Box::new(e), Box::new(self.negation()?));
        }
        Ok(e)
    }

    fn negation(&mut self) -> R<Expr> {
        if self.eat_kw("not") {
            return Ok(Expr::Not(Box::new(self.negation()?)));
        }
        self.comparison()
    }

    fn comparison(&mut self) -> R<Expr> {
        let e = self.sum()?;
        let op = match self.peek() {
            Some(Kind::Sym("=")) => BinOp::Cmp(CmpOp::Eq),
            Some(Kind::Sym("<>")) => BinOp::Cmp(CmpOp::Ne),
            Some(Kind::Sym("<")) => BinOp::Cmp(CmpOp::Lt),
            Some(Kind::Sym("<=")) => BinOp::Cmp(CmpOp::Le),
            Some(Kind::Sym(">")) => BinOp::Cmp(CmpOp::Gt),
            Some(Kind::Sym(">=")) => BinOp::Cmp(CmpOp::Ge),
            _ => return Ok(e),
        };
        self.i += 1;
        Ok(Expr::Bin(op, Box::new(e), Box::new(self.sum()?)))
    }

    fn sum(&mut self) -> R<Expr> {
        let mut e = self.product()?;
        loop {
            let op = match self.peek() {
                Some(Kind::Sym("+")) => BinOp::Add,
                Some(Kind::Sym("-")) => BinOp::Sub,
                _ => return Ok(e),
            };
            self.i += 1;
            e = Expr::Bin(op, Box::new(e), Box::new(self.product()?));
        }
    }

    fn product(&mut self) -> R<Expr> {
        let mut e = self.unary()?;
        loop {
            let op = match self.peek() {
                Some(Kind::Sym("*")) => BinOp::Mul,
                Some(Kind::Sym("/")) => BinOp::Div,
                Some(Kind::Sym("%")) => BinOp::Mod,
                _ => return Ok(e),
            };
            self.i += 1;
            e = Expr::Bin(op, Box::new(e), Box::new(self.unary()?));
        }
    }

    fn unary(&mut self) -> R<Expr> {
        if self.eat_sym("-") {
            return Ok(Expr::Neg(Box::new(self.unary()?)));
        }
        if self.eat_sym("(") {
            let e = self.expr()?;
            self.sym(")")?;
            return Ok(e);
        }
        if self.eat_kw("true") {
            return Ok(Expr::Bool(true));
        }
        if self.eat_kw("false") {
            return Ok(Expr::Bool(false));
        }
        if let Some(Kind::Int(v)) = self.peek() {
            let v = *v;
            self.i += 1;
            return Ok(Expr::Int(v));
        }
        Ok(Expr::Var(self.ident()?))
    }
}

/// Fiacre's reserved words the parser meets (never identifiers).
const KEYWORDS: [&str; 34] = [
    "and",
    "assert",
    "component",
    "const",
    "do",
    "else",
    "elsif",
    "end",
    "false",
    "from",
    "if",
    "in",
    "init",
    "is",
    "loop",
    "not",
    "null",
    "on",
    "or",
    "par",
    "port",
    "priority",
    "process",
    "property",
    "select",
    "states",
    "then",
    "to",
    "true",
    "type",
    "var",
    "wait",
    "while",
    "function",
];
