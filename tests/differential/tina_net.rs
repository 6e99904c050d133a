//! A reader of TINA's textual `.net` format, written from the format's
//! reference (the TINA toolbox manual, "formats": `net`, `tr`, `pl`, `lb`,
//! `pr`, `nt` declarations; names plain, or between braces with `{`, `}`
//! and `\` escaped; intervals `[a,b]`, `]a,b[`, `[a,w[`; arcs `p`,
//! `p*w`, read `p?w`, inhibitor `p?-w`; `#` comments), not from genom-check's
//! printer, so that a test can rebuild the net a `tina` export describes
//! and explore it. The comment line right above a `tr` declaration is kept
//! as the transition's label (genom-check writes what it stands for
//! there).

use std::collections::BTreeMap;

use genom_model::component::Idx;
use genom_model::petri::{
    G3Place, G3Step, PetriNet, Place, PlaceId, PlaceKind, Transition, TransitionKind,
};
use genom_model::span::Span;

/// An arc of a transition's input.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Arc {
    /// Consumes `w` tokens.
    Normal(String, u32),
    /// Needs `w` tokens, keeps them.
    Test(String, u32),
    /// Needs fewer than `w` tokens.
    Inhibitor(String, u32),
}

/// A `tr` declaration.
#[derive(Debug, Clone)]
pub struct Tr {
    pub name: String,
    pub label: String,
    pub interval: String,
    pub inputs: Vec<Arc>,
    pub outputs: Vec<(String, u32)>,
}

/// A whole `.net` file.
#[derive(Debug, Clone, Default)]
pub struct Net {
    pub name: String,
    /// Places in declaration order, with their initial marking.
    pub places: Vec<(String, u32)>,
    pub transitions: Vec<Tr>,
    /// `pr` declarations: (higher, lower) transition names.
    pub priorities: Vec<(Vec<String>, Vec<String>)>,
}

/// A token of a declaration line.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Tok {
    Name(String),
    Punct(char),
}

fn tokens(line: &str) -> Result<Vec<Tok>, String> {
    let mut out = Vec::new();
    let mut chars = line.chars().peekable();
    while let Some(&c) = chars.peek() {
        if c.is_whitespace() {
            chars.next();
        } else if c == '{' {
            chars.next();
            let mut name = String::new();
            loop {
                match chars.next() {
                    Some('\\') => name.push(chars.next().ok_or("dangling escape")?),
                    Some('}') => break,
                    Some(x) => name.push(x),
                    None => return Err(format!("unclosed brace in `{line}`")),
                }
            }
            out.push(Tok::Name(name));
        } else if c.is_ascii_alphanumeric() || c == '_' || c == '\'' {
            let mut name = String::new();
            while let Some(&x) = chars.peek() {
                if x.is_ascii_alphanumeric() || x == '_' || x == '\'' {
                    name.push(x);
                    chars.next();
                } else {
                    break;
                }
            }
            out.push(Tok::Name(name));
        } else {
            out.push(Tok::Punct(c));
            chars.next();
        }
    }
    Ok(out)
}

/// A cursor over one line's tokens.
struct Line {
    toks: Vec<Tok>,
    at: usize,
}

impl Line {
    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.at)
    }
    fn punct(&mut self, c: char) -> bool {
        if self.peek() == Some(&Tok::Punct(c)) {
            self.at += 1;
            return true;
        }
        false
    }
    fn name(&mut self) -> Result<String, String> {
        match self.toks.get(self.at) {
            Some(Tok::Name(n)) => {
                self.at += 1;
                Ok(n.clone())
            }
            other => Err(format!("expected a name, found {other:?}")),
        }
    }
    fn int(&mut self) -> Result<u32, String> {
        let n = self.name()?;
        n.parse()
            .map_err(|_| format!("expected an integer, found `{n}`"))
    }
    fn done(&self) -> bool {
        self.at == self.toks.len()
    }
}

/// `[a,b]`, `]a,b[`, `[a,w[`... as written back.
fn interval(l: &mut Line) -> Result<Option<String>, String> {
    let open = match l.peek() {
        Some(Tok::Punct(c @ ('[' | ']'))) => *c,
        _ => return Ok(None),
    };
    l.at += 1;
    let low = l.int()?;
    if !l.punct(',') {
        return Err("expected `,` in an interval".into());
    }
    let high = l.name()?;
    if high != "w" && high.parse::<u32>().is_err() {
        return Err(format!("bad interval bound `{high}`"));
    }
    let close = match l.peek() {
        Some(Tok::Punct(c @ ('[' | ']'))) => *c,
        other => return Err(format!("expected `[` or `]`, found {other:?}")),
    };
    l.at += 1;
    if high == "w" && close != '[' {
        return Err("an infinite bound is open".into());
    }
    Ok(Some(format!("{open}{low},{high}{close}")))
}

/// One input arc: `p`, `p*w`, `p?w`, `p?-w`.
fn input(l: &mut Line) -> Result<Arc, String> {
    let place = l.name()?;
    if l.punct('*') {
        return Ok(Arc::Normal(place, l.int()?));
    }
    if l.punct('?') {
        if l.punct('-') {
            return Ok(Arc::Inhibitor(place, l.int()?));
        }
        return Ok(Arc::Test(place, l.int()?));
    }
    Ok(Arc::Normal(place, 1))
}

