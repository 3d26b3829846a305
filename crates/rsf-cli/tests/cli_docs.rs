//! The CLI reference (docs/cli.md) cannot go stale: every long option that `rsf <cmd> --help`
//! prints must appear in it. Regenerate it with `bash docs/make_cli.sh`.

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::process::Command;

/// The help text of `rsf <args> --help`.
fn help(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_rsf")).args(args).arg("--help").output().unwrap();
    assert!(out.status.success(), "rsf {args:?} --help: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

/// The long options (`--name`) in the option lines of a help text: lines whose first word
/// starts with `-`, as clap prints them (`  -o, --output <OUTPUT>  …`, `      --json  …`).
fn long_options(help: &str) -> BTreeSet<String> {
    help.lines()
        .filter(|l| l.trim_start().starts_with('-'))
        .flat_map(|l| l.split(|c: char| c.is_whitespace() || c == ',' || c == '=' || c == '<'))
        .filter(|w| w.starts_with("--") && w.len() > 2)
        .map(str::to_string)
        .collect()
}

/// The subcommands listed by `rsf --help` (without `help`).
fn subcommands() -> Vec<String> {
    let top = help(&[]);
    let list: Vec<String> = top
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .map(str::to_string)
        .collect();
    for expected in ["simulate", "segments", "fit", "diagnose"] {
        assert!(list.iter().any(|c| c == expected), "`rsf --help` does not list {expected}: {list:?}");
    }
    list
}

fn reference() -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/cli.md");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn every_long_option_is_in_the_cli_reference() {
    let doc = reference();
    let mut missing = vec![];
    let mut total = 0;
    let subs = subcommands();
    let commands = std::iter::once(vec![]).chain(subs.iter().map(|c| vec![c.as_str()]));
    for cmd in commands {
        let opts = long_options(&help(&cmd));
        assert!(opts.contains("--help"), "no options parsed from `rsf {cmd:?} --help`");
        total += opts.len();
        for o in opts {
            // the option as the reference prints it: followed by a space, `<` or end of line
            let documented = doc.match_indices(&o).any(|(i, _)| {
                doc[i + o.len()..].chars().next().is_none_or(|c| !(c.is_alphanumeric() || c == '-' || c == '_'))
            });
            if !documented {
                missing.push(format!("rsf {} {o}", cmd.join(" ")));
            }
        }
    }
    assert!(total > 40, "only {total} options found: has the help format changed?");
    assert!(missing.is_empty(), "not in docs/cli.md (run `bash docs/make_cli.sh`): {missing:?}");
}

#[test]
fn every_subcommand_has_a_section() {
    let doc = reference();
    for cmd in subcommands() {
        assert!(doc.contains(&format!("## `rsf {cmd}`")), "docs/cli.md has no section for `rsf {cmd}`");
        assert!(doc.contains(&format!("$ rsf {cmd} --help")), "docs/cli.md lacks `rsf {cmd} --help`");
    }
}

/// Each subcommand's own help opens with the summary `rsf --help` lists for it (deferred
/// subcommands build their arguments late; a flattened argument group must not replace it).
#[test]
fn each_subcommand_help_opens_with_its_summary() {
    let top = help(&[]);
    for sub in subcommands() {
        let listed = top
            .lines()
            .find(|l| l.split_whitespace().next() == Some(sub.as_str()))
            .map(|l| l.trim_start()[sub.len()..].trim().to_string())
            .unwrap();
        let own = help(&[sub.as_str()]);
        let first = own.lines().next().unwrap_or_default().trim_end_matches('.');
        assert!(
            listed.starts_with(first) && !first.is_empty(),
            "rsf {sub} --help opens with {first:?}, listed as {listed:?}"
        );
    }
}
