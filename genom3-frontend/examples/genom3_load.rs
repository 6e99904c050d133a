//! `cargo run -p genom3-frontend --example genom3_load -- [-I DIR]... [--wcet FILE] FILE.gen`:
//! loads a GenoM3 file and prints a summary of the lowered component and
//! every diagnostic (a development aid until the CLI reads GenoM3).

#![allow(clippy::print_stdout)]

use std::path::PathBuf;

use genom_render::human::{HumanOptions, render_diagnostic};
use genom3_frontend::{Genom3Options, load};

fn main() {
    let mut options = Genom3Options {
        use_env_include_path: true,
        ..Genom3Options::default()
    };
    let mut files = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "-I" => options.include_dirs.extend(args.next().map(PathBuf::from)),
            "--wcet" => options.wcet_file = args.next().map(PathBuf::from),
            _ => files.push(PathBuf::from(a)),
        }
    }
    for f in files {
        let out = match load(&f, &options) {
            Ok(out) => out,
            Err(e) => {
                println!("{}: {e}", f.display());
                continue;
            }
        };
        for d in &out.diagnostics {
            println!(
                "{}",
                render_diagnostic(&out.sources, d, HumanOptions::default())
            );
        }
        let errors = out
            .diagnostics
            .iter()
            .filter(|d| d.severity == genom_model::Severity::Error)
            .count();
        println!("RESULT {} errors={errors}", f.display());
        match &out.component {
            Some(c) => {
                let g = c.genom3.as_deref();
                println!(
                    "{}: component {}: {} threads, {} services, {} codels, {} structures, {} ports, {} remotes, {} diagnostics",
                    f.display(),
                    c.name.name,
                    c.threads.len(),
                    c.services.len(),
                    c.codels.len(),
                    c.structures.len(),
                    g.map_or(0, |g| g.ports.len()),
                    g.map_or(0, |g| g.remotes.len()),
                    out.diagnostics.len()
                );
            }
            None => println!(
                "{}: no component (interface only: {}), {} diagnostics",
                f.display(),
                out.is_interface_only,
                out.diagnostics.len()
            ),
        }
    }
}
