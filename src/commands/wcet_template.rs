//! `genom-check wcet-template FILE [-o PATH]`: a WCET file to start from
//! for a GenoM3 component (`genom3_frontend::wcet_template`): every codel
//! that can take time, one line each with the placeholder `?`, which
//! `--wcet` accepts unchanged. The component is read and checked
//! statically only (it need not verify: WCETs are what it lacks). A file
//! whose component cannot be read (syntax errors...) gets its report as
//! `check` prints it and exit 1; a LANGUAGE.md file, whose codels carry
//! their own `wcet:`, is a usage error (exit 2). With `-o`, the file is
//! written as [`crate::output`] says: never over an input of the run.

use genom_check::CheckOptions;
use genom_model::Dialect;
use genom_render::FileReport;

use super::{EXIT_ERRORS, EXIT_OK, EXIT_USAGE};
use crate::cli::{OutputArgs, WcetTemplateArgs};
use crate::output::{Input, Plan};
use crate::terminal;

/// Writes the template; returns the exit status.
pub fn run(args: &WcetTemplateArgs, output: &OutputArgs) -> u8 {
    let shown = genom_check::display(&args.file);
    let options = CheckOptions::new().behaviour(false);
    let result = match genom_check::check_path(&args.file, &args.input.inputs(), &options) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {}", genom_render::escaped(&e.to_string()));
            return EXIT_USAGE;
        }
    };
    if result.dialect != Dialect::Genom3 {
        eprintln!(
            "error: `{}` was read as LANGUAGE.md, whose codels carry their own `wcet:`; \
             `wcet-template` writes WCET files of GenoM3 components",
            genom_render::escaped(&shown)
        );
        return EXIT_USAGE;
    }
    let template = result.component.as_ref().and_then(|c| {
        let name = args
            .file
            .file_name()
            .map_or_else(|| shown.clone(), |n| n.to_string_lossy().into_owned());
        genom3_frontend::wcet_template(c, &name, env!("CARGO_PKG_VERSION"))
    });
    let Some(template) = template else {
        report(&result.report(&shown), output);
        eprintln!(
            "error: `{}` has no component to write WCETs for",
            genom_render::escaped(&shown)
        );
        return EXIT_ERRORS;
    };
    write(args, &template, &result)
}

/// The check's report on stderr, as `check` prints it (stdout may carry
/// the template).
fn report(report: &FileReport<'_>, output: &OutputArgs) {
    eprint!(
        "{}",
        super::check::human_report(std::slice::from_ref(report), output, false)
    );
}

/// Writes the template to stdout or `-o`.
fn write(args: &WcetTemplateArgs, template: &str, result: &genom_check::CheckResult) -> u8 {
    let Some(path) = &args.output else {
        terminal::emit(template);
        return EXIT_OK;
    };
    let mut inputs = vec![Input {
        path: &args.file,
        role: "the checked file",
    }];
    if let Some(wcet) = &args.input.wcet {
        inputs.push(Input {
            path: wcet,
            role: "the WCET file",
        });
    }
    for (_, file) in result.sources.files().skip(1) {
        if !file.path.as_os_str().to_string_lossy().starts_with('<') {
            inputs.push(Input {
                path: &file.path,
                role: "an included file",
            });
        }
    }
    let done = Plan::new(path, template, &[])
        .and_then(|plan| plan.refuse_inputs(&inputs).map(|()| plan))
        .and_then(Plan::write);
    match done {
        Ok(()) => {
            eprintln!("wrote `{}`", terminal::shown(path));
            EXIT_OK
        }
        Err(e) => {
            eprintln!("error: {e}");
            EXIT_USAGE
        }
    }
}
