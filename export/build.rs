//! Build script of genom-export: tells the SVG rendering test whether
//! this machine has a font to lay its texts out with, so that without one
//! the text test shows as `ignored` with its reason instead of failing or
//! passing without running. `cfg(genom_fonts)`: a `.ttf`/`.otf`/`.ttc`
//! file in the usual font folders (or `GENOM_REQUIRE_FONTS=1`, which makes
//! their absence a failure).

use std::path::Path;

const FOLDERS: [&str; 3] = [
    "/usr/share/fonts",
    "/usr/local/share/fonts",
    "/Library/Fonts",
];

/// Whether `dir` holds a font file, at most `depth` folders down.
fn has_font(dir: &Path, depth: u32) -> bool {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return false;
    };
    entries.flatten().any(|e| {
        let path = e.path();
        if path.is_dir() {
            return depth > 0 && has_font(&path, depth - 1);
        }
        path.extension()
            .and_then(|x| x.to_str())
            .is_some_and(|x| matches!(x.to_ascii_lowercase().as_str(), "ttf" | "otf" | "ttc"))
    })
}

fn main() {
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-env-changed=GENOM_REQUIRE_FONTS");
    println!("cargo::rustc-check-cfg=cfg(genom_fonts)");
    let required = std::env::var("GENOM_REQUIRE_FONTS").is_ok_and(|v| v == "1");
    let home = std::env::var_os("HOME").map(|h| Path::new(&h).join(".fonts"));
    let found = FOLDERS
        .iter()
        .map(Path::new)
        .chain(home.as_deref())
        .any(|d| has_font(d, 4));
    if required || found {
        println!("cargo::rustc-cfg=genom_fonts");
    }
}
