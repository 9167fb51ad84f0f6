//! `squeal friction`: the paper's friction curves (Figs 4-7) in physical units, as CSV and PNG.
//!
//! All curves are `F / (m g)` from the dimensional law (paper eqs. 3.2-3.4,
//! [`squeal_core::friction::dimensional`]) for a material given by `mu_k`, `tau` and
//! `Phi = arcsin(mu_k / mu_s)` (the paper's figures: `mu_k = 1`, `tau = 1e-3 s`, `Phi = 1`):
//!
//! * `fig4_5_fixed_acceleration`: against the slip velocity at fixed acceleration
//!   `x'' = +2` and `-2 m/s^2`, over a velocity range of 2.5 times the quasi-static window
//!   `2 |x''| tau / mu_k` on each side (+-0.01 m/s for the paper's material).
//! * `fig6_loop_w200`: along the imposed motion `x = A sin(w t)` with `A = 0.5e-6 m`,
//!   `w = 200 rad/s` over one period (belt at rest, so the slip velocity is `x' = A w cos wt`
//!   and `x'' = -A w^2 sin wt`): a hysteresis loop.
//! * `fig7_loop_w20`: the same with `A = 5e-6 m`, `w = 20 rad/s`: Coulomb-like with a sharp
//!   peak near zero velocity.
//!
//! Sample points are computed by index, never by accumulating a step.

use squeal_core::error::Number;
use std::f64::consts::TAU;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, bail};
use squeal_core::friction::dimensional;
use squeal_plot::{Curve, Rgb};

use super::out_files::{create_file, refuse_existing};

/// Points per fixed-acceleration curve.
const N_VELOCITY: usize = 4001;
/// Points per period of the imposed motions (the Fig 7 peak lasts about 0.6% of the period).
const N_PERIOD: usize = 10001;
/// The accelerations of Figs 4-5, m/s^2.
const ACCEL: f64 = 2.0;

/// Flags of `squeal friction`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Directory for the CSV and PNG files (created if missing).
    #[arg(long, value_name = "DIR", default_value = "friction")]
    out_dir: PathBuf,
    /// Kinetic friction coefficient mu_k > 0.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    mu_k: f64,
    /// Characteristic time tau > 0 of the surfaces, in seconds.
    #[arg(long, default_value_t = 1e-3, allow_negative_numbers = true)]
    tau: f64,
    /// Phi = arcsin(mu_k/mu_s), in [1e-5, pi/2].
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    phi: f64,
    /// Overwrite existing files.
    #[arg(long)]
    force: bool,
}

/// The material of the curves.
#[derive(Clone, Copy, Debug)]
struct Material {
    mu_k: f64,
    tau: f64,
    phi: f64,
}

impl Material {
    /// `F / (m g)` at slip velocity `v` (m/s) and acceleration `a` (m/s^2).
    fn force(&self, v: f64, a: f64) -> f64 {
        dimensional(v, a, self.mu_k, self.tau, self.phi)
    }
}

/// One output: a table and its picture.
struct Figure {
    /// File stem in the output directory.
    stem: &'static str,
    title: String,
    header: &'static str,
    /// Table rows, in column order of `header`.
    rows: Vec<Vec<f64>>,
    curves: Vec<Curve>,
}

/// Runs `squeal friction`.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    if !args.mu_k.is_finite() || args.mu_k <= 0.0 {
        bail!(
            "--mu-k: invalid mu_k = {}: expected a finite coefficient > 0",
            Number(args.mu_k)
        );
    }
    if !args.tau.is_finite() || args.tau <= 0.0 {
        bail!(
            "--tau: invalid tau = {}: expected a finite time > 0 (seconds)",
            Number(args.tau)
        );
    }
    squeal_core::Surface::check_phi(args.phi).map_err(|e| anyhow::anyhow!("--phi: {e}"))?;
    let m = Material {
        mu_k: args.mu_k,
        tau: args.tau,
        phi: args.phi,
    };
    let figures = [
        fixed_acceleration(&m),
        imposed_motion(&m, "fig6_loop_w200", 6, 0.5e-6, 200.0),
        imposed_motion(&m, "fig7_loop_w20", 7, 5e-6, 20.0),
    ];
    let dir = &args.out_dir;
    let paths = |f: &Figure| {
        (
            dir.join(format!("{}.csv", f.stem)),
            dir.join(format!("{}.png", f.stem)),
        )
    };
    for f in &figures {
        check_drawable(f)?;
    }
    for f in &figures {
        let (csv, png) = paths(f);
        refuse_existing("--out-dir", &csv, args.force)?;
        refuse_existing("--out-dir", &png, args.force)?;
    }
    std::fs::create_dir_all(dir)
        .with_context(|| format!("--out-dir: cannot create {}", dir.display()))?;
    for f in &figures {
        let (csv, png) = paths(f);
        write_table(&csv, f, args.force)
            .with_context(|| format!("cannot write {}", csv.display()))?;
        squeal_plot::line_plot(
            &png,
            &f.title,
            "velocity (m/s)",
            "F / mg",
            &f.curves,
            &[],
            false,
        )
        .with_context(|| format!("cannot draw {}", png.display()))?;
        println!("wrote {} and {}", csv.display(), png.display());
    }
    Ok(ExitCode::SUCCESS)
}

