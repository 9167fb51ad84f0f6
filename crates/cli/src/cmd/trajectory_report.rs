//! What `squeal trajectory` reports: its summary (JSON and words) and the run's parameters.

use std::path::PathBuf;

use serde::Serialize;
use squeal_core::error::Number;
use squeal_core::{Named, Sample, SolverKind, SolverStats, State};
use squeal_scan::trajectory::{Oscillation, StickPhases};

/// Model and run parameters, as printed and stored: the law, its own parameters by name
/// (`nu, lambda, tau, phi` or `xi, v_d, mu_d, mu_sd, v_0, mu_v`), then the run's settings.
pub(super) struct RunParams {
    pub(super) law: &'static str,
    pub(super) named: Vec<Named>,
    pub(super) dt: f64,
    pub(super) solver: &'static str,
    pub(super) scheme: &'static str,
    pub(super) x0: f64,
    pub(super) v0: f64,
    pub(super) t_end: f64,
    pub(super) every: u64,
}

impl Serialize for RunParams {
    fn serialize<S: serde::Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = ser.serialize_map(None)?;
        m.serialize_entry("law", self.law)?;
        for n in &self.named {
            m.serialize_entry(n.name, &n.value)?;
        }
        m.serialize_entry("dt", &self.dt)?;
        m.serialize_entry("solver", self.solver)?;
        m.serialize_entry("scheme", self.scheme)?;
        m.serialize_entry("x0", &self.x0)?;
        m.serialize_entry("v0", &self.v0)?;
        m.serialize_entry("t_end", &self.t_end)?;
        m.serialize_entry("every", &self.every)?;
        m.end()
    }
}

/// A verdict: `steady_slip`, `stick_slip` or `undecided`, why, and when (`t_end` if
/// undecided by the time limit).
#[derive(Serialize)]
pub(super) struct Verdict {
    pub(super) regime: &'static str,
    pub(super) reason: &'static str,
    pub(super) t_decision: f64,
}

impl Verdict {
    fn of(o: &squeal_core::Outcome) -> Verdict {
        let (regime, reason, t_decision) = (o.regime.name(), o.reason.name(), o.t_decision);
        Verdict {
            regime,
            reason,
            t_decision,
        }
    }
}

/// The label of the start (the classifier's verdict on the same run, or the start rule's).
#[derive(Serialize)]
pub(super) struct Classification {
    #[serde(flatten)]
    pub(super) label: Verdict,
    /// Time on stick-slip before the run settled, as a scan stores it per cell
    /// (`squeal_core::classify::t_squeal`; JSON has no infinity, so by kind).
    pub(super) squeal: squeal_core::Squeal,
    /// The run's own verdict (the classifier without the trap or any shortcut; steady slip
    /// where the run reached the fixed point).
    pub(super) run: Verdict,
    /// Whether the label was decided at the start (the start rule of `squeal scan` and
    /// `classify`), without the run.
    pub(super) at_start: bool,
    /// The rule that said stick-slip although the run then reached the fixed point
    /// (`null` if none): refuted, the label is the run's.
    pub(super) refuted: Option<&'static str>,
}

impl Classification {
    /// The label of run `t` and, where the start rule gave it, the run's own verdict.
    pub(super) fn of(t: &squeal_scan::trajectory::Trajectory) -> Classification {
        Classification {
            label: Verdict::of(&t.outcome),
            squeal: squeal_core::Squeal::of(t.outcome.t_squeal),
            run: Verdict::of(&t.own),
            at_start: t.at_start,
            refuted: t.refuted.map(|r| r.name()),
        }
    }
}

/// Everything `squeal trajectory` reports.
#[derive(Serialize)]
pub(super) struct Summary {
    pub(super) squeal_version: &'static str,
    pub(super) params: RunParams,
    pub(super) steps: u64,
    pub(super) fixed_point: State,
    /// Steady slip's own stability: the linearisation of the law at the fixed point.
    pub(super) steady_slip: squeal_core::SteadySlip,
    pub(super) classification: Classification,
    pub(super) final_state: Sample,
    pub(super) oscillation: Oscillation,
    /// The lasting oscillation of the last turns (maximum of `x` to maximum), wherever it
    /// lies (`null`: the last window of turns is no band without trend, or too few turns).
    pub(super) lasting: Option<squeal_core::Lasting>,
    /// Whether the parameters lie where the labels were checked against long runs
    /// (`squeal_core::validated`): `checked`, the keys `outside`, and the `checks`.
    pub(super) validated: squeal_core::Validity,
    /// Stick phases (laws with true stick only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) stick: Option<StickPhases>,
    pub(super) stats: SolverStats,
    pub(super) max_residual: f64,
    /// Steps (including the initial solve) whose solve did not converge: the paper's
    /// iteration hitting its cap, or a robust failure.
    pub(super) unconverged_steps: u64,
    /// Times of the first few of them.
    pub(super) first_unconverged_times: Vec<f64>,
    /// The rule groups withdrawn from this model's map (a census run refuted
    /// their premise), each with why; the label was decided without them.
    pub(super) rules_withdrawn: Vec<String>,
    /// Rows written to `--out` (and drawn, before any further decimation, in `--plot`).
    pub(super) rows: u64,
    /// The stride of the rows kept and how it was chosen, in words (`null`: none kept).
    pub(super) sampling: Option<String>,
    pub(super) out: Option<PathBuf>,
    pub(super) plot: Option<PathBuf>,
    /// A physical system (`--m ...`): the start, the end and the oscillation in SI units.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) si: Option<serde_json::Value>,
}

