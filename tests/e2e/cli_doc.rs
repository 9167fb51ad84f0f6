//! The command synopsis of docs/cli.md ("What it does") and every command line README.md
//! and the pages of docs/ show, against the parser (`squeal CMD --help`, which clap derives
//! from the same definitions that parse): a flag shown for a command must be one it
//! accepts, and every flag a command accepts must be in its synopsis line (the model flags
//! of `trajectory`, `classify`, `ulc` and `critical` may instead be in the section's text,
//! where `MODEL` is spelled out). The README's tour is run: each command shown with its
//! output must print that output. docs/spec.md's keys are checked the same way by
//! crates/scan/tests/scanning/spec_doc.rs.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::process::Command;

const README: &str = include_str!("../../README.md");
const CLI: &str = include_str!("../../docs/cli.md");

/// Pages of docs/ whose command lines are not today's: a worked extension with a law that
/// does not exist, and the dated record of earlier versions (every page under it).
const NOT_TODAY: [&str; 2] = ["docs/extending.md", "docs/history/"];

/// README.md and every page under docs/ but [`NOT_TODAY`], as (path, text).
fn docs() -> Vec<(String, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = vec![("README.md".to_string(), README.to_string())];
    let mut dirs = vec![root.join("docs")];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).expect("reading docs/") {
            let path = entry.expect("reading docs/").path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                let text = std::fs::read_to_string(&path).expect("reading a page of docs/");
                let name = path
                    .strip_prefix(root)
                    .unwrap_or(&path)
                    .display()
                    .to_string();
                if !NOT_TODAY.iter().any(|p| name.starts_with(p)) {
                    out.push((name, text));
                }
            }
        }
    }
    assert!(
        out.len() > 8,
        "README.md and docs/: only {} pages",
        out.len()
    );
    out
}

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

