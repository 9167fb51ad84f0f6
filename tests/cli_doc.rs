//! README's command synopsis ("What it does") and every command line README.md and docs/
//! show, against the parser (`squeal CMD --help`, which clap derives from the same
//! definitions that parse): a flag shown for a command must be one it accepts, and every
//! flag a command accepts must be in its synopsis line (the model flags of `trajectory`,
//! `classify`, `ulc` and `critical` may instead be in the section's text, where `MODEL` is
//! spelled out). docs/spec.md's keys are checked the same way by
//! crates/scan/tests/spec_doc.rs.

use std::collections::{BTreeMap, BTreeSet};
use std::process::Command;

const README: &str = include_str!("../README.md");
const DOCS: [(&str, &str); 3] = [
    ("README.md", README),
    ("docs/spec.md", include_str!("../docs/spec.md")),
    ("docs/atlas-spec.md", include_str!("../docs/atlas-spec.md")),
];

/// Every `--flag` in `text`.
fn flags(text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let b = text.as_bytes();
    let mut i = 0;
    while i + 2 < b.len() {
        let boundary = i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'-');
        if boundary && b[i] == b'-' && b[i + 1] == b'-' && b[i + 2].is_ascii_lowercase() {
            let end = (i + 2..b.len())
                .find(|&j| !(b[j].is_ascii_lowercase() || b[j].is_ascii_digit() || b[j] == b'-'))
                .unwrap_or(b.len());
            out.insert(text[i..end].trim_end_matches('-').to_string());
            i = end;
        } else {
            i += 1;
        }
    }
    out
}

/// The flags `squeal CMD --help` lists (its option lines), without --help and --version.
fn accepted(cmd: &str) -> BTreeSet<String> {
    let out = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args([cmd, "--help"])
        .output()
        .expect("running squeal");
    assert!(out.status.success(), "squeal {cmd} --help failed");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    text.lines()
        .map(str::trim_start)
        .filter(|l| l.starts_with('-'))
        .filter_map(|l| flags(l.split("  ").next().unwrap_or("")).into_iter().next())
        .filter(|f| f != "--help" && f != "--version")
        .collect()
}

/// The text of README's section `heading` (up to the next heading of the same level).
fn section<'a>(heading: &str) -> &'a str {
    let start = README.find(heading).expect("section heading");
    let rest = &README[start + heading.len()..];
    let end = rest.find("\n## ").unwrap_or(rest.len());
    &rest[..end]
}

/// Command lines shown in a document: lines of code blocks and inline code spans that start
/// with `squeal CMD` (or `target/release/squeal CMD`, `cargo run --release -- CMD`), as
/// (command, the rest of the line).
fn shown(doc: &str) -> Vec<(String, String)> {
    let mut lines: Vec<String> = Vec::new();
    let mut in_block = false;
    for line in doc.lines() {
        if line.trim_start().starts_with("```") {
            in_block = !in_block;
            continue;
        }
        if in_block {
            lines.push(line.trim().to_string());
        } else {
            lines.extend(line.split('`').skip(1).step_by(2).map(str::to_string));
        }
    }
    let mut out = Vec::new();
    for l in lines {
        for prefix in [
            "squeal ",
            "target/release/squeal ",
            "cargo run --release -- ",
        ] {
            if let Some(rest) = l.strip_prefix(prefix) {
                let cmd = rest.split_whitespace().next().unwrap_or("").to_string();
                // The flags before a comment only.
                let args = rest.split('#').next().unwrap_or("").to_string();
                out.push((cmd, args));
            }
        }
    }
    out
}

const COMMANDS: [&str; 11] = [
    "trajectory",
    "friction",
    "scan",
    "classify",
    "render",
    "info",
    "ulc",
    "critical",
    "atlas",
    "compare",
    "merge",
];

#[test]
fn every_command_line_shown_uses_flags_the_command_accepts() {
    let parser: BTreeMap<&str, BTreeSet<String>> =
        COMMANDS.iter().map(|c| (*c, accepted(c))).collect();
    let mut checked = 0;
    for (doc, text) in DOCS {
        for (cmd, args) in shown(text) {
            let Some(ok) = parser.get(cmd.as_str()) else {
                continue;
            };
            for f in flags(&args) {
                assert!(
                    ok.contains(&f),
                    "{doc} shows `squeal {cmd} ... {f}`, which `squeal {cmd}` does not accept \
                     (it accepts {ok:?}): {args}"
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 50, "only {checked} flags checked");
}

#[test]
fn the_synopsis_lists_every_command_and_flag() {
    let what = section("## What it does");
    let block = what.split("```").nth(1).expect("the synopsis code block");
    let mut synopsis: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (cmd, args) in shown(&format!("```\n{block}\n```")) {
        let mut f = flags(&args);
        // `-o` is the short form of `--out`.
        if args.split(['[', ' ']).any(|t| t == "-o") {
            f.insert("--out".into());
        }
        synopsis.entry(cmd).or_default().extend(f);
    }
    let mut missing = Vec::new();
    for cmd in COMMANDS {
        let shown = synopsis
            .get(cmd)
            .unwrap_or_else(|| panic!("README's synopsis has no line for `squeal {cmd}`"));
        // MODEL is spelled out in the section's text.
        let model_cmd = matches!(cmd, "trajectory" | "classify" | "ulc" | "critical");
        let described = if model_cmd {
            flags(what)
        } else {
            BTreeSet::new()
        };
        for f in accepted(cmd) {
            if !(shown.contains(&f) || described.contains(&f)) {
                missing.push(format!("squeal {cmd} {f}"));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "flags the parser accepts that README's synopsis (\"What it does\") does not show: {missing:?}"
    );
}

#[test]
fn flags_are_found_in_text() {
    let f = flags("squeal x --m 2 --v-belt 0.05 (--tau-s) a--b `--json`");
    let want: BTreeSet<String> = ["--m", "--v-belt", "--tau-s", "--json"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    assert_eq!(f, want);
}
