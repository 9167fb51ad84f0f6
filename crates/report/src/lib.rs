//! # squeal-report: a self-contained interactive page of a squeal file
//!
//! [`page`] turns a file read by [`squeal_store::dump::dump`] (a scan, an atlas or a
//! trajectory) into one HTML file that opens offline in any browser: the data, the page's
//! script and the charting library (plotly.js, MIT, vendored in `assets/`) are all inside
//! it, and it loads nothing from the network. The page draws, for
//!
//! * a scan: each basin map (a slider steps through the swept values), the located unstable
//!   cycle and the fixed point, basin stability with its error, and every parameter;
//!   hovering a cell shows its start (in SI where the system is physical), label, reason,
//!   decision time and the oscillation its run reached;
//! * an atlas: the chart of regimes; hovering a point shows its regime, critical damping and
//!   fold with their intervals and note; clicking it shows its basin map (where the atlas has
//!   maps), its cycle and attractor figures, and the commands that reproduce it alone;
//! * a trajectory: the time series and the phase plane, zoomable, in SI where physical;
//!
//! and the provenance (spec, version, revision, the command that remakes the file).
//!
//! The data travel as typed arrays (per-cell maps as 32-bit floats, coordinates as 64-bit),
//! zlib-compressed and base64-encoded; the page inflates them with the browser's own
//! `DecompressionStream`.

use std::io::Write;
use std::path::{Path, PathBuf};

use serde_json::{Map, Value as Json, json};
use squeal_store::dump::{Data, Dump, Kind, Value};

/// The charting library, vendored (`assets/README.md` says which and how to update it).
const PLOTLY: &str = include_str!("../assets/plotly-cartesian.min.js");
/// Its licence, carried in the page beside it.
const PLOTLY_LICENSE: &str = include_str!("../assets/plotly-LICENSE");
/// The page's own script, style and frame.
const SCRIPT: &str = include_str!("page.js");
const STYLE: &str = include_str!("page.css");
const FRAME: &str = include_str!("page.html");

/// Where a page came from: the file's path as given, and squeal's version.
#[derive(Clone, Debug)]
pub struct Source<'a> {
    /// The file shown, as the user named it.
    pub file: &'a str,
    /// The squeal that wrote the page.
    pub version: &'a str,
}

/// Why a report was not written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReportError {
    /// The file could not be read as a squeal file.
    #[error(transparent)]
    Store(#[from] squeal_store::StoreError),
    /// The output's name does not end in `.html`.
    #[error("{}: expected a file name ending in .html", .0.display())]
    NotHtml(PathBuf),
    /// The output exists (and `force` was not given).
    #[error("{} exists (use --force to overwrite it)", .0.display())]
    Exists(PathBuf),
    /// Something other than a regular file is at the output.
    #[error(transparent)]
    NotRegular(#[from] squeal_scan::files::NotRegular),
    /// Writing failed.
    #[error("{}: cannot write the report: {source}", path.display())]
    Write {
        /// The output.
        path: PathBuf,
        /// The system's reason.
        source: std::io::Error,
    },
}

/// Where the report of `file` goes by default: beside it, `.html` for `.h5`.
pub fn default_out(file: &Path) -> PathBuf {
    file.with_extension("html")
}

/// Writes the report of `file` to `out` (default: [`default_out`]) and returns its path.
/// The output is checked before the file is read (a name ending in `.html`, nothing but a
/// regular file there, not overwritten without `force`), and written whole or not at all
/// (a temporary file beside it, renamed).
pub fn write(
    file: &Path,
    out: Option<&Path>,
    force: bool,
    version: &str,
) -> Result<PathBuf, ReportError> {
    let out = out.map_or_else(|| default_out(file), Path::to_path_buf);
    if out.extension().and_then(|e| e.to_str()) != Some("html") {
        return Err(ReportError::NotHtml(out));
    }
    squeal_scan::files::refuse_non_regular(&out)?;
    if !force && out.exists() {
        return Err(ReportError::Exists(out));
    }
    let dump = squeal_store::dump::dump(file)?;
    let shown = file.display().to_string();
    let html = page(
        &dump,
        &Source {
            file: &shown,
            version,
        },
    );
    let err = |source| ReportError::Write {
        path: out.clone(),
        source,
    };
    let mut tmp = out.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = PathBuf::from(tmp);
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(err)?;
    }
    std::fs::write(&tmp, html).map_err(err)?;
    if !force && out.exists() {
        let _ = std::fs::remove_file(&tmp);
        return Err(ReportError::Exists(out));
    }
    std::fs::rename(&tmp, &out).map_err(err)?;
    Ok(out)
}

