//! Shared helpers of the GenoM3 differential test: the mutator (a
//! tokenizer that steps over comments and preprocessor lines, the kinds of
//! mutation, deterministic mutants), running `genom3` and `genom-check` on
//! one file with a timeout, and the corpus files with the `genom3` version
//! each requires.

use std::collections::BTreeSet;
use std::io::Read as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Time allowed to one run of either tool.
const TIMEOUT: Duration = Duration::from_secs(60);

// ---------------------------------------------------------------------------
// Tokens

/// What a token is, as far as the mutator cares.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Tok {
    /// An identifier or keyword (`codels-require`, `clock-rate` and
    /// `real-time` are one token).
    Word,
    /// A number, with its exponent and suffixes.
    Number,
    /// A string or character literal.
    Literal,
    /// `::` or a single punctuation character.
    Punct,
}

/// A token: its kind and its byte range in the source.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Token {
    kind: Tok,
    pub(crate) start: usize,
    pub(crate) end: usize,
}

/// Keywords made of two words joined by `-`.
const HYPHENATED: [&str; 3] = ["codels-require", "clock-rate", "real-time"];

/// The GenoM3 keywords the mutator swaps with each other.
const KEYWORDS: &[&str] = &[
    "module",
    "const",
    "enum",
    "union",
    "switch",
    "case",
    "default",
    "struct",
    "sequence",
    "optional",
    "typedef",
    "native",
    "exception",
    "interface",
    "component",
    "task",
    "function",
    "activity",
    "attribute",
    "codel",
    "port",
    "ids",
    "doc",
    "version",
    "lang",
    "email",
    "require",
    "codels-require",
    "clock-rate",
    "period",
    "delay",
    "priority",
    "scheduling",
    "real-time",
    "stack",
    "validate",
    "yield",
    "pause",
    "throw",
    "throws",
    "interrupt",
    "interrupts",
    "before",
    "after",
    "async",
    "provides",
    "uses",
    "in",
    "out",
    "inout",
    "local",
    "remote",
    "multiple",
    "unsigned",
    "short",
    "long",
    "float",
    "double",
    "char",
    "boolean",
    "octet",
    "string",
    "TRUE",
    "FALSE",
];

/// Parameter directions.
const DIRECTIONS: [&str; 3] = ["in", "out", "inout"];

fn is_word_start(b: u8) -> bool {
    b.is_ascii_alphabetic() || b == b'_'
}

fn is_word_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

