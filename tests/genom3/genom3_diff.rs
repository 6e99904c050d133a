//! Differential test of the GenoM3 front-end against the real GenoM3
//! parser: `genom3 -n` (parse and check only) and
//! `genom-check --dialect genom3 --static-only` must accept and reject the
//! same files, the GenoM3 corpus (`../shared/corpus/genom3`) and mutants
//! of it (a token deleted, duplicated or swapped with the next, a missing
//! `;`, a keyword or a parameter direction replaced by another, a name
//! misspelt, a bracket deleted).
//!
//! The comparison needs the `genom3` executable, so it is ignored by a plain
//! `cargo test`; docs/testing/genom3.md says how to build `genom3` and run
//! it:
//!
//! ```sh
//! GENOM3=/path/to/bin/genom3 cargo test --test genom3 genom3_diff:: -- --ignored --nocapture
//! ```
//!
//! Both tools read each file with `-I <the corpus folder of the file>` and
//! `-I tests/fixtures/genom3/include` (the interface stubs). `genom3` runs
//! with `PKG_CONFIG=true`, so that its `#pragma require` lines succeed
//! without the packages installed (the stubs stand in for them).
//!
//! Accept is exit status 0 for both tools. A `genom3` crash or timeout
//! leaves the file out of the comparison (listed); a `genom-check` crash,
//! timeout or exit status other than 0, 1 or 2 is a failure. A corpus file
//! whose `require "genom3 >= V"` is newer than the `genom3` under test is
//! left out (listed), with its mutants.
//!
//! Other variables:
//!
//! - `GENOM3_CORPUS`: the corpus folder (default `../shared/corpus/genom3`
//!   from the workspace root);
//! - `GENOM3_MUTANTS_PER_KIND`: mutants of each kind per corpus file
//!   (default 2: 8 kinds, 19 files, 304 mutants);
//! - `GENOM3_SEED`: changes every mutant (default 0);
//! - `GENOM3_SHOW`: disagreements printed with their whole mutated file
//!   (default 3; the others print the lines around the mutation);
//! - `GENOM3_KEEP`: a folder that keeps every mutant (by default they are
//!   written to a temporary folder, kept when the tools disagree).
//!
//! The mutator itself (deterministic, distinct mutants that never touch
//! comments or preprocessor lines) is checked by the ordinary tests below.