/// The start, final state and final oscillation in SI units (lengths in m, velocities in
/// m/s, times in s, frequencies in Hz) of the system `ph`, with its normal force (N).
/// `x` where finite (JSON has no NaN).
fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

pub(super) fn si_summary(s: &Summary, ph: &squeal_core::Physical) -> serde_json::Value {
    let sc = &ph.scales();
    let f = &s.final_state;
    serde_json::json!({
        "x0_m": s.params.x0 * sc.length,
        "v0_m_per_s": s.params.v0 * sc.velocity,
        "t_end_s": s.params.t_end * sc.time,
        "final_t_s": f.t * sc.time,
        "final_x_m": f.x * sc.length,
        "final_v_m_per_s": f.v * sc.velocity,
        "fixed_point_x_m": s.fixed_point.x * sc.length,
        "frequency_hz": s.oscillation.omega.map(|w| sc.hz(w)),
        "amplitude_m_per_s": s.oscillation.amplitude.map(|r| r * sc.velocity),
        "lasting_frequency_hz": s.lasting.map(|l| sc.hz(l.omega)),
        "lasting_x_range_m": s.lasting.map(|l| l.x_range.map(|x| x * sc.length)),
        "lasting_v_range_m_per_s": s.lasting.map(|l| l.v_range.map(|v| v * sc.velocity)),
        // Only a finite time on stick-slip has seconds (0 too); `classification.squeal`
        // says which kind it is.
        "t_squeal_s": match s.classification.squeal {
            squeal_core::Squeal::Never => Some(0.0),
            squeal_core::Squeal::Transient { t_squeal } => Some(t_squeal * sc.time),
            _ => None,
        },
        "steady_slip_growth_per_s": finite(s.steady_slip.growth / sc.time),
        "steady_slip_period_s": s.steady_slip.period.map(|t| t * sc.time),
        "length_unit_m": sc.length,
        "velocity_unit_m_per_s": sc.velocity,
        "time_unit_s": sc.time,
        "normal_force_n": ph.normal_force(),
    })
}

/// The summary in words.
pub(super) fn print_summary(s: &Summary, kind: SolverKind) {
    let p = &s.params;
    let named: Vec<String> = p
        .named
        .iter()
        .map(|n| format!("{}={}", n.name, Number(n.value)))
        .collect();
    // Exponent form for huge or tiny values: `--tau 1e-300` was printed with 300 zeros.
    println!(
        "run: {} {} dt={} solver={} scheme={} from (x0, x'0) = ({}, {}) to t = {} ({} steps)",
        p.law,
        named.join(" "),
        Number(p.dt),
        p.solver,
        p.scheme,
        Number(p.x0),
        Number(p.v0),
        Number(p.t_end),
        s.steps
    );
    if let Some(w) = s.validated.warning() {
        println!("{w}");
    }
    let time_unit = s.si.as_ref().and_then(|v| v["time_unit_s"].as_f64());
    println!("{}", s.steady_slip.words(time_unit));
    print_ended(s);
    let f = &s.final_state;
    println!(
        "final state: t = {} x = {:.9} x' = {:.9} x'' = {:.9} F = {:.9}",
        Number(f.t),
        Number(f.x),
        Number(f.v),
        Number(f.a),
        Number(f.force)
    );
    let o = &s.oscillation;
    match (o.omega, o.amplitude) {
        (Some(w), Some(r)) => println!(
            "final oscillation: omega = {w:.6} (last revolution), section amplitude x' = {r:.6} \
             at t = {:.4}, {} crossings of x = {}",
            o.t_last_crossing.unwrap_or(f64::NAN),
            o.crossings,
            Number(s.fixed_point.x)
        ),
        _ => println!(
            "final oscillation: none ({} crossings of x = {}, x' > 0)",
            o.crossings,
            Number(s.fixed_point.x)
        ),
    }
    if let Some(l) = &s.lasting {
        print_lasting(l, s.fixed_point.x);
    }
    if let Some(sp) = &s.stick {
        print_stick_phases(sp);
    }
    print_solver(s, kind);
    if let Some(out) = &s.out {
        let how = s.sampling.as_deref().unwrap_or_default();
        println!("wrote {} ({} rows: {how})", out.display(), s.rows);
    }
    if let Some(plot) = &s.plot {
        println!("wrote {}", plot.display());
    }
}

