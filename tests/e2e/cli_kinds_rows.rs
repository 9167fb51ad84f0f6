//! What a command says of a file it was given: squeal's own files of another kind named as
//! what they are, rows of extra values refused naming the row, numbers written compactly.

use std::path::Path;
use std::process::{Command, Output};

fn squeal(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the squeal binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn refused(o: &Output, needles: &[&str]) -> String {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "should fail with code 2: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
    for n in needles {
        assert!(err.contains(n), "the message should hold {n:?}: {err}");
    }
    err
}

/// A row of initial conditions with more values than the header names (`0,0,0` under
/// `x0,v0`) had its third value dropped without a word, while a friction CSV's row of three
/// numbers is refused. It is refused naming the line, the row and the header.
#[test]
fn an_initial_conditions_row_of_extra_values_is_refused_naming_the_line() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("ics.csv"), "x0,v0\n0.5,0.0\n0,0,0\n").unwrap();
    let o = squeal(
        d.path(),
        &["classify", "--ics", "ics.csv", "--out", "l.csv"],
    );
    refused(
        &o,
        &["ics.csv:3", "`0,0,0` holds 3 value(s)", "`x0,v0` names 2"],
    );
    assert!(!d.path().join("l.csv").exists());
}

/// `compare` of a scan and a trajectory (or an atlas) said the second was "not a squeal
/// file": it names what each file is and what compare takes.
#[test]
fn compare_names_a_trajectory_or_an_atlas_as_what_it_is() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    std::fs::write(
        dir.join("s.toml"),
        "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = 1e-2\n[grid]\n\
         x0 = { min = 0.0, max = 2.0, count = 3 }\nv0 = { min = -1.0, max = 1.0, count = 3 }\n\
         [classifier]\nt_max = 500.0\n[output]\npath = \"s.h5\"\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("a.toml"),
        "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = 1e-2\n[boundaries]\nfold = false\n\
         critical = false\n[output]\npath = \"a.h5\"\n",
    )
    .unwrap();
    for args in [
        &["scan", "s.toml", "--quiet"][..],
        &["atlas", "a.toml", "--quiet"],
        &["trajectory", "--t-end", "10", "--out", "t.h5"],
    ] {
        let o = squeal(dir, args);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    }
    for (first, second, other, is) in [
        ("s.h5", "t.h5", "t.h5", "is a trajectory"),
        ("t.h5", "s.h5", "t.h5", "is a trajectory"),
        ("s.h5", "a.h5", "a.h5", "is an atlas"),
    ] {
        let o = squeal(dir, &["compare", first, second]);
        let err = refused(&o, &[&format!("{other} {is}"), "compare takes two scans"]);
        assert!(!err.contains("not a squeal file"), "{err}");
    }
}

/// `info` wrote a friction table's slip speed 1e300 with 301 digits (and 1e-300 as 300
/// zeros after the point): every number it prints is written as the error messages write
/// them, the shortest that reads back, in exponent form for a huge or tiny magnitude.
#[test]
fn info_writes_huge_and_tiny_numbers_compactly() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    std::fs::write(dir.join("pad.csv"), "0,0.5\n1e-300,0.45\n1e300,0.4\n").unwrap();
    let o = squeal(
        dir,
        &[
            "trajectory",
            "--law",
            "table",
            "--friction-csv",
            "pad.csv",
            "--t-end",
            "10",
            "--out",
            "t.h5",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = squeal(dir, &["info", "t.h5"]);
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(text.contains("1e300") && text.contains("1e-300"), "{text}");
    // No number of more digits than an f64 needs (17), as 1e300 written out has 301.
    let longest = text
        .split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0);
    assert!(longest <= 17, "a number of {longest} digits: {text}");
}