/// The tokens of a GenoM3 source, leaving out comments and preprocessor
/// lines (a `#` first on its line, up to an end of line not escaped by
/// `\`). Non-ASCII characters outside comments and literals are one
/// punctuation token each, so that every token boundary is a character
/// boundary.
pub(crate) fn tokenize(src: &str) -> Vec<Token> {
    let s = src.as_bytes();
    let mut tokens = Vec::new();
    let mut i = 0;
    let mut line_start = true;
    while i < s.len() {
        let b = s[i];
        if b == b'\n' {
            line_start = true;
            i += 1;
            continue;
        }
        if b.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        if b == b'#' && line_start {
            while i < s.len() && s[i] != b'\n' {
                if s[i] == b'\\' && s.get(i + 1) == Some(&b'\n') {
                    i += 1;
                }
                i += 1;
            }
            continue;
        }
        line_start = false;
        let start = i;
        if s[i..].starts_with(b"//") {
            while i < s.len() && s[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        if s[i..].starts_with(b"/*") {
            i += 2;
            while i < s.len() && !s[i..].starts_with(b"*/") {
                i += 1;
            }
            i = (i + 2).min(s.len());
            continue;
        }
        let kind = if b == b'"' || b == b'\'' {
            i += 1;
            while i < s.len() && s[i] != b {
                if s[i] == b'\\' {
                    i += 1;
                }
                i += 1;
            }
            i = (i + 1).min(s.len());
            Tok::Literal
        } else if is_word_start(b) {
            while i < s.len() && is_word_byte(s[i]) {
                i += 1;
            }
            for joined in HYPHENATED {
                if s[start..].starts_with(joined.as_bytes())
                    && !s
                        .get(start + joined.len())
                        .copied()
                        .is_some_and(is_word_byte)
                {
                    i = start + joined.len();
                }
            }
            Tok::Word
        } else if b.is_ascii_digit() || (b == b'.' && s.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            let hex = s[i..].starts_with(b"0x") || s[i..].starts_with(b"0X");
            i += 1;
            while i < s.len() {
                let c = s[i];
                let exponent_sign =
                    (c == b'+' || c == b'-') && !hex && matches!(s[i - 1], b'e' | b'E');
                if is_word_byte(c) || c == b'.' || exponent_sign {
                    i += 1;
                } else {
                    break;
                }
            }
            Tok::Number
        } else if s[i..].starts_with(b"::") {
            i += 2;
            Tok::Punct
        } else {
            i += 1;
            while i < s.len() && (s[i] & 0xC0) == 0x80 {
                i += 1;
            }
            Tok::Punct
        };
        tokens.push(Token {
            kind,
            start,
            end: i,
        });
    }
    tokens
}

// ---------------------------------------------------------------------------
// Mutants

/// The kinds of mutation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Kind {
    /// Any token deleted.
    DeleteToken,
    /// Any token written twice.
    DuplicateToken,
    /// Two different neighbouring tokens swapped.
    SwapAdjacent,
    /// A `;` deleted.
    MissingSemicolon,
    /// A keyword replaced by another keyword.
    SwapKeyword,
    /// `in`, `out` or `inout` replaced by another of them.
    SwapDirection,
    /// A name that is not a keyword misspelt (`_x` appended).
    MisspellName,
    /// A `{`, `}`, `(` or `)` deleted.
    DeleteBracket,
}

impl Kind {
    pub(crate) const ALL: [Self; 8] = [
        Self::DeleteToken,
        Self::DuplicateToken,
        Self::SwapAdjacent,
        Self::MissingSemicolon,
        Self::SwapKeyword,
        Self::SwapDirection,
        Self::MisspellName,
        Self::DeleteBracket,
    ];

    pub(crate) fn name(self) -> &'static str {
        match self {
            Self::DeleteToken => "delete-token",
            Self::DuplicateToken => "duplicate-token",
            Self::SwapAdjacent => "swap-adjacent",
            Self::MissingSemicolon => "missing-semicolon",
            Self::SwapKeyword => "swap-keyword",
            Self::SwapDirection => "swap-direction",
            Self::MisspellName => "misspell-name",
            Self::DeleteBracket => "delete-bracket",
        }
    }
}

/// A mutated source.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Mutant {
    pub(crate) kind: Kind,
    /// Its rank among the mutants of its kind of the same file.
    pub(crate) index: usize,
    /// The mutated text.
    pub(crate) text: String,
    /// The mutation, e.g. ``line 12:5: deleted `;` ``.
    pub(crate) what: String,
    /// The line (1-based) of the mutation in the original source.
    pub(crate) line: usize,
}

/// The pseudo-random numbers of the mutations (the generator's splitmix64).
type Rng = genom_generate::SplitMix;

/// FNV-1a, a hash stable across runs and Rust versions.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xCBF2_9CE4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01B3)
    })
}

/// Line and column (1-based, in characters) of a byte offset.
fn line_col(src: &str, at: usize) -> (usize, usize) {
    let before = &src[..at];
    let line = before.matches('\n').count() + 1;
    let col = before[before.rfind('\n').map_or(0, |p| p + 1)..]
        .chars()
        .count()
        + 1;
    (line, col)
}

/// Whether `left` then `right` with nothing between would lex as one token
/// where they were two (`a` `b`, `:` `:`, `/` `*`, ...).
fn would_merge(left: &str, right: &str) -> bool {
    match (left.bytes().last(), right.bytes().next()) {
        (Some(l), Some(r)) => {
            (is_word_byte(l) && is_word_byte(r))
                || matches!(
                    (l, r),
                    (b'/', b'*' | b'/') | (b'*', b'/') | (b':', b':') | (b'<', b'<') | (b'>', b'>')
                )
        }
        _ => false,
    }
}

/// The parts joined, with a space where two would merge into one token.
fn glue(parts: &[&str]) -> String {
    let mut out = String::new();
    for part in parts.iter().filter(|p| !p.is_empty()) {
        if would_merge(&out, part) {
            out.push(' ');
        }
        out.push_str(part);
    }
    out
}