#![allow(clippy::expect_used, clippy::print_stdout, clippy::print_stderr)] // test harness

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
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
struct Token {
    kind: Tok,
    start: usize,
    end: usize,
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
fn tokenize(src: &str) -> Vec<Token> {
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
enum Kind {
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
    const ALL: [Self; 8] = [
        Self::DeleteToken,
        Self::DuplicateToken,
        Self::SwapAdjacent,
        Self::MissingSemicolon,
        Self::SwapKeyword,
        Self::SwapDirection,
        Self::MisspellName,
        Self::DeleteBracket,
    ];

    fn name(self) -> &'static str {
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
struct Mutant {
    kind: Kind,
    /// Its rank among the mutants of its kind of the same file.
    index: usize,
    /// The mutated text.
    text: String,
    /// The mutation, e.g. ``line 12:5: deleted `;` ``.
    what: String,
    /// The line (1-based) of the mutation in the original source.
    line: usize,
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
fn mutants(src: &str, name: &str, per_kind: usize, seed: u64) -> Vec<Mutant> {
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
enum Exit {
    Code(i32),
    /// Killed by a signal.
    Signal,
    TimedOut,
}

/// A finished run: how it ended and its stdout then stderr.
struct Run {
    exit: Exit,
    output: String,
}

impl Run {
    fn accepted(&self) -> bool {
        self.exit == Exit::Code(0)
    }

    fn exit_text(&self) -> String {
        match self.exit {
            Exit::Code(c) => format!("exit {c}"),
            Exit::Signal => "killed by a signal".to_owned(),
            Exit::TimedOut => format!("timed out after {}s", TIMEOUT.as_secs()),
        }
    }
}

/// Runs `cmd` to its end or to `TIMEOUT`.
fn run(mut cmd: Command) -> Run {
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

fn run_genom3(genom3: &Path, file: &Path, home: &Path) -> Run {
    let mut cmd = Command::new(genom3);
    cmd.env("PKG_CONFIG", "true").arg("-n");
    for dir in includes(home) {
        cmd.arg("-I").arg(dir);
    }
    cmd.arg(file);
    run(cmd)
}

fn run_genom_check(file: &Path, home: &Path) -> Run {
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

fn corpus_dir() -> PathBuf {
    std::env::var_os("GENOM3_CORPUS").map_or_else(
        || workspace().join("../shared/corpus/genom3"),
        PathBuf::from,
    )
}

/// The corpus files, sorted: every `.gen` of each component folder, and
/// GenoM3's own `regress/component.gen`, `regress/datatypes.gen` and
/// `templates/common/genom.gen` from the `genom3` folder.
fn corpus_files(corpus: &Path) -> Vec<PathBuf> {
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
fn version(text: &str) -> Vec<u64> {
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
fn required_genom3(src: &str) -> Option<Vec<u64>> {
    let at = src.find("\"genom3 >=")? + "\"genom3 >=".len();
    let rest = &src[at..];
    Some(version(&rest[..rest.find('"')?]))
}

// ---------------------------------------------------------------------------
// The comparison

/// One file compared: the corpus file or a mutant of it.
struct Case {
    /// The corpus file's name relative to the corpus.
    base: String,
    /// `None` for the corpus file itself.
    mutant: Option<Mutant>,
    /// The file both tools read.
    path: PathBuf,
    /// The corpus folder of the base file (first `-I`).
    home: PathBuf,
}

/// Counts of one row of the summary table.
#[derive(Default)]
struct Row {
    files: usize,
    genom3_rejects: usize,
    genom_check_rejects: usize,
    agree: usize,
    genom3_broken: usize,
}

fn show_text(mutant: Option<&Mutant>, text: &str, whole: bool) -> String {
    let mut out = String::new();
    let (from, to) = match mutant {
        Some(m) if !whole => (m.line.saturating_sub(4), m.line + 3),
        _ => (0, usize::MAX),
    };
    for (n, line) in text.lines().enumerate() {
        if (from..to).contains(&n) {
            let _ = writeln!(out, "{:5} | {line}", n + 1);
        }
    }
    out
}

#[test]
#[ignore = "needs GENOM3=path/to/genom3 (see docs/testing/genom3.md)"]
fn genom3_and_genom_check_agree() {
    let genom3 = PathBuf::from(std::env::var_os("GENOM3").expect(
        "GENOM3 must name the genom3 executable (docs/testing/genom3.md says how to build it)",
    ));
    assert!(
        genom3.is_file(),
        "GENOM3={} is not a file",
        genom3.display()
    );
    let env_number = |name: &str, default: u64| {
        std::env::var(name).map_or(default, |v| {
            v.trim()
                .parse()
                .unwrap_or_else(|_| panic!("{name}: an integer"))
        })
    };
    let per_kind = usize::try_from(env_number("GENOM3_MUTANTS_PER_KIND", 2)).expect("small");
    let seed = env_number("GENOM3_SEED", 0);
    let show = usize::try_from(env_number("GENOM3_SHOW", 3)).expect("small");

    let version_run = run({
        let mut c = Command::new(&genom3);
        c.arg("--version");
        c
    });
    let genom3_version = version(version_run.output.lines().next().unwrap_or(""));
    println!(
        "genom3 {} ({})",
        version_run.output.trim(),
        genom3.display()
    );

    let corpus = corpus_dir();
    let files = corpus_files(&corpus);
    assert!(
        !files.is_empty(),
        "no .gen file in the corpus {} (set GENOM3_CORPUS)",
        corpus.display()
    );
    let tmp = tempfile::tempdir().expect("temporary folder");
    let keep = std::env::var_os("GENOM3_KEEP").map(PathBuf::from);
    let mutant_dir = keep.clone().unwrap_or_else(|| tmp.path().to_path_buf());
    std::fs::create_dir_all(&mutant_dir).expect("mutant folder");

    let mut notes = Vec::new();
    let mut cases = Vec::new();
    for file in &files {
        let base = file
            .strip_prefix(&corpus)
            .unwrap_or(file)
            .to_string_lossy()
            .replace('\\', "/");
        let src = std::fs::read_to_string(file).expect("readable corpus file");
        if let Some(required) = required_genom3(&src).filter(|r| *r > genom3_version) {
            notes.push(format!(
                "left out {base} and its mutants: it requires genom3 >= {}, this genom3 is {}",
                required
                    .iter()
                    .map(u64::to_string)
                    .collect::<Vec<_>>()
                    .join("."),
                version_run.output.trim()
            ));
            continue;
        }
        let home = file
            .parent()
            .expect("a corpus file has a folder")
            .to_path_buf();
        cases.push(Case {
            base: base.clone(),
            mutant: None,
            path: file.clone(),
            home: home.clone(),
        });
        let stem = base.replace(['/', '.'], "_");
        for m in mutants(&src, &base, per_kind, seed) {
            let path = mutant_dir.join(format!("{stem}-{}-{}.gen", m.kind.name(), m.index));
            std::fs::write(&path, &m.text).expect("write a mutant");
            cases.push(Case {
                base: base.clone(),
                mutant: Some(m),
                path,
                home: home.clone(),
            });
        }
    }
    let mutant_count = cases.iter().filter(|c| c.mutant.is_some()).count();
    assert!(
        mutant_count >= 200,
        "only {mutant_count} mutants (raise GENOM3_MUTANTS_PER_KIND)"
    );

    let mut rows: BTreeMap<&'static str, Row> = BTreeMap::new();
    let mut disagreements = Vec::new();
    let mut broken = Vec::new();
    for case in &cases {
        let g3 = run_genom3(&genom3, &case.path, &case.home);
        let gc = run_genom_check(&case.path, &case.home);
        let row = rows
            .entry(
                case.mutant
                    .as_ref()
                    .map_or("corpus file", |m| m.kind.name()),
            )
            .or_default();
        row.files += 1;
        let label = case.mutant.as_ref().map_or_else(
            || case.base.clone(),
            |m| format!("{} mutant of {} ({})", m.kind.name(), case.base, m.what),
        );
        if !matches!(g3.exit, Exit::Code(_)) {
            row.genom3_broken += 1;
            notes.push(format!("left out {label}: genom3 {}", g3.exit_text()));
            continue;
        }
        if !matches!(gc.exit, Exit::Code(0..=2)) {
            broken.push(format!(
                "genom-check {} on {label} ({})\n{}",
                gc.exit_text(),
                case.path.display(),
                gc.output
            ));
        }
        row.genom3_rejects += usize::from(!g3.accepted());
        row.genom_check_rejects += usize::from(!gc.accepted());
        if g3.accepted() == gc.accepted() {
            row.agree += 1;
        } else {
            disagreements.push((case, g3, gc, label));
        }
    }

    let mut table = String::from(
        "| kind | files | genom3 rejects | genom-check rejects | agree | genom3 crashed |\n\
         |---|---:|---:|---:|---:|---:|\n",
    );
    let mut total = Row::default();
    for (kind, row) in &rows {
        let _ = writeln!(
            table,
            "| {kind} | {} | {} | {} | {} | {} |",
            row.files, row.genom3_rejects, row.genom_check_rejects, row.agree, row.genom3_broken
        );
        total.files += row.files;
        total.genom3_rejects += row.genom3_rejects;
        total.genom_check_rejects += row.genom_check_rejects;
        total.agree += row.agree;
        total.genom3_broken += row.genom3_broken;
    }
    let _ = writeln!(
        table,
        "| all | {} | {} | {} | {} | {} |",
        total.files,
        total.genom3_rejects,
        total.genom_check_rejects,
        total.agree,
        total.genom3_broken
    );

    let mut report = String::new();
    for (n, (case, g3, gc, label)) in disagreements.iter().enumerate() {
        let text = std::fs::read_to_string(&case.path).unwrap_or_default();
        let whole = n < show || case.mutant.is_none();
        let _ = write!(
            report,
            "\n=== disagreement {}: {label}\nfile: {}\n--- genom3 ({}, {}):\n{}--- genom-check ({}, {}):\n{}--- {}:\n{}",
            n + 1,
            case.path.display(),
            g3.exit_text(),
            if g3.accepted() { "accepts" } else { "rejects" },
            g3.output,
            gc.exit_text(),
            if gc.accepted() { "accepts" } else { "rejects" },
            gc.output,
            if whole || case.mutant.is_none() {
                "mutated file"
            } else {
                "mutated file around the mutation"
            },
            if case.mutant.is_none() {
                "(the corpus file itself)\n".to_owned()
            } else {
                show_text(case.mutant.as_ref(), &text, whole)
            }
        );
    }
    println!("{report}");
    for note in &notes {
        println!("note: {note}");
    }
    println!(
        "\n{mutant_count} mutants of {} corpus files; agreement {}/{}\n\n{table}",
        rows.get("corpus file").map_or(0, |r| r.files),
        total.agree,
        total.files - total.genom3_broken
    );
    if !disagreements.is_empty() || !broken.is_empty() {
        let kept = if keep.is_some() {
            mutant_dir.display().to_string()
        } else {
            tmp.keep().display().to_string()
        };
        panic!(
            "genom3 and genom-check disagree on {} of {} files, genom-check crashed on {} \
             (mutants kept in {kept})\n{}\n{table}",
            disagreements.len(),
            total.files - total.genom3_broken,
            broken.len(),
            broken.join("\n")
        );
    }
}

// ---------------------------------------------------------------------------
// The mutator's own tests (ordinary `cargo test`)

/// A small component with everything the tokenizer must step over.
const SAMPLE: &str = r#"/* a comment; with { brackets } */
#pragma require "openrobots2-idl >= 2.0"
#include "or/pose/pose_estimator.gen"
#define TWO \
  2

component sample {
  version "1.0";  // a line comment; too
  codels-require "eigen3";
  uses or_pose_estimator;
  port in or_pose_estimator::state state;
  const double gain = 1e-2;
  ids { double x[TWO]; struct s_s { long a; } s; };
  task main {
    period 10 ms;
    codel<start> start(out ::ids) yield ether;
  };
  activity go(in double v = 0.5 : "speed; in m/s") {
    task main;
    codel<start> go_start(in v, ids inout x, port in state) yield pause::start, ether;
  };
};
"#;

fn words(src: &str) -> Vec<&str> {
    tokenize(src).iter().map(|t| &src[t.start..t.end]).collect()
}

#[test]
fn tokenizer_skips_comments_and_preprocessor_lines() {
    let w = words(SAMPLE);
    assert_eq!(&w[..3], ["component", "sample", "{"]);
    assert!(w.contains(&"codels-require"));
    assert!(w.contains(&"1e-2"));
    assert!(w.contains(&"::"));
    assert!(w.contains(&"\"speed; in m/s\""));
    assert!(!w.contains(&"#pragma") && !w.contains(&"comment") && !w.contains(&"2"));
    assert_eq!(w.last(), Some(&";"));
    assert_eq!(
        words("a::b 0x1e-2 'c'"),
        ["a", "::", "b", "0x1e", "-", "2", "'c'"]
    );
}

#[test]
fn mutants_are_deterministic_and_distinct() {
    let per_kind = 3;
    let first = mutants(SAMPLE, "sample/sample.gen", per_kind, 0);
    assert_eq!(first, mutants(SAMPLE, "sample/sample.gen", per_kind, 0));
    assert_eq!(first.len(), Kind::ALL.len() * per_kind);
    let texts: BTreeSet<&str> = first.iter().map(|m| m.text.as_str()).collect();
    assert_eq!(texts.len(), first.len(), "mutants are pairwise distinct");
    assert!(
        !texts.contains(SAMPLE),
        "every mutant differs from the source"
    );
    for kind in Kind::ALL {
        assert_eq!(first.iter().filter(|m| m.kind == kind).count(), per_kind);
    }
    // Another name or seed gives other mutants.
    assert_ne!(first, mutants(SAMPLE, "other.gen", per_kind, 0));
    assert_ne!(first, mutants(SAMPLE, "sample/sample.gen", per_kind, 1));

    let semicolons = words(SAMPLE).iter().filter(|w| **w == ";").count();
    for m in &first {
        // Comments and preprocessor lines are never mutated.
        for kept in [
            "/* a comment; with { brackets } */\n#pragma require",
            "#include \"or/pose/pose_estimator.gen\"\n#define TWO \\\n  2\n",
            "// a line comment; too\n",
        ] {
            assert!(m.text.contains(kept), "{}: {}", m.what, m.text);
        }
        let w = words(&m.text);
        match m.kind {
            Kind::MissingSemicolon => {
                assert_eq!(w.iter().filter(|w| **w == ";").count(), semicolons - 1);
            }
            Kind::DeleteToken | Kind::DeleteBracket => {
                assert_eq!(w.len(), words(SAMPLE).len() - 1, "{}", m.what);
            }
            Kind::DuplicateToken => assert_eq!(w.len(), words(SAMPLE).len() + 1),
            Kind::SwapDirection => assert!(
                m.what.contains("`in`") || m.what.contains("`out`") || m.what.contains("`inout`")
            ),
            Kind::MisspellName => assert!(m.what.contains("_x`")),
            Kind::SwapAdjacent | Kind::SwapKeyword => {
                assert_eq!(w.len(), words(SAMPLE).len(), "{}", m.what);
            }
        }
    }
}

#[test]
fn mutant_positions_are_those_of_the_source() {
    let src = "component c {\n  version \"1\";\n  lang \"c\";\n};\n";
    let m = mutants(src, "c.gen", 2, 0);
    let semicolon = m
        .iter()
        .find(|m| m.kind == Kind::MissingSemicolon)
        .expect("a missing-semicolon mutant");
    assert!(
        [
            "line 2:14: deleted `;`",
            "line 3:11: deleted `;`",
            "line 4:2: deleted `;`"
        ]
        .contains(&semicolon.what.as_str()),
        "{}",
        semicolon.what
    );
    let line = semicolon.line;
    assert_eq!(
        semicolon.text.lines().nth(line - 1),
        src.lines()
            .nth(line - 1)
            .map(|l| l.replacen(';', "", 1))
            .as_deref()
    );
}

#[test]
fn genom3_versions_compare_numerically() {
    assert!(version("2.99.41") > version("2.99.39"));
    assert!(version("2.99.100") > version("2.99.41"));
    assert_eq!(
        required_genom3("  require \"genom3 >= 2.99.41\";"),
        Some(vec![2, 99, 41])
    );
    assert_eq!(required_genom3("require \"eigen3\";"), None);
}
