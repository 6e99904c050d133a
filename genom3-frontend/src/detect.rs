//! Dialect detection by syntax: tells a GenoM3 file from a LANGUAGE.md one
//! without parsing it.

/// True when `text` reads as GenoM3: a preprocessor line (`#pragma`,
/// `#ifndef`, `#define`...; `#include` is LANGUAGE.md syntax too), a
/// colon-less property such as `version "1";`,
/// or a GenoM3-only keyword (`task`, `activity`, `function`, `attribute`,
/// `port`, `interface`) opening a line.
pub fn looks_like_genom3(text: &str) -> bool {
    let mut in_comment = false;
    for raw in text.lines() {
        let mut line = raw.trim();
        if in_comment {
            match line.find("*/") {
                Some(i) => {
                    in_comment = false;
                    line = line[i + 2..].trim();
                }
                None => continue,
            }
        }
        if line.starts_with("/*") && !line.contains("*/") {
            in_comment = true;
            continue;
        }
        if line.starts_with("//") || line.is_empty() {
            continue;
        }
        if let Some(directive) = line.strip_prefix('#') {
            let word = directive.trim_start();
            // `#include` is also LANGUAGE.md syntax: it decides nothing.
            if ["pragma", "ifndef", "ifdef", "define", "if "]
                .iter()
                .any(|w| word.starts_with(w))
            {
                return true;
            }
        }
        let mut words = line.split_whitespace();
        let first = words.next().unwrap_or("");
        let second = words.next().unwrap_or("");
        if matches!(
            first,
            "version" | "lang" | "email" | "require" | "codels-require"
        ) && second.starts_with('"')
        {
            return true;
        }
        if matches!(first, "activity" | "function" | "attribute" | "interface")
            || (first == "task" && !second.starts_with(':'))
            || (first == "port" && matches!(second, "in" | "out" | "multiple"))
        {
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::looks_like_genom3;

    #[test]
    fn genom3_by_directive_property_or_keyword() {
        assert!(looks_like_genom3("#pragma require \"x\"\ncomponent a {};"));
        assert!(looks_like_genom3("component a {\n  version \"1.0\";\n};"));
        assert!(looks_like_genom3("component a {\n  activity go() { };\n};"));
        assert!(looks_like_genom3("/* c\n*/\n#ifndef X\n"));
        assert!(!looks_like_genom3(
            "#include \"x.idl\"\ncomponent c {\n  lang: C;\n};\n"
        ));
    }

    #[test]
    fn language_md_files_are_not_genom3() {
        let text = "component demo {\n  version: \"1.0\";\n};\nthread main { period: 10ms; };\n";
        assert!(!looks_like_genom3(text));
        assert!(!looks_like_genom3("include \"a.idl\";\n"));
    }
}