/// The text of docs/cli.md's section `heading` (up to the next heading of the same level).
fn section<'a>(heading: &str) -> &'a str {
    let start = CLI.find(heading).expect("section heading");
    let rest = &CLI[start + heading.len()..];
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
    for (doc, text) in docs() {
        for (cmd, args) in shown(&text) {
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
            .unwrap_or_else(|| panic!("docs/cli.md's synopsis has no line for `squeal {cmd}`"));
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
        "flags the parser accepts that docs/cli.md's synopsis (\"What it does\") does not show: \
         {missing:?}"
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

/// The fenced code blocks of `doc` in order, as (info string, body, index of the line after
/// the closing fence, index of the opening fence's line).
fn blocks(doc: &str) -> Vec<(String, String, usize, usize)> {
    let lines: Vec<&str> = doc.lines().collect();
    let mut out = Vec::new();
    let mut open: Option<(String, usize)> = None;
    let mut body = String::new();
    for (i, line) in lines.iter().enumerate() {
        let Some(info) = line.trim_start().strip_prefix("```") else {
            if open.is_some() {
                body.push_str(line);
                body.push('\n');
            }
            continue;
        };
        match open.take() {
            None => open = Some((info.trim().to_string(), i)),
            Some((lang, start)) => out.push((lang, std::mem::take(&mut body), i + 1, start)),
        }
    }
    out
}

/// The README's commands shown with their output: a ```sh block of `squeal` command lines
/// followed (blank lines apart) by a ```text block, as (command lines, output lines).
fn shown_with_output() -> Vec<(Vec<String>, Vec<String>)> {
    let lines: Vec<&str> = README.lines().collect();
    let b = blocks(README);
    let mut out = Vec::new();
    for pair in b.windows(2) {
        let ((lang, cmds, end, _), (next, text, _, start)) = (&pair[0], &pair[1]);
        let adjacent = lines[*end..*start].iter().all(|l| l.trim().is_empty());
        if lang == "sh" && next == "text" && adjacent {
            let cmds: Vec<String> = cmds.lines().map(str::to_string).collect();
            assert!(
                cmds.iter().all(|c| c.starts_with("squeal ")),
                "README shows output for a block that is not all `squeal` commands: {cmds:?}"
            );
            out.push((cmds, text.lines().map(str::to_string).collect()));
        }
    }
    out
}

/// Each output line the README shows must be printed, in the order shown (stdout and
/// stderr together); a line ending in ` ...` is the start of a printed line.
#[test]
#[ignore = "long check (a minute or more on 2 cores): run by scripts/ci/long-checks.sh, which .ci/run calls"]
fn the_readme_tour_prints_what_it_shows() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let shown = shown_with_output();
    assert!(
        shown.len() >= 3,
        "only {} commands with output",
        shown.len()
    );
    for (cmds, want) in shown {
        // A fresh folder with the shipped specs and their data (the friction curves), as a
        // checkout: outputs land in its out/.
        let dir = tempfile::tempdir().expect("a temporary folder");
        std::fs::create_dir_all(dir.path().join("scans/data")).unwrap();
        for entry in std::fs::read_dir(root.join("scans/data")).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "csv") {
                let to = dir
                    .path()
                    .join("scans/data")
                    .join(path.file_name().unwrap());
                std::fs::copy(&path, to).unwrap();
            }
        }
        for entry in std::fs::read_dir(root.join("scans")).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "toml") {
                std::fs::copy(
                    &path,
                    dir.path().join("scans").join(path.file_name().unwrap()),
                )
                .unwrap();
            }
        }
        let mut printed = Vec::new();
        for cmd in &cmds {
            let args: Vec<&str> = cmd.split_whitespace().skip(1).collect();
            let out = Command::new(env!("CARGO_BIN_EXE_squeal"))
                .args(&args)
                .current_dir(dir.path())
                .output()
                .expect("running squeal");
            assert!(out.status.success(), "`{cmd}` failed: {out:?}");
            for stream in [&out.stdout, &out.stderr] {
                printed.extend(
                    String::from_utf8_lossy(stream)
                        .lines()
                        .map(|l| l.trim().to_string()),
                );
            }
        }
        let mut at = 0;
        for line in &want {
            let line = line.trim();
            let found = match line.strip_suffix(" ...") {
                Some(start) => printed[at..].iter().position(|p| p.starts_with(start)),
                None => printed[at..].iter().position(|p| p == line),
            };
            let Some(k) = found else {
                panic!(
                    "README shows `{line}` for {cmds:?}, which printed (from line {at}):\n{}",
                    printed[at..].join("\n")
                );
            };
            at += k + 1;
        }
    }
}

/// docs/model.md and docs/atlas-spec.md said the table law had "no `[physical]` yet", while
/// README, engineers.md and spec.md use it and `scans/brake-curve.toml` is one: an atlas of a
/// pad on a measured curve under `[physical]`, which the parser takes. No page says "yet"
/// of `[physical]` now.
#[test]
fn no_page_denies_the_table_law_its_physical_system() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = root.join("scans/brake-curve.toml");
    let spec = std::fs::read_to_string(&path).unwrap();
    assert!(spec.contains("law = \"table\"") && spec.contains("[physical]"));
    let plan = squeal_scan::atlas::AtlasPlan::from_toml(&spec, &path.display().to_string())
        .expect("a [physical] spec of the table law");
    assert_eq!(plan.space.law, squeal_core::FrictionLaw::Table);
    // A slice of `s` widened to whole characters (docs have non-ASCII letters).
    let cut = |s: &str, mut a: usize, mut b: usize| -> String {
        b = b.min(s.len());
        while !s.is_char_boundary(a) {
            a -= 1;
        }
        while !s.is_char_boundary(b) {
            b += 1;
        }
        s[a..b].to_string()
    };
    for (page, text) in docs() {
        let flat = text.split_whitespace().collect::<Vec<_>>().join(" ");
        for (at, _) in flat.match_indices("`[physical]`") {
            let after = cut(&flat, at, at + 40);
            let before = cut(&flat, at.saturating_sub(4), at);
            assert!(
                !after.contains(" yet") && !before.trim().eq_ignore_ascii_case("no"),
                "{page}: \"{}\"",
                cut(&flat, at.saturating_sub(60), at + 60)
            );
        }
    }
}
