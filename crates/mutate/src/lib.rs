//! The shipped specs of `scans/` and paths to their numbers, shared by the spec mutations
//! of `crates/scan/tests/scanning/shipped_mutations.rs` (the parser) and the fuzz run of the
//! binary (`tests/e2e/fuzz.rs`). A dev-dependency of both; no product code uses it.

use toml::Value;

/// One step of the path to a value: a table key or a list index.
#[derive(Clone, Debug)]
pub enum Step {
    Key(String),
    Index(usize),
}

/// Paths to every integer and float in `v`.
pub fn numbers(v: &Value, path: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    match v {
        Value::Integer(_) | Value::Float(_) => out.push(path.clone()),
        Value::Table(t) => {
            for (k, x) in t {
                path.push(Step::Key(k.clone()));
                numbers(x, path, out);
                path.pop();
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                path.push(Step::Index(i));
                numbers(x, path, out);
                path.pop();
            }
        }
        _ => {}
    }
}

pub fn at<'a>(v: &'a mut Value, path: &[Step]) -> &'a mut Value {
    path.iter().fold(v, |v, s| match s {
        Step::Key(k) => &mut v.as_table_mut().unwrap()[k.as_str()],
        Step::Index(i) => &mut v.as_array_mut().unwrap()[*i],
    })
}

/// A shipped spec: its file name, whether it is an atlas spec, its TOML and the paths to
/// its numbers.
pub struct Shipped {
    pub name: String,
    pub atlas: bool,
    pub spec: Value,
    pub paths: Vec<Vec<Step>>,
}

pub fn shipped(dir: &std::path::Path) -> Vec<Shipped> {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
        .iter()
        .map(|file| {
            let name = file.file_name().unwrap().to_string_lossy().into_owned();
            let spec: Value = toml::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
            let mut paths = Vec::new();
            numbers(&spec, &mut Vec::new(), &mut paths);
            Shipped {
                // atlas-*.toml, or a spec without [grid] and [sample] (a scan needs one).
                atlas: name.starts_with("atlas-")
                    || spec.get("grid").is_none() && spec.get("sample").is_none(),
                name,
                spec,
                paths,
            }
        })
        .collect()
}
