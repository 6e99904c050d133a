//! The comparison itself (ignored without `GENOM3`): `genom3` and
//! `genom-check` must accept and reject the same corpus files and mutants.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::Command;

use super::support::*;

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