fn material_text(m: &Material) -> String {
    format!(
        "mu_k={}, tau={} s, Phi={}",
        Number(m.mu_k),
        Number(m.tau),
        Number(m.phi)
    )
}

/// Refuses a figure whose axes the plot cannot draw ([`squeal_plot::check_axis`]), before
/// anything is written, naming the flags they come from: `--mu-k 5e307` put F/mg near
/// 1e308, and the plotting library's tick search looped for ever.
fn check_drawable(f: &Figure) -> anyhow::Result<()> {
    let span = |v: &dyn Fn(&Curve) -> &[f64]| {
        let all = f.curves.iter().flat_map(|c| v(c).iter().copied());
        all.filter(|x| x.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x), b.max(x))
            })
    };
    let axes = [
        (
            "x",
            span(&|c| &c.xs),
            "--tau and --mu-k (the velocity window 2 |x''| tau / mu_k)",
        ),
        (
            "y",
            span(&|c| &c.ys),
            "--mu-k and --phi (the friction force F/mg, up to mu_s = mu_k / sin Phi)",
        ),
    ];
    for (axis, (lo, hi), flags) in axes {
        squeal_plot::check_axis(axis, lo, hi)
            .with_context(|| format!("{flags}: {} cannot be drawn", f.stem))?;
    }
    Ok(())
}

/// Figs 4-5: `F/mg` against slip velocity at `x'' = +2` and `-2 m/s^2`.
fn fixed_acceleration(m: &Material) -> Figure {
    let window = 2.0 * ACCEL * m.tau / m.mu_k;
    let v_max = 2.5 * window;
    let vs: Vec<f64> = (0..N_VELOCITY)
        .map(|i| -v_max + i as f64 * (2.0 * v_max) / (N_VELOCITY - 1) as f64)
        .collect();
    let pos: Vec<f64> = vs.iter().map(|&v| m.force(v, ACCEL)).collect();
    let neg: Vec<f64> = vs.iter().map(|&v| m.force(v, -ACCEL)).collect();
    let rows = (0..N_VELOCITY)
        .map(|i| vec![vs[i], pos[i], neg[i]])
        .collect();
    Figure {
        stem: "fig4_5_fixed_acceleration",
        title: format!(
            "Figs 4-5: friction at fixed acceleration ({})",
            material_text(m)
        ),
        header: "v_m_per_s,f_over_mg_accel_plus2,f_over_mg_accel_minus2",
        rows,
        curves: vec![
            Curve {
                label: format!("x'' = +{ACCEL} m/s^2 ({})", material_text(m)),
                xs: vs.clone(),
                ys: pos,
                color: Rgb(49, 110, 198),
                points_only: false,
            },
            Curve {
                label: format!("x'' = -{ACCEL} m/s^2 ({})", material_text(m)),
                xs: vs,
                ys: neg,
                color: Rgb(238, 118, 22),
                points_only: false,
            },
        ],
    }
}

/// Figs 6-7: `F/mg` along `x = A sin(w t)` over one period, belt at rest.
fn imposed_motion(m: &Material, stem: &'static str, fig: u32, amp: f64, w: f64) -> Figure {
    let period = TAU / w;
    let mut rows = Vec::with_capacity(N_PERIOD);
    let (mut vs, mut fs) = (Vec::with_capacity(N_PERIOD), Vec::with_capacity(N_PERIOD));
    for i in 0..N_PERIOD {
        let t = i as f64 * period / (N_PERIOD - 1) as f64;
        let (sn, cs) = (w * t).sin_cos();
        let x = amp * sn;
        let v = amp * w * cs;
        let a = -amp * w * w * sn;
        let f = m.force(v, a);
        rows.push(vec![t, x, v, a, f]);
        vs.push(v);
        fs.push(f);
    }
    Figure {
        stem,
        title: format!("Fig {fig}: friction along x = {amp:e} sin({w} t) m"),
        header: "t_s,x_m,v_m_per_s,a_m_per_s2,f_over_mg",
        rows,
        curves: vec![Curve {
            label: format!("one period ({})", material_text(m)),
            xs: vs,
            ys: fs,
            color: Rgb(49, 110, 198),
            points_only: false,
        }],
    }
}

fn write_table(path: &Path, f: &Figure, force: bool) -> anyhow::Result<()> {
    let mut w = BufWriter::new(create_file(path, force)?);
    writeln!(w, "{}", f.header)?;
    for row in &f.rows {
        let line: Vec<String> = row.iter().map(|x| x.to_string()).collect();
        writeln!(w, "{}", line.join(","))?;
    }
    w.into_inner().map_err(|e| e.into_error())?.sync_all()?;
    Ok(())
}
