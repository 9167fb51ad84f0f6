use super::*;

/// The surfaces of a McMillan system, to edit.
fn sf(p: &mut Physical) -> &mut SurfaceSi {
    match &mut p.friction {
        FrictionSi::Kinetic {
            surface: Some(s), ..
        } => s,
        other => panic!("{other:?}"),
    }
}

/// The system `p` with the surfaces `surface`.
fn with_surface(p: Physical, surface: Option<SurfaceSi>) -> Physical {
    Physical {
        friction: FrictionSi::Kinetic {
            mu_k: p.friction.mu_k().unwrap(),
            surface,
        },
        ..p
    }
}

fn example() -> Physical {
    // A 2 kg block on a 20 kN/m spring: omega_0 = 100 rad/s (about 15.9 Hz).
    Physical {
        m: 2.0,
        k: 2.0e4,
        c: 4.0,
        v_belt: 0.1,
        friction: FrictionSi::Kinetic {
            mu_k: 0.4,
            surface: Some(SurfaceSi {
                mu_s: 0.5,
                tau: 1e-3,
            }),
        },
        load: Load::Weight(G_STANDARD),
    }
}

#[test]
fn scaling_is_the_papers() {
    let ph = example();
    let p = ph.params(FrictionLaw::McMillan).unwrap();
    // nu = c / (2 sqrt(m k)) = 4 / (2 * 200) = 0.01.
    assert!((p.nu - 0.01).abs() < 1e-15);
    // lambda = v_B / (mu_k g) * omega_0 = 0.1 / 3.924 * 100.
    assert!((p.lambda - 0.1 / (0.4 * 9.81) * 100.0).abs() < 1e-12);
    // tau' = tau / mu_k * omega_0 = 1e-3 / 0.4 * 100 = 0.25.
    let c = p.law.surface().unwrap();
    assert!((c.tau - 0.25).abs() < 1e-15);
    // Phi = arcsin(0.8).
    assert!((c.phi - 0.8f64.asin()).abs() < 1e-15);
    let s = ph.scales();
    // One nondimensional length is mu_k g / omega_0^2 = 3.924e-4 m.
    assert!((s.length - 3.924e-4).abs() < 1e-16);
    // Angular frequency 1 is omega_0 / (2 pi) Hz.
    assert!((s.hz(1.0) - 100.0 / std::f64::consts::TAU).abs() < 1e-12);
}

#[test]
fn conversion_round_trips() {
    let ph = example();
    let p = ph.params(FrictionLaw::McMillanNonHysteretic).unwrap();
    let back = Physical::from_params(&ph, &p);
    let (sb, sf) = (
        back.friction.surface().unwrap(),
        ph.friction.surface().unwrap(),
    );
    for (a, b) in [
        (back.c, ph.c),
        (back.v_belt, ph.v_belt),
        (sb.tau, sf.tau),
        (sb.mu_s, sf.mu_s),
    ] {
        assert!((a - b).abs() <= 1e-14 * b.abs(), "{a} vs {b}");
    }
    let p2 = back.params(p.kind()).unwrap();
    assert!((p2.nu - p.nu).abs() < 1e-15 && (p2.lambda - p.lambda).abs() < 1e-13);
}

#[test]
fn bad_values_name_the_key() {
    type Edit = fn(&mut Physical);
    let cases: [(Edit, &str); 6] = [
        (|p| p.m = -1.0, "m"),
        (|p| p.k = 0.0, "k"),
        (|p| sf(p).mu_s = 0.4, "mu_s"),
        // Phi = arcsin(0.4 / 1e300) = 4e-301: the static peak 2.5e300 times kinetic
        // friction (law::MIN_PHI).
        (|p| sf(p).mu_s = 1e300, "mu_s"),
        (|p| p.c = f64::NAN, "c"),
        (|p| sf(p).tau = -1e-3, "tau"),
    ];
    // mu_s / mu_k = 9e4: Phi = arcsin(1 / 9e4) = 1.1e-5 >= 1e-5, accepted.
    let high = with_surface(
        example(),
        Some(SurfaceSi {
            mu_s: 0.4 * 9e4,
            tau: 1e-3,
        }),
    );
    assert!(high.params(FrictionLaw::McMillan).is_ok());
    for (f, key) in cases {
        let mut p = example();
        f(&mut p);
        match p.validate() {
            Err(CoreError::InvalidParameter { name, .. }) => assert_eq!(name, key),
            other => panic!("{key}: {other:?}"),
        }
    }
}