/// Applies one mutation of `kind` chosen by `rng`, or `None` when the
/// source has nothing to mutate that way.
fn mutate_once(
    src: &str,
    tokens: &[Token],
    kind: Kind,
    rng: &mut Rng,
) -> Option<(String, String, usize)> {
    let text = |t: &Token| &src[t.start..t.end];
    let candidates: Vec<usize> = (0..tokens.len())
        .filter(|&i| {
            let t = &tokens[i];
            match kind {
                Kind::DeleteToken | Kind::DuplicateToken => true,
                Kind::SwapAdjacent => tokens.get(i + 1).is_some_and(|next| text(next) != text(t)),
                Kind::MissingSemicolon => text(t) == ";",
                Kind::SwapKeyword => t.kind == Tok::Word && KEYWORDS.contains(&text(t)),
                Kind::SwapDirection => t.kind == Tok::Word && DIRECTIONS.contains(&text(t)),
                Kind::MisspellName => t.kind == Tok::Word && !KEYWORDS.contains(&text(t)),
                Kind::DeleteBracket => matches!(text(t), "{" | "}" | "(" | ")"),
            }
        })
        .collect();
    let i = *rng.pick(&candidates)?;
    let t = tokens[i];
    let old = text(&t);
    let (line, col) = line_col(src, t.start);
    let replace = |new: &str| glue(&[&src[..t.start], new, &src[t.end..]]);
    let (mutated, what) = match kind {
        Kind::DeleteToken | Kind::MissingSemicolon | Kind::DeleteBracket => {
            (replace(""), format!("deleted `{old}`"))
        }
        Kind::DuplicateToken => (
            replace(&format!("{old} {old}")),
            format!("duplicated `{old}`"),
        ),
        Kind::SwapAdjacent => {
            let n = tokens[i + 1];
            let next = text(&n);
            let swapped = glue(&[
                &src[..t.start],
                next,
                &src[t.end..n.start],
                old,
                &src[n.end..],
            ]);
            (swapped, format!("swapped `{old}` and `{next}`"))
        }
        Kind::SwapKeyword | Kind::SwapDirection => {
            let pool: Vec<&str> = if kind == Kind::SwapKeyword {
                KEYWORDS.iter().copied().filter(|k| *k != old).collect()
            } else {
                DIRECTIONS.iter().copied().filter(|k| *k != old).collect()
            };
            let new = *rng.pick(&pool)?;
            (replace(new), format!("replaced `{old}` by `{new}`"))
        }
        Kind::MisspellName => {
            let new = format!("{old}_x");
            let what = format!("replaced `{old}` by `{new}`");
            (replace(&new), what)
        }
    };
    Some((mutated, format!("line {line}:{col}: {what}"), line))
}

/// `per_kind` mutants of each kind of `src`, all different from `src` and
/// from each other; `name` (the file's name in the corpus) and `seed`
/// choose them, the same every run.
pub(crate) fn mutants(src: &str, name: &str, per_kind: usize, seed: u64) -> Vec<Mutant> {
    const ATTEMPTS: u64 = 64;
    let tokens = tokenize(src);
    let mut seen = BTreeSet::new();
    seen.insert(src.to_owned());
    let mut out = Vec::new();
    for (k, kind) in (0u64..).zip(Kind::ALL) {
        for (j, index) in (0u64..).zip(0..per_kind) {
            for attempt in 0..ATTEMPTS {
                let mut rng = Rng::new(
                    fnv1a(name.as_bytes())
                        ^ seed.wrapping_mul(0x2545_F491_4F6C_DD1D)
                        ^ (k << 56)
                        ^ (j << 40)
                        ^ attempt,
                );
                let Some((text, what, line)) = mutate_once(src, &tokens, kind, &mut rng) else {
                    break;
                };
                if seen.insert(text.clone()) {
                    out.push(Mutant {
                        kind,
                        index,
                        text,
                        what,
                        line,
                    });
                    break;
                }
            }
        }
    }
    out
}

// ---------------------------------------------------------------------------
// Running the tools

/// How a run ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum Exit {
    Code(i32),
    /// Killed by a signal.
    Signal,
    TimedOut,
}

/// A finished run: how it ended and its stdout then stderr.
pub(crate) struct Run {
    pub(crate) exit: Exit,
    pub(crate) output: String,
}