/// How the run ended: its label and by what it was decided (the classifier, the rule
/// decided at the start, or the run refuting a rule), the rules withdrawn, and the squeal.
fn print_ended(s: &Summary) {
    let c = &s.classification;
    let label = match c.label.regime {
        "steady_slip" => "steady slip",
        "stick_slip" => "stick-slip",
        "slip_oscillation" => "on the small slip oscillation about the unstable steady slip",
        _ => "not yet settled",
    };
    let l = &c.label;
    match (c.refuted, c.at_start) {
        (Some(rule), _) => println!(
            "ended: {label} (the run: {} at t = {:.6}; the rule {rule}, which squeal scan and \
             classify label this start by, said stick_slip and is refuted by the run)",
            l.reason, l.t_decision
        ),
        (None, false) => println!(
            "ended: {label} (classifier: {}, {} at t = {:.6})",
            l.regime, l.reason, l.t_decision
        ),
        (None, true) => println!(
            "ended: {label} ({}: decided at the start, as squeal scan and classify decide it)",
            l.reason
        ),
    }
    if c.refuted.is_none() {
        let r = &c.run;
        println!(
            "the run itself: {} ({} at t = {:.6})",
            r.regime, r.reason, r.t_decision
        );
    }
    for w in &s.rules_withdrawn {
        println!("rule withdrawn for this model (the label is decided without it): {w}");
    }
    println!("squeal: {}", c.squeal.words());
}

/// The lasting oscillation of the last turns.
fn print_lasting(l: &squeal_core::Lasting, x_star: f64) {
    let mut how = Vec::new();
    if l.stuck {
        how.push("sticks".to_string());
    }
    if l.reversed {
        how.push("the slip reverses (x' > lambda)".to_string());
    }
    how.push(match l.crossings {
        0 => format!("never reaches x = {x_star} (the section)"),
        k => format!("crosses the section x = {x_star} in {k} of them"),
    });
    println!(
        "lasting oscillation: omega = {:.6} over the last {} turns (t = {:.4}), x in [{:.6}, \
         {:.6}], x' in [{:.6}, {:.6}], half-range of x {:.6} to {:.6}; {}",
        l.omega,
        l.turns,
        l.t,
        l.x_range[0],
        l.x_range[1],
        l.v_range[0],
        l.v_range[1],
        l.amplitude[0],
        l.amplitude[1],
        how.join(", ")
    );
}

/// The solver's counts, the largest residual and the unconverged steps.
fn print_solver(s: &Summary, kind: SolverKind) {
    let st = &s.stats;
    println!(
        "solver: solves={} evaluations={} newton_steps={} bisections={} expansions={} \
         multi_root={} discontinuities={} failures={} iterations={} unconverged={} sticks={} \
         bracket_fallbacks={}",
        st.solves,
        st.evaluations,
        st.newton_steps,
        st.bisections,
        st.expansions,
        st.multi_root,
        st.discontinuities,
        st.failures,
        st.iterations,
        st.unconverged,
        st.sticks,
        st.fallbacks
    );
    println!("max residual |G(F)| = {:.3e}", s.max_residual);
    if kind == SolverKind::Paper || s.unconverged_steps > 0 {
        let times: Vec<String> = s
            .first_unconverged_times
            .iter()
            .map(|t| format!("{}", (t * 1e9).round() / 1e9))
            .collect();
        println!(
            "unconverged steps: {} of {} ({:.2}%){}",
            s.unconverged_steps,
            st.solves,
            100.0 * s.unconverged_steps as f64 / st.solves.max(1) as f64,
            if times.is_empty() {
                String::new()
            } else {
                format!(", first at t = {}", times.join(", "))
            }
        );
    }
}

/// The stick phases of a law with true stick.
fn print_stick_phases(sp: &StickPhases) {
    let times = |v: &[f64]| {
        v.iter()
            .map(|t| format!("{t:.6}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let last = |t: Option<f64>| t.map_or("none".to_string(), |t| format!("{t:.6}"));
    println!(
        "stick phases: {} onsets, {} breakaways, {} passages through zero slip without sticking; {} at the end",
        sp.onsets,
        sp.breakaways,
        sp.reversals,
        if sp.stuck_at_end { "stuck" } else { "slipping" }
    );
    if sp.onsets + sp.breakaways > 0 {
        for (what, count, first, latest) in [
            ("onsets", sp.onsets, &sp.first_onsets, sp.last_onset),
            (
                "breakaways",
                sp.breakaways,
                &sp.first_breakaways,
                sp.last_breakaway,
            ),
        ] {
            let more = if count as usize > first.len() {
                ", ..."
            } else {
                ""
            };
            println!(
                "  {what} at t = {}{more}; last at t = {}",
                times(first),
                last(latest)
            );
        }
    }
}