/// The page of `dump`.
pub fn page(dump: &Dump, source: &Source) -> String {
    let data = payload(dump, source).to_string();
    // A spec or note holding "</script>" must not end the data block.
    let data = data.replace("</", "<\\/");
    let title = format!("squeal report: {}", escape(source.file));
    let license = PLOTLY_LICENSE.replace("*/", "* /");
    FRAME
        .replace("{{TITLE}}", &title)
        .replace("{{STYLE}}", STYLE)
        .replace("{{DATA}}", &data)
        .replace(
            "{{PLOTLY}}",
            &format!("/*! plotly.js, bundled with squeal's report.\n{license}*/\n{PLOTLY}"),
        )
        .replace("{{SCRIPT}}", SCRIPT)
}

/// The data block: the file's kind, attributes and datasets, with how they were thinned.
fn payload(d: &Dump, source: &Source) -> Json {
    let mut vars = Map::new();
    for v in &d.vars {
        let two_d = v.shape.len() >= 2;
        vars.insert(
            v.name.clone(),
            json!({
                "shape": v.shape,
                "dims": v.dims,
                "attrs": attrs(&v.attrs),
                "data": encode(&v.data, two_d),
            }),
        );
    }
    json!({
        "kind": match d.kind { Kind::Scan => "scan", Kind::Atlas => "atlas", Kind::Trajectory => "trajectory" },
        "file": source.file,
        "report_version": source.version,
        "attrs": attrs(&d.attrs),
        "vars": vars,
        "map_stride": d.map_stride,
        "map_size": d.map_size,
        "sample_stride": d.sample_stride,
        "samples": d.samples,
    })
}

fn attrs(a: &[(String, Value)]) -> Json {
    let mut m = Map::new();
    for (k, v) in a {
        let j = match v {
            Value::Text(t) => Json::from(t.clone()),
            Value::Numbers(n) if n.len() == 1 => number(n[0]),
            Value::Numbers(n) => Json::from(n.iter().map(|x| number(*x)).collect::<Vec<_>>()),
        };
        m.insert(k.clone(), j);
    }
    Json::Object(m)
}

/// A number for JSON: NaN and infinities as the strings JavaScript's `Number()` reads.
fn number(x: f64) -> Json {
    if x.is_finite() {
        json!(x)
    } else if x.is_nan() {
        json!("NaN")
    } else if x > 0.0 {
        json!("Infinity")
    } else {
        json!("-Infinity")
    }
}

/// An array as `{type, b64}`: little-endian bytes, zlib-compressed, base64; text as a list.
fn encode(data: &Data, two_d: bool) -> Json {
    let (ty, bytes): (&str, Vec<u8>) = match data {
        Data::Text(t) => return json!({"type": "text", "values": t}),
        Data::Byte(b) => ("u8", b.clone()),
        // Per-cell maps as f32 (seven digits: more than a page shows), halving the page.
        Data::Float(f) if two_d => (
            "f32",
            f.iter().flat_map(|x| (*x as f32).to_le_bytes()).collect(),
        ),
        Data::Float(f) => ("f64", f.iter().flat_map(|x| x.to_le_bytes()).collect()),
    };
    json!({"type": ty, "b64": base64(&deflate(&bytes))})
}

fn deflate(bytes: &[u8]) -> Vec<u8> {
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
    // Writing to a Vec cannot fail.
    z.write_all(bytes).expect("write to memory");
    z.finish().expect("write to memory")
}

/// Standard base64 with padding (RFC 4648), as `atob` reads it.
fn base64(bytes: &[u8]) -> String {
    const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for c in bytes.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for (i, shift) in [18, 12, 6, 0].into_iter().enumerate() {
            if i <= c.len() {
                out.push(ABC[((n >> shift) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// Text for HTML.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// RFC 4648 section 10's test vectors.
    #[test]
    fn base64_matches_the_rfc_vectors() {
        for (plain, coded) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(plain.as_bytes()), coded);
        }
    }

    /// A page carries its data, the library and the script, and nothing that loads from
    /// elsewhere: no `src=` or `href=` attribute in the page's own frame.
    #[test]
    fn the_page_is_self_contained() {
        let d = Dump {
            kind: Kind::Trajectory,
            attrs: vec![("spec".into(), Value::Text("a </script> in text".into()))],
            vars: vec![],
            map_stride: 1,
            map_size: None,
            sample_stride: 1,
            samples: Some(0),
        };
        let p = page(
            &d,
            &Source {
                file: "run.h5",
                version: "0",
            },
        );
        assert!(p.contains("Plotly Technologies") && p.contains("a <\\/script> in text"));
        assert_eq!(p.matches("</script>").count(), 3, "data, library, script");
        assert!(!FRAME.contains("src=") && !FRAME.contains("href="));
    }
}