impl Run {
    pub(crate) fn accepted(&self) -> bool {
        self.exit == Exit::Code(0)
    }

    pub(crate) fn exit_text(&self) -> String {
        match self.exit {
            Exit::Code(c) => format!("exit {c}"),
            Exit::Signal => "killed by a signal".to_owned(),
            Exit::TimedOut => format!("timed out after {}s", TIMEOUT.as_secs()),
        }
    }
}

/// Runs `cmd` to its end or to `TIMEOUT`.
pub(crate) fn run(mut cmd: Command) -> Run {
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot run {cmd:?}: {e}"));
    let drain = |pipe: Option<Box<dyn std::io::Read + Send>>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            if let Some(mut p) = pipe {
                let _ = p.read_to_end(&mut bytes);
            }
            String::from_utf8_lossy(&bytes).into_owned()
        })
    };
    let out = drain(child.stdout.take().map(|p| Box::new(p) as _));
    let err = drain(child.stderr.take().map(|p| Box::new(p) as _));
    let started = Instant::now();
    let exit = loop {
        if let Some(status) = child.try_wait().expect("wait for a child") {
            break status.code().map_or(Exit::Signal, Exit::Code);
        }
        if started.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            break Exit::TimedOut;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let mut output = out.join().expect("stdout reader");
    output.push_str(&err.join().expect("stderr reader"));
    Run { exit, output }
}

/// The include folders both tools get for a file of corpus folder `home`.
fn includes(home: &Path) -> [PathBuf; 2] {
    [
        home.to_path_buf(),
        workspace().join("tests/fixtures/genom3/include"),
    ]
}

pub(crate) fn run_genom3(genom3: &Path, file: &Path, home: &Path) -> Run {
    let mut cmd = Command::new(genom3);
    cmd.env("PKG_CONFIG", "true").arg("-n");
    for dir in includes(home) {
        cmd.arg("-I").arg(dir);
    }
    cmd.arg(file);
    run(cmd)
}

pub(crate) fn run_genom_check(file: &Path, home: &Path) -> Run {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_genom-check"));
    cmd.args(["--dialect", "genom3", "--static-only", "--color", "never"]);
    for dir in includes(home) {
        cmd.arg("-I").arg(dir);
    }
    cmd.arg(file);
    run(cmd)
}

// ---------------------------------------------------------------------------
// The corpus

fn workspace() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub(crate) fn corpus_dir() -> PathBuf {
    std::env::var_os("GENOM3_CORPUS").map_or_else(
        || workspace().join("../shared/corpus/genom3"),
        PathBuf::from,
    )
}

/// The corpus files, sorted: every `.gen` of each component folder, and
/// GenoM3's own `regress/component.gen`, `regress/datatypes.gen` and
/// `templates/common/genom.gen` from the `genom3` folder.
pub(crate) fn corpus_files(corpus: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut folders: Vec<PathBuf> = std::fs::read_dir(corpus)
        .unwrap_or_else(|e| panic!("cannot read the corpus {}: {e}", corpus.display()))
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    folders.sort();
    for folder in folders {
        if folder.file_name().is_some_and(|n| n == "genom3") {
            for own in [
                "regress/component.gen",
                "regress/datatypes.gen",
                "templates/common/genom.gen",
            ] {
                let path = folder.join(own);
                if path.is_file() {
                    files.push(path);
                }
            }
            continue;
        }
        let mut gens: Vec<PathBuf> = std::fs::read_dir(&folder)
            .expect("readable corpus folder")
            .filter_map(|entry| entry.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "gen"))
            .collect();
        gens.sort();
        files.extend(gens);
    }
    files
}

/// A dotted version as numbers, for comparison.
pub(crate) fn version(text: &str) -> Vec<u64> {
    text.trim()
        .split('.')
        .map(|part| {
            part.chars()
                .take_while(char::is_ascii_digit)
                .collect::<String>()
                .parse()
                .unwrap_or(0)
        })
        .collect()
}

/// The version in a `require "genom3 >= V"` of the source, if any.
pub(crate) fn required_genom3(src: &str) -> Option<Vec<u64>> {
    let at = src.find("\"genom3 >=")? + "\"genom3 >=".len();
    let rest = &src[at..];
    Some(version(&rest[..rest.find('"')?]))
}