fn tr(l: &mut Line, label: String) -> Result<Tr, String> {
    let name = l.name()?;
    let interval = interval(l)?.unwrap_or_else(|| "[0,w[".into());
    let mut inputs = Vec::new();
    while !l.punct('-') {
        if l.done() {
            return Err(format!("`tr {name}` has no `->`"));
        }
        inputs.push(input(l)?);
    }
    if !l.punct('>') {
        return Err("expected `->`".into());
    }
    let mut outputs = Vec::new();
    while !l.done() {
        let place = l.name()?;
        let w = if l.punct('*') { l.int()? } else { 1 };
        outputs.push((place, w));
    }
    Ok(Tr {
        name,
        label,
        interval,
        inputs,
        outputs,
    })
}

/// Reads a `.net` text; `Err` names the first line that does not follow
/// the grammar.
pub fn parse(text: &str) -> Result<Net, String> {
    let mut net = Net::default();
    let mut comment = String::new();
    for (n, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if let Some(c) = line.strip_prefix('#') {
            comment = c.trim().to_owned();
            continue;
        }
        if line.is_empty() {
            continue;
        }
        let mut l = Line {
            toks: tokens(line)?,
            at: 0,
        };
        let err = |e: String| format!("line {}: {e}: `{line}`", n + 1);
        let keyword = l.name().map_err(err)?;
        match keyword.as_str() {
            "net" => net.name = l.name().map_err(err)?,
            "pl" => {
                let place = l.name().map_err(err)?;
                let marking = if l.punct('(') {
                    let m = l.int().map_err(err)?;
                    if !l.punct(')') {
                        return Err(err("expected `)`".into()));
                    }
                    m
                } else {
                    0
                };
                net.places.push((place, marking));
            }
            "tr" => net
                .transitions
                .push(tr(&mut l, std::mem::take(&mut comment)).map_err(err)?),
            "pr" => {
                let mut left = Vec::new();
                while !l.punct('>') {
                    if l.punct('<') || l.done() {
                        return Err(err("expected `>`".into()));
                    }
                    left.push(l.name().map_err(err)?);
                }
                let mut right = Vec::new();
                while !l.done() {
                    right.push(l.name().map_err(err)?);
                }
                net.priorities.push((left, right));
            }
            other => return Err(err(format!("unknown declaration `{other}`"))),
        }
        if !l.done() && keyword != "tr" {
            return Err(err("trailing tokens".into()));
        }
    }
    Ok(net)
}

impl Net {
    /// The net as a [`PetriNet`] the oracles' token game explores: each
    /// transition's priority is its rank in the `pr` relation (0 for a
    /// transition no `pr` puts above another, one more than the highest
    /// it is above otherwise); labels from the comments; step
    /// transitions (priority 0) are GenoM3 steps, the others settle steps.
    pub fn to_petri(&self) -> Result<PetriNet, String> {
        let index: BTreeMap<&str, usize> = self
            .places
            .iter()
            .enumerate()
            .map(|(k, (name, _))| (name.as_str(), k))
            .collect();
        let place = |name: &str| {
            index
                .get(name)
                .map(|&k| PlaceId::new(k))
                .ok_or_else(|| format!("undeclared place `{name}`"))
        };
        let rank = self.ranks()?;
        let mut transitions = Vec::new();
        for t in &self.transitions {
            let mut tr = Transition {
                name: t.name.clone(),
                label: t.label.clone(),
                span: Span::default(),
                priority: rank.get(t.name.as_str()).copied().unwrap_or(0),
                kind: TransitionKind::Genom3(G3Step::Settle),
                pre: Vec::new(),
                post: Vec::new(),
                read: Vec::new(),
                inhibit: Vec::new(),
            };
            for a in &t.inputs {
                match a {
                    Arc::Normal(p, w) => tr.pre.push((place(p)?, *w)),
                    Arc::Test(p, w) => tr.read.push((place(p)?, *w)),
                    Arc::Inhibitor(p, w) => tr.inhibit.push((place(p)?, *w)),
                }
            }
            for (p, w) in &t.outputs {
                tr.post.push((place(p)?, *w));
            }
            transitions.push(tr);
        }
        Ok(PetriNet {
            places: self
                .places
                .iter()
                .map(|(name, _)| Place {
                    name: name.clone(),
                    label: String::new(),
                    span: Span::default(),
                    kind: PlaceKind::Genom3(G3Place::Stage),
                })
                .collect(),
            transitions,
            initial: self.places.iter().map(|&(_, m)| m).collect(),
            services: Vec::new(),
            init_done: PlaceId::new(0),
            init_not_done: PlaceId::new(0),
        })
    }

    /// Each transition's rank in the `pr` relation (a longest path down
    /// the "is above" graph).
    fn ranks(&self) -> Result<BTreeMap<&str, u8>, String> {
        let mut above: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
        for (left, right) in &self.priorities {
            for l in left {
                above
                    .entry(l.as_str())
                    .or_default()
                    .extend(right.iter().map(String::as_str));
            }
        }
        let mut rank: BTreeMap<&str, u8> = BTreeMap::new();
        // Relax until stable: at most as many rounds as transitions.
        for _ in 0..=self.transitions.len() {
            let mut changed = false;
            for (&hi, lows) in &above {
                let need = lows
                    .iter()
                    .map(|lo| rank.get(lo).copied().unwrap_or(0) + 1)
                    .max()
                    .unwrap_or(0);
                if rank.get(hi).copied().unwrap_or(0) < need {
                    rank.insert(hi, need);
                    changed = true;
                }
            }
            if !changed {
                return Ok(rank);
            }
        }
        Err("the `pr` relation has a cycle".into())
    }
}