/// Coulomb's force has no static peak and no surface time: its physical system is
/// `m, k, c, v_B, mu_k, g` alone, and `mu_s` or `tau` given to it is refused by name
/// (they were required and then ignored); McMillan's laws need both.
#[test]
fn each_law_takes_its_own_surface_keys() {
    let coulomb = with_surface(example(), None);
    let p = coulomb.params(FrictionLaw::Coulomb).unwrap();
    assert_eq!(p.law, Friction::Coulomb);
    // nu and lambda as for McMillan's laws (scaling_is_the_papers): c / (2 sqrt(m k)).
    assert!((p.nu - 0.01).abs() < 1e-15);
    let back = Physical::from_params(&coulomb, &p);
    assert_eq!(back.friction.surface(), None);
    let key_of = |r: Result<Params, CoreError>| match r {
        Err(e @ (CoreError::MissingPhysicalKey { .. } | CoreError::UnusedPhysicalKey { .. })) => {
            (e.key().unwrap(), e.to_string())
        }
        other => panic!("{other:?}"),
    };
    let (key, msg) = key_of(example().params(FrictionLaw::Coulomb));
    assert_eq!(key, "mu_s");
    assert!(msg.contains("law coulomb does not use it"), "{msg}");
    for law in [FrictionLaw::McMillan, FrictionLaw::McMillanNonHysteretic] {
        let (key, msg) = key_of(coulomb.params(law));
        assert_eq!(key, "mu_s");
        assert!(msg.contains(&format!("law {law} needs it")), "{msg}");
    }
    // One of the two given: the other is named.
    let of = |law, mu_s, tau| FrictionSi::of(law, Some(0.4), mu_s, tau, None);
    let only_tau = of(FrictionLaw::McMillan, None, Some(1e-3)).unwrap_err();
    assert_eq!(only_tau.key(), Some("mu_s"));
    let only_mu_s = of(FrictionLaw::McMillan, Some(0.5), None).unwrap_err();
    assert_eq!(only_mu_s.key(), Some("tau"));
    let tau_to_coulomb = of(FrictionLaw::Coulomb, None, Some(1e-3)).unwrap_err();
    assert_eq!(tau_to_coulomb.key(), Some("tau"));
    assert_eq!(
        of(FrictionLaw::Coulomb, None, None),
        Ok(FrictionSi::Kinetic {
            mu_k: 0.4,
            surface: None
        })
    );
    assert!(matches!(
        of(FrictionLaw::Stribeck, None, None),
        Err(CoreError::NoPhysicalUnits(_))
    ));
}

/// The README's disc-brake pad: 0.8 kg on a 200 kN/m mount, clamped with 1.5 kN.
fn clamped(load: Load) -> Physical {
    Physical {
        m: 0.8,
        k: 2e5,
        c: 20.0,
        v_belt: 0.3,
        friction: FrictionSi::Kinetic {
            mu_k: 0.38,
            surface: Some(SurfaceSi {
                mu_s: 0.48,
                tau: 5e-4,
            }),
        },
        load,
    }
}

/// Friction is mu N: a normal force N stands where the weight m g stood, so the pad
/// clamped with 1500 N is the paper's system of a 0.8 kg block under g = N / m = 1875
/// m/s^2 (the only way to state it before `normal_force`), bit for bit.
#[test]
fn a_normal_force_stands_for_the_weight() {
    let pad = clamped(Load::NormalForce(1500.0));
    let p = pad.params(FrictionLaw::McMillan).unwrap();
    let hack = clamped(Load::Weight(1875.0));
    assert_eq!(p, hack.params(FrictionLaw::McMillan).unwrap());
    assert_eq!(pad.scales(), hack.scales());
    assert_eq!(pad.normal_force(), 1500.0);
    assert_eq!(hack.normal_force(), 1500.0);
    // Closed form (MODEL.md, "Units"): omega_0 = sqrt(2e5 / 0.8) = 500 rad/s;
    // nu = c / (2 sqrt(m k)) = 20 / 800 = 0.025; lambda = v_B sqrt(m k) / (mu_k N)
    // = 0.3 * 400 / 570 = 0.2105...; tau' = tau omega_0 / mu_k = 0.25 / 0.38 = 0.6579;
    // Phi = arcsin(0.38 / 0.48) = 0.9135.
    assert!((p.nu - 0.025).abs() < 1e-15);
    assert!((p.lambda - 120.0 / 570.0).abs() < 1e-15);
    let sf = p.law.surface().unwrap();
    assert!((sf.tau - 0.25 / 0.38).abs() < 1e-14);
    assert!((sf.phi - (0.38f64 / 0.48).asin()).abs() < 1e-15);
    // The length unit mu_k N / k = 570 / 2e5 m = 2.85 mm.
    assert!((pad.scales().length - 2.85e-3).abs() < 1e-17);
    // The weight's normal force is m g.
    assert_eq!(example().normal_force(), 2.0 * G_STANDARD);
}

