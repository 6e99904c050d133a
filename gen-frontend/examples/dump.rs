//! Prints the AST and diagnostics of a file (debugging aid).
#![allow(clippy::print_stdout)]
fn main() {
    let path = std::env::args().nth(1).unwrap_or_default();
    match gen_frontend::parse_file(std::path::Path::new(&path), &gen_frontend::FsLoader) {
        Ok(r) => {
            println!("{:#?}", r.ast);
            for d in &r.diagnostics {
                println!(
                    "{}",
                    genom_render::human::render_diagnostic(&r.sources, d, Default::default())
                );
            }
        }
        Err(e) => println!("cannot read {path}: {e}"),
    }
}
