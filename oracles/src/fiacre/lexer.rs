//! The tokens of Fiacre: identifiers and keywords, integers, the symbols
//! of the language, strings (in `assert`), and comments (`/* */`, `//`)
//! skipped.

/// A token with its line (from 1).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Tok {
    /// What it is.
    pub kind: Kind,
    /// Its line.
    pub line: usize,
}

/// A token's kind.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Kind {
    /// An identifier or a keyword.
    Ident(String),
    /// An integer literal.
    Int(i64),
    /// A string literal.
    Str(String),
    /// A symbol (`:=`, `[]`, `||`, `...`, `<>`, `<=`, `>=`, or one character).
    Sym(&'static str),
}

const SYMBOLS: [&str; 26] = [
    "...", ":=", "[]", "||", "<>", "<=", ">=", "->", "(", ")", "[", "]", "{", "}", ",", ";", ":",
    "&", "=", "<", ">", "+", "-", "*", "/", "%",
];

/// The tokens of `text`, or the line of the first character that is not
/// Fiacre.
pub fn lex(text: &str) -> Result<Vec<Tok>, String> {
    let b = text.as_bytes();
    let (mut i, mut line) = (0, 1);
    let mut out = Vec::new();
    while i < b.len() {
        let c = b[i];
        if c == b'\n' {
            line += 1;
            i += 1;
        } else if c.is_ascii_whitespace() {
            i += 1;
        } else if text[i..].starts_with("/*") {
            let end = text[i + 2..]
                .find("*/")
                .ok_or(format!("line {line}: comment not closed"))?;
            line += text[i..i + 2 + end].matches('\n').count();
            i += end + 4;
        } else if text[i..].starts_with("//") {
            i += text[i..].find('\n').unwrap_or(text.len() - i);
        } else if c.is_ascii_alphabetic() || c == b'_' {
            let n = text[i..]
                .find(|ch: char| !(ch.is_ascii_alphanumeric() || ch == '_'))
                .unwrap_or(text.len() - i);
            out.push(Tok {
                kind: Kind::Ident(text[i..i + n].to_owned()),
                line,
            });
            i += n;
        } else if c.is_ascii_digit() {
            let n = text[i..]
                .find(|ch: char| !ch.is_ascii_digit())
                .unwrap_or(text.len() - i);
            let v = text[i..i + n]
                .parse()
                .map_err(|_| format!("line {line}: integer too large"))?;
            out.push(Tok {
                kind: Kind::Int(v),
                line,
            });
            i += n;
        } else if c == b'"' {
            let end = text[i + 1..]
                .find('"')
                .ok_or(format!("line {line}: string not closed"))?;
            out.push(Tok {
                kind: Kind::Str(text[i + 1..i + 1 + end].to_owned()),
                line,
            });
            i += end + 2;
        } else {
            let sym = SYMBOLS
                .iter()
                .find(|s| text[i..].starts_with(*s))
                .ok_or(format!("line {line}: unexpected character `{}`", c as char))?;
            out.push(Tok {
                kind: Kind::Sym(sym),
                line,
            });
            i += sym.len();
        }
    }
    Ok(out)
}