/// A normal force <= 0, NaN or infinite is refused naming `normal_force`; `g` and
/// `normal_force` both given are refused naming `normal_force` (N replaces m g).
#[test]
fn a_bad_normal_force_is_named() {
    for n in [0.0, -1500.0, f64::NAN, f64::INFINITY] {
        let e = clamped(Load::NormalForce(n)).validate().unwrap_err();
        assert_eq!(e.key(), Some("normal_force"), "{n}: {e}");
    }
    let both = Load::of(Some(9.81), Some(1500.0), G_STANDARD).unwrap_err();
    assert_eq!(both, CoreError::BothLoads);
    assert_eq!(both.key(), Some("normal_force"));
    assert_eq!(
        Load::of(None, None, G_STANDARD),
        Ok(Load::Weight(G_STANDARD))
    );
    assert_eq!(
        Load::of(None, Some(1500.0), G_STANDARD),
        Ok(Load::NormalForce(1500.0))
    );
}

/// The static peak's bound is Phi's ([`crate::law::MIN_PHI`], checked by
/// [`crate::Surface::check_phi`]), named by `mu_s` with the value given: `mu_s` just
/// inside it (Phi = 1.01e-5) is taken, just outside (Phi = 0.99e-5) refused.
#[test]
fn the_static_peak_takes_phis_bound() {
    let mut ph = example();
    let mu_k = ph.friction.mu_k().unwrap();
    let at = |phi: f64| SurfaceSi {
        mu_s: mu_k / phi.sin(),
        tau: 1e-3,
    };
    ph = with_surface(ph, Some(at(1.01e-5)));
    assert!(ph.validate().is_ok());
    ph = with_surface(ph, Some(at(0.99e-5)));
    let e = ph.validate().unwrap_err().to_string();
    // mu_s = 0.4 / sin(0.99e-5) = 40404.04...
    assert!(
        e.contains("invalid mu_s = 40404.04") && e.contains("1e5 mu_k"),
        "{e}"
    );
}

/// Computed plainly, `m = k = 1e200` overflows `m k` (the critical damping `inf`, `nu` 0
/// and "every start squeals"). The same system scaled by 1e200 in m, k and c has the
/// same nondimensional numbers as `m = k = 1, c = [1, 2]` (nu = c / (2 sqrt(m k)) =
/// 0.5 and 1, computed in ratios); one whose scales no f64 holds is refused by key.
#[test]
fn huge_and_tiny_systems_scale_without_overflow() {
    let at = |m: f64, k: f64, c: f64| Physical {
        m,
        k,
        c,
        ..example()
    };
    let close = |a: f64, b: f64| (a - b).abs() <= 4.0 * f64::EPSILON * b.abs();
    for c in [1.0, 2.0] {
        let one = at(1.0, 1.0, c).params(FrictionLaw::McMillan).unwrap();
        let big = at(1e200, 1e200, c * 1e200)
            .params(FrictionLaw::McMillan)
            .unwrap();
        let tiny = at(1e-200, 1e-200, c * 1e-200)
            .params(FrictionLaw::McMillan)
            .unwrap();
        assert!(close(one.nu, 0.5 * c) && close(big.nu, one.nu), "{big:?}");
        assert!(close(tiny.nu, one.nu), "{tiny:?}");
        for p in [big, tiny] {
            assert!(close(p.lambda, one.lambda), "{p:?} vs {one:?}");
            let (a, b) = (p.law.surface().unwrap(), one.law.surface().unwrap());
            assert!(close(a.tau, b.tau), "{a:?} vs {b:?}");
        }
        let s = at(1e200, 1e200, c * 1e200).scales();
        assert!(close(s.damping, 2e200) && close(s.omega0, 1.0), "{s:?}");
    }
    // 2 sqrt(m k) = 2e308 is no f64: refused, naming m.
    let e = at(1e308, 1e308, 1.0)
        .params(FrictionLaw::McMillan)
        .unwrap_err();
    assert_eq!(e.key(), Some("m"), "{e}");
    // nu = 1e-300 / 2e300 underflows to 0 from c > 0: refused, naming c, the key whose
    // value (301 decades below a plausible damper) takes it there.
    let e = at(1e300, 1e300, 1e-300)
        .params(FrictionLaw::McMillan)
        .unwrap_err();
    assert_eq!(e.key(), Some("c"), "{e}");
}

/// The brake of README section 4 (0.8 kg, 200 kN/m, 20 N s/m, 0.3 m/s, mu_k 0.38, mu_s 0.48,
/// 0.5 ms, 1.5 kN) with one key pushed out of range: the refusal names that key with the
/// value given, and the figure it made. Before, `normal_force = 5e-324` was blamed on
/// `m`, `m = 1e-300` on `nu` (the command line's `--c`) and `k = 1e300` on `lambda`
/// (`--v-belt`).
#[test]
fn a_figure_out_of_range_names_the_key_at_fault() {
    let brake = Physical {
        m: 0.8,
        k: 2e5,
        c: 20.0,
        v_belt: 0.3,
        friction: FrictionSi::Kinetic {
            mu_k: 0.38,
            surface: Some(SurfaceSi {
                mu_s: 0.48,
                tau: 5e-4,
            }),
        },
        load: Load::NormalForce(1500.0),
    };
    assert!(brake.params(FrictionLaw::McMillan).is_ok());
    type Edit = fn(&mut Physical);
    let cases: [(Edit, &str, &str, &str); 4] = [
        (
            |p| p.load = Load::NormalForce(5e-324),
            "normal_force",
            "invalid normal_force = 5e-324: it makes the length unit",
            "= 0,",
        ),
        (
            |p| p.m = 1e-300,
            "m",
            "invalid m = 1e-300: it makes the damping ratio nu",
            "a damping ratio <= 1e6",
        ),
        (
            |p| p.k = 1e300,
            "k",
            "invalid k = 1e300: it makes the model's belt speed lambda",
            "(0, 1e6]",
        ),
        (
            |p| p.c = 1e300,
            "c",
            "invalid c = 1e300: it makes the damping ratio nu",
            "<= 1e6",
        ),
    ];
    for (edit, key, head, tail) in cases {
        let mut p = brake;
        edit(&mut p);
        let e = p.params(FrictionLaw::McMillan).unwrap_err();
        let text = e.to_string();
        assert_eq!(e.key(), Some(key), "{text}");
        assert!(text.starts_with(head) && text.contains(tail), "{text}");
    }
}

/// A belt speed the step cannot resolve (`lambda < dt`, Params::check_step) is refused
/// naming the key at fault: the engineers' brake (2 kg, 50 kN/m, 0.05 m/s, mu_k 0.35) under
/// a clamp of 1e308 N has lambda = 4.5e-307, under g = 1e308 2.3e-307, and on a belt of
/// 1e-12 m/s 4.6e-11; at the default step each is refused by its key, and the brake
/// itself (lambda 2.3) is not.
#[test]
fn a_belt_speed_below_the_step_names_the_key_at_fault() {
    let dt = crate::defaults::DT;
    let brake = Physical {
        m: 2.0,
        k: 5e4,
        c: 10.0,
        v_belt: 0.05,
        friction: FrictionSi::Kinetic {
            mu_k: 0.35,
            surface: Some(SurfaceSi {
                mu_s: 0.45,
                tau: 1e-3,
            }),
        },
        load: Load::Weight(G_STANDARD),
    };
    let step = |ph: Physical| {
        let p = ph.params(FrictionLaw::McMillan).unwrap();
        ph.check_step(&p, dt)
    };
    assert!(step(brake).is_ok());
    let cases: [(Physical, &str); 3] = [
        (
            Physical {
                load: Load::NormalForce(1e308),
                ..brake
            },
            "normal_force",
        ),
        (
            Physical {
                load: Load::Weight(1e308),
                ..brake
            },
            "g",
        ),
        (
            Physical {
                v_belt: 1e-12,
                ..brake
            },
            "v_belt",
        ),
    ];
    for (ph, key) in cases {
        let e = step(ph).unwrap_err();
        let text = e.to_string();
        assert_eq!(e.key(), Some(key), "{text}");
        assert!(
            text.contains("it makes the model's belt speed lambda") && text.contains("dt = 0.005"),
            "{text}"
        );
    }
}

/// A clamped pad of mass 6.6e-309 kg (found by the shipped-spec mutation test on
/// `scans/brake-curve.toml`): `N / m = 1500 / 6.6e-309` is `inf` in f64, so the velocity
/// unit was `inf`, every slip speed of the curve 0, and the refusal named the curve's
/// rows. It names `m`.
#[test]
fn a_mass_too_small_for_the_clamp_force_is_named() {
    let pad = Physical {
        m: 6.58514077742547e-309,
        k: 2e5,
        c: 20.0,
        v_belt: 0.3,
        friction: FrictionSi::Table {
            friction_table: pad_curve(),
        },
        load: Load::NormalForce(1500.0),
    };
    let e = pad.params(FrictionLaw::Table).unwrap_err();
    assert_eq!(e.key(), Some("m"), "{e}");
}

/// A clamp force of 4.1e-311 N (found by the same test): the velocity unit `N / sqrt(m
/// k)` is 1e-313, a subnormal f64, and the curve's speeds divided by it are `inf`. The
/// refusal named the curve's rows; it names `normal_force`.
#[test]
fn a_clamp_force_too_small_for_the_curve_is_named() {
    let pad = Physical {
        m: 0.8,
        k: 2e5,
        c: 20.0,
        v_belt: 0.3,
        friction: FrictionSi::Table {
            friction_table: pad_curve(),
        },
        load: Load::NormalForce(4.1444957096256e-311),
    };
    let e = pad.params(FrictionLaw::Table).unwrap_err();
    assert_eq!(e.key(), Some("normal_force"), "{e}");
}

/// A pad's measured curve in SI: mu falls from 0.48 at rest to 0.36 at 1 m/s (rows in
/// m/s), for the table law's tests.
fn pad_curve() -> &'static FrictionTable {
    FrictionTable::new(&[
        (0.0, 0.48),
        (0.05, 0.44),
        (0.2, 0.4),
        (0.5, 0.37),
        (1.0, 0.36),
    ])
    .unwrap()
}

/// The README's clamped pad with a measured curve: the law is written in the normal
/// load (MODEL.md section 8), so with m = 0.8 kg, k = 2e5 N/m, c = 20 N s/m, v_B = 0.3
/// m/s, N = 1500 N: omega_0 = 500 rad/s, sqrt(m k) = 400 kg/s, the force unit N =
/// 1500 N, the length unit N / k = 7.5 mm, the velocity unit N / sqrt(m k) = 3.75 m/s,
/// xi = c / (2 sqrt(m k)) = 0.025, v_d = v_B / 3.75 = 0.08, and the table's speeds
/// divided by 3.75 (its mu as measured). The g-hack g = N / m = 1875 gives the same, bit
/// for bit; mu_k or a surface given to it is refused by name.
#[test]
fn a_measured_curve_scales_in_the_normal_load() {
    let pad = |load| Physical {
        m: 0.8,
        k: 2e5,
        c: 20.0,
        v_belt: 0.3,
        friction: FrictionSi::Table {
            friction_table: pad_curve(),
        },
        load,
    };
    let clamped = pad(Load::NormalForce(1500.0));
    let p = clamped.params(FrictionLaw::Table).unwrap();
    assert_eq!(
        p,
        pad(Load::Weight(1875.0))
            .params(FrictionLaw::Table)
            .unwrap()
    );
    let s = clamped.scales();
    assert!((s.length - 7.5e-3).abs() < 1e-17 && (s.velocity - 3.75).abs() < 1e-15);
    assert!(
        (p.nu - 0.025).abs() < 1e-15 && (p.lambda - 0.08).abs() < 1e-15,
        "{p:?}"
    );
    let t = p.law.table().unwrap();
    for ((s_nd, mu_nd), (s_si, mu_si)) in t.rows().into_iter().zip(pad_curve().rows()) {
        assert_eq!(mu_nd, mu_si);
        assert!((s_nd - s_si / 3.75).abs() <= 1e-16, "{s_nd} vs {s_si}");
    }
    assert_eq!(clamped.values()[4], None, "a table has no mu_k");
    assert_eq!(
        Physical::from_params(&clamped, &p).friction,
        clamped.friction
    );
    let e = FrictionSi::of(FrictionLaw::Table, Some(0.4), None, None, Some(pad_curve()));
    assert_eq!(e.unwrap_err().key(), Some("mu_k"));
    let e = FrictionSi::of(FrictionLaw::Table, None, None, None, None).unwrap_err();
    assert_eq!(e.key(), Some("friction_table"));
    assert!(e.to_string().contains("m/s"), "{e}");
    let e = FrictionSi::of(
        FrictionLaw::Coulomb,
        Some(0.4),
        None,
        None,
        Some(pad_curve()),
    );
    assert_eq!(e.unwrap_err().key(), Some("friction_table"));
    // A McMillan system asked for the table law: the curve is named missing.
    let e = example().params(FrictionLaw::Table).unwrap_err();
    assert_eq!(e.key(), Some("mu_k"), "{e}");
}
