//! Periodic orbits of several damper units (model.md §14, issue 68 item 2): checks that can
//! fail.
//!
//! * The census of two units with different clearances finds a period-1 orbit with two impacts
//!   per unit and period; the independent reference (`tests/oracle/units.py --shoot`: its own
//!   period map, Newton with a central-difference Jacobian) converges to the same fixed point to
//!   `1e-9` of the orbit's scale, with the same Floquet multipliers.
//! * `N` identical units started in step have the orbit and the multipliers of one unit of
//!   mass `N m`.
//! * The two-trajectory Lyapunov exponent of several units gives a periodic orbit's exact
//!   `ln |mu|_max`, and on a chaotic motion of one unit agrees with the exact tangent map.

use crate::common;
use impactsweep::model::System;
use impactsweep::orbits::map::Forcing;
use impactsweep::orbits::shoot::{self, Newton, Stability, Termination};
use impactsweep::orbits::units::{self, UnitsCensusSettings, map as umap};

/// Two units of 10 g (`m = 0.02` split), clearances 8 and 12 mm (`d = 0.01`,
/// `d_spread = 0.2`), `e = 0.7`, `C = 1`, under `0.5 cos(omega t)` N at `r = 1.1`.
fn two_units() -> Forcing {
    let mut f = common::table_i(0.02, 0.01, 0.7, 1.0, 0.5, 1.1);
    f.sys.units = 2.0;
    f.sys.d_spread = 0.2;
    f.sys.validate().unwrap();
    f
}

/// The census of [`two_units`] from rest: 4 starts of 1,000 periods at seed 68.
fn census_of_two(f: &Forcing) -> units::UnitsCensus {
    units::census_from_rest(
        f,
        &UnitsCensusSettings {
            starts: 4,
            max_periods: 1000,
            seed: 68,
            ..UnitsCensusSettings::default()
        },
    )
}

/// The census's period-1 orbit of four impacts of [`two_units`] (each unit crosses its cavity).
fn period_one_orbit(f: &Forcing) -> units::UnitsOrbit {
    census_of_two(f)
        .attractors
        .into_iter()
        .find(|a| a.orbit.period == 1 && a.orbit.impacts == 4)
        .expect("the period-1 orbit of four impacts")
        .orbit
}

/// The oracle's shooting from `s0`: its fixed point, iterations and multipliers.
fn oracle_shoot(f: &Forcing, s0: &[f64]) -> (Vec<f64>, u64, f64, Vec<(f64, f64)>) {
    use serde_json::json;
    let units: Vec<_> = f
        .sys
        .unit_list()
        .iter()
        .map(|u| json!({"m": u.m, "d": u.d, "e": u.e}))
        .collect();
    let spec = json!({"M": f.sys.M, "K": f.sys.K, "C": f.sys.C, "units": units,
                      "load": {"kind": "harmonic", "F0": f.F0, "omega": f.omega},
                      "p": 1, "s0": s0});
    let out = std::process::Command::new(common::python())
        .arg(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/oracle/units.py"
        ))
        .arg("--shoot")
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .and_then(|mut child| {
            use std::io::Write;
            child
                .stdin
                .take()
                .unwrap()
                .write_all(spec.to_string().as_bytes())?;
            child.wait_with_output()
        })
        .expect("the oracle runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let s = v["s"]
        .as_array()
        .unwrap()
        .iter()
        .map(|q| q.as_f64().unwrap())
        .collect();
    let mult = v["multipliers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|z| (z[0].as_f64().unwrap(), z[1].as_f64().unwrap()))
        .collect();
    (
        s,
        v["iterations"].as_u64().unwrap(),
        v["residual"].as_f64().unwrap(),
        mult,
    )
}

/// Largest component difference, velocities divided by `wn` (m).
fn worst(f: &Forcing, a: &[f64], b: &[f64]) -> f64 {
    let wn = f.sys.omega();
    a.iter()
        .zip(b)
        .enumerate()
        .map(|(k, (p, q))| (p - q).abs() / if k % 2 == 1 { wn } else { 1.0 })
        .fold(0.0, f64::max)
}

/// Largest distance between two multiplier lists sorted alike.
fn multipliers_apart(a: &[(f64, f64)], b: &[(f64, f64)]) -> f64 {
    assert_eq!(a.len(), b.len());
    // Conjugate pairs may come in either order: match each to its nearest.
    a.iter()
        .map(|x| {
            b.iter()
                .map(|y| (x.0 - y.0).hypot(x.1 - y.1))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

#[test]
fn the_census_of_two_units_finds_the_reference_orbit() {
    let f = two_units();
    let t0 = std::time::Instant::now();
    let c = census_of_two(&f);
    let census_time = t0.elapsed();
    for a in &c.attractors {
        eprintln!(
            "attractor: period {}, {} impacts, amplitude {:e} m, {} of {} starts, |lambda|max {}",
            a.orbit.period,
            a.orbit.impacts,
            a.orbit.amplitude,
            a.starts,
            c.starts,
            a.orbit.multiplier_max()
        );
    }
    assert_eq!(
        c.attractors.iter().map(|a| a.starts).sum::<u32>() + c.unsettled() + c.non_impacting,
        c.starts
    );
    // Every period-1 orbit of four impacts (each unit hits both its walls once a period: it
    // crosses its own cavity) against the reference's shooting.
    let mut compared = 0;
    for a in c
        .attractors
        .iter()
        .filter(|a| a.orbit.period == 1 && a.orbit.impacts == 4)
    {
        let o = &a.orbit;
        assert_eq!(o.stability, Stability::Stable, "{:?}", o.multipliers);
        assert_eq!(o.multipliers.len(), 6);
        assert_eq!(o.relative_modes, 0);
        // Impacts one unit at a time, no sticking: the exact Jacobian.
        assert!(o.exact);
        let l = umap::scale(&f, &o.s);
        // The reference starts 1e-4 of the scale away from the census's fixed point.
        let s0: Vec<f64> =
            o.s.iter()
                .enumerate()
                .map(|(k, q)| q + 1e-4 * l * if k % 2 == 1 { f.sys.omega() } else { 1.0 })
                .collect();
        let t1 = std::time::Instant::now();
        let (s_ref, iterations, residual, mult_ref) = oracle_shoot(&f, &s0);
        let diff = worst(&f, &o.s, &s_ref);
        let mult_diff = multipliers_apart(&o.multipliers, &mult_ref);
        eprintln!(
            "two units: census {census_time:?} ({} starts, {} periods, Newton {} iterations), \
             oracle {:?} ({iterations} iterations, residual {residual:e}); fixed points \
             {diff:e} m apart ({:e} of L = {l:e}), multipliers {mult_diff:e} apart, \
             |lambda|max {}",
            c.starts,
            c.periods,
            a.iterations,
            t1.elapsed(),
            diff / l,
            o.multiplier_max()
        );
        assert!(diff <= 1e-9 * l, "fixed points {diff:e} apart (L = {l:e})");
        assert!(mult_diff < 1e-5, "multipliers {mult_diff:e} apart");
        compared += 1;
    }
    assert!(compared >= 1, "no period-1 orbit of 4 impacts: {c:?}");
}

#[test]
fn identical_units_in_step_have_the_orbit_of_one_unit_of_their_mass() {
    let one = common::table_i(0.02, 0.01, 0.7, 1.0, 0.5, 1.1);
    let newton = Newton::default();
    // One unit: a transient, then Newton with the exact Jacobian.
    let s = impactsweep::orbits::map::eval(&one, &[0.002, 0.0, 0.0, 0.1], 300, false).end;
    let (term, state) = shoot::solve(&one, 1, &s, &newton);
    assert!(matches!(term, Termination::Converged { .. }), "{term:?}");
    let o1 = shoot::orbit_at(&one, 1, &state.unwrap(), &newton).unwrap();
    for n in [2.0, 3.0] {
        let several = Forcing {
            sys: System {
                units: n,
                ..one.sys
            },
            ..one.clone()
        };
        let mut s0 = vec![s[0], s[1]];
        for _ in 0..n as usize {
            s0.extend([s[2], s[3]]);
        }
        let (term, state) = units::solve(&several, 1, &s0, &newton);
        assert!(matches!(term, Termination::Converged { .. }), "{term:?}");
        let on = units::orbit_at(&several, 1, &state.unwrap(), &newton).unwrap();
        assert_eq!(on.groups.len(), 1, "N = {n}: units stay in step");
        assert_eq!(on.relative_modes, 2 * (n as usize - 1));
        let l = shoot::scale(&one, &o1.s);
        for k in 0..n as usize {
            let unit = [on.s[0], on.s[1], on.s[2 + 2 * k], on.s[3 + 2 * k]];
            let d = shoot::distance(&one, &unit, &o1.s);
            assert!(d <= 1e-9 * l, "N = {n}, unit {k}: {d:e} (L = {l:e})");
        }
        assert_eq!(on.impacts, o1.impacts);
        assert!((on.amplitude - o1.amplitude).abs() <= 1e-9 * l);
        let md = multipliers_apart(&on.multipliers, &o1.multipliers);
        eprintln!(
            "N = {n} in step: multipliers {:?}, one unit's {:?}, {md:e} apart",
            on.multipliers, o1.multipliers
        );
        assert!(md < 1e-5, "N = {n}: multipliers {md:e} apart");
        assert_eq!(on.stability, o1.stability);
    }
}

/// The relative modes of identical units in step have no multipliers: the map is not
/// differentiable there. Moved apart by any `delta` (`1e-9` to `1e-3` of the scale), two units
/// on their in-step orbit hit one after the other, and after one period they are apart by an
/// amount that does not shrink with `delta`; they do not come back into step but settle on an
/// orbit of their own, on which each unit moves differently.
#[test]
fn units_in_step_part_at_any_relative_offset() {
    let mut f = common::table_i(0.02, 0.01, 0.7, 1.0, 0.5, 1.1);
    f.sys.units = 2.0;
    let newton = Newton::default();
    let s = umap::eval(&f, &umap::initial(&f), 300).end;
    let (term, state) = units::solve(&f, 1, &s, &newton);
    assert!(matches!(term, Termination::Converged { .. }), "{term:?}");
    let step = units::orbit_at(&f, 1, &state.unwrap(), &newton).unwrap();
    assert_eq!(step.groups.len(), 1);
    let l = umap::scale(&f, &step.s);
    let wn = f.sys.omega();
    let apart = |s: &[f64]| (s[4] - s[2]).hypot((s[5] - s[3]) / wn) / l;
    let mut after_one = Vec::new();
    for delta in [1e-9, 1e-6, 1e-3] {
        let mut s = step.s.clone();
        s[4] += delta * l;
        s = umap::eval(&f, &s, 1).end;
        after_one.push(apart(&s));
        s = umap::eval(&f, &s, 200).end;
        let end = apart(&s);
        let (term, state) = units::solve(&f, 1, &s, &newton);
        let orbit = match (term, state) {
            (Termination::Converged { .. }, Some(st)) => units::orbit_at(&f, 1, &st, &newton),
            _ => None,
        };
        eprintln!(
            "relative offset {delta:e} L: apart {:.3e} L after one period, {end:.3e} L after 201; \
             orbit there: {:?}",
            after_one.last().unwrap(),
            orbit.as_ref().map(|o| (
                o.amplitude,
                o.impacts,
                o.exact,
                o.multiplier_max(),
                o.stability
            ))
        );
        assert!(end > 0.1, "{delta:e}: back in step ({end:e} L apart)");
        let o = orbit.expect("a periodic orbit out of step");
        assert_eq!(o.groups.len(), 2);
        assert!(apart(&o.s) > 0.1);
    }
    eprintln!(
        "in step: amplitude {}, |lambda|max {}",
        step.amplitude,
        step.multiplier_max()
    );
    // Apart by the same amount after one period, whatever the offset (not in proportion).
    assert!(after_one.iter().all(|&a| a > 1e-2), "{after_one:?}");
}

/// The two-trajectory exponent of several units (`orbits::units::lyapunov`) on a stable
/// periodic orbit of two units is `ln |mu|_max / p`, the Floquet multipliers' exact value, to
/// 0.5 % over 512 periods (measured: 0.2 %; the separation's turning between the multipliers'
/// directions leaves a bias of order `1/n`).
#[test]
fn two_trajectories_give_a_periodic_orbits_exponent() {
    let f = two_units();
    let o = &period_one_orbit(&f);
    let exact = o.multiplier_max().ln();
    let p = units::lyapunov::two_trajectory(&f, &o.s, units::lyapunov::PERIODS).unwrap();
    eprintln!(
        "periodic orbit: ln|mu|max = {exact:.6}, two trajectories {:.6} ± {:.2e}",
        p.lambda, p.se
    );
    assert!(
        (p.lambda - exact).abs() <= 5e-3 * exact.abs(),
        "two trajectories give {} against {exact}",
        p.lambda
    );
}

/// On a chaotic motion of one unit (m = 5 g, d = 5 mm, e = 0.9, r = 0.975 on M = 0.1 kg,
/// K = 400 N/m: the life tests' P2) the two-trajectory exponent through the map of several units
/// agrees with one unit's exact tangent map (Benettin's method with the saltation matrices) over
/// the same 8,192 periods: within 5 % plus twice the tangent map's standard error.
#[test]
fn two_trajectories_agree_with_one_units_tangent_map_on_a_chaotic_motion() {
    use impactsweep::orbits::lyapunov::Benettin;
    let sys = System {
        M: 0.1,
        K: 400.0,
        C: 0.1,
        m: 0.005,
        d: 0.005,
        e: 0.9,
        x0: 0.0,
        v0: 0.0,
        y0: 0.0,
        w0: 0.0,
        ..System::TABLE_I
    };
    let f = Forcing {
        omega: 0.975 * sys.omega(),
        sys,
        F0: 0.1,
        settings: Default::default(),
    };
    // Onto the attractor.
    let mut s = [0.0; 4];
    for _ in 0..400 {
        s = impactsweep::orbits::map::eval(&f, &s, 1, false).end;
    }
    let n = 8192;
    let burn = units::lyapunov::BURN;
    let mut b = Benettin::new(burn);
    let mut t = s;
    for _ in 0..burn + n {
        let e = impactsweep::orbits::map::eval(&f, &t, 1, true);
        t = e.end;
        b.step(e.jacobian.as_ref());
    }
    let (exact, exact_se) = b.estimate();
    let p = units::lyapunov::two_trajectory(&f, &s, n).unwrap();
    eprintln!(
        "chaotic motion: tangent map {exact:.4} ± {exact_se:.4} ({} of {} periods skipped), \
         two trajectories {:.4} ± {:.4}",
        b.skipped, b.seen, p.lambda, p.se
    );
    assert!(exact > 3.0 * exact_se, "not chaotic: {exact} ± {exact_se}");
    assert!(
        (p.lambda - exact).abs() <= 0.05 * exact + 2.0 * exact_se,
        "two trajectories {} ± {} against the tangent map's {exact} ± {exact_se}",
        p.lambda,
        p.se
    );
}

/// The lowest and highest `r` a branch of several units reaches.
fn r_span(b: &units::continuation::UnitsBranch) -> (f64, f64) {
    b.points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.r), hi.max(p.r))
        })
}

/// The continuation of several units over `r` in `range` with steps of one unit's showcase.
fn units_cont(range: (f64, f64)) -> units::continuation::UnitsContSettings {
    units::continuation::UnitsContSettings {
        range,
        h0: 0.01,
        h_min: 1e-6,
        h_max: 0.05,
        max_points: 400,
    }
}

/// Two identical units of 10 g in step follow the branch of one unit of 20 g: every point of the
/// continuation of several units is, read as one unit's section `(x, x', z, y')`, a fixed point
/// of one unit's exact map at its `r` to `1e-9 L`, with its amplitude to `1e-9` relative; and
/// each fold, period doubling or Neimark–Sacker one unit's continuation locates inside the
/// units' branch lies between two consecutive points of it, the second with the same label.
#[test]
fn identical_units_in_step_follow_one_units_branch() {
    use impactsweep::orbits::continuation::{ContSettings, End, Param, follow};
    use impactsweep::orbits::label::Label;
    let one = common::table_i(0.02, 0.01, 0.7, 1.0, 0.5, 1.1);
    let mut two = one.clone();
    two.sys.units = 2.0;
    two.sys.validate().unwrap();
    let c = census_of_two(&two);
    let o = &c
        .attractors
        .iter()
        .find(|a| a.orbit.groups.len() == 1)
        .expect("an orbit of the units in step")
        .orbit;
    let range = (0.8, 1.4);
    let b = units::continuation::follow_units(&two, o, &units_cont(range));
    eprintln!(
        "units in step: {} points over r = {:.4} … {:.4}, ends {:?}, {} periods, labels {:?}",
        b.points.len(),
        r_span(&b).0,
        r_span(&b).1,
        b.ends,
        b.periods,
        b.points
            .iter()
            .filter(|p| p.label != Label::None)
            .map(|p| (p.label, p.r))
            .collect::<Vec<_>>()
    );
    assert!(b.points.len() > 10);
    // Each end named: here the range above, and below a new contact that grazes near
    // r = 1.0722 (one unit's continuation passes it with steps of 1e-5, along the orbit that
    // keeps its two impacts; this one stops there).
    for end in [b.ends.0, b.ends.1] {
        assert!(
            matches!(end, End::Range | End::GrazingEnd),
            "a branch of units in step ended {end:?}"
        );
    }
    let l = one.half_gap();
    for p in &b.points {
        let f = one.at_ratio(p.r);
        let s: [f64; 4] = std::array::from_fn(|k| p.orbit.s[k]);
        let e = impactsweep::orbits::map::eval(&f, &s, u64::from(p.orbit.period), false);
        let off = shoot::distance(&f, &e.end, &s);
        assert!(
            off <= 1e-9 * l,
            "r = {}: {off:e} m off one unit's orbit",
            p.r
        );
        assert!((e.amplitude - p.orbit.amplitude).abs() <= 1e-9 * e.amplitude);
    }
    // One unit's branch from the same orbit, its folds located.
    let s0: [f64; 4] = std::array::from_fn(|k| o.s[k]);
    let (_, state) = shoot::solve(&one, u64::from(o.period), &s0, &Newton::default());
    let orbit = shoot::orbit_at(
        &one,
        u64::from(o.period),
        &state.unwrap(),
        &Newton::default(),
    )
    .unwrap();
    let cont = ContSettings {
        range,
        h0: 0.01,
        h_min: 1e-6,
        h_max: 0.05,
        max_points: 400,
        switch_pd: false,
    };
    let mine = &follow(&one, &orbit, Param::Ratio, &cont)[0];
    let (lo, hi) = r_span(&b);
    let located: Vec<(Label, f64)> = mine
        .points
        .iter()
        .filter(|p| p.located && matches!(p.label, Label::SN | Label::PD | Label::NS))
        .map(|p| (p.label, p.r))
        .collect();
    eprintln!(
        "one unit: located {located:?}, ends {:?}, r = {:.4} … {:.4}",
        mine.ends,
        mine.points
            .iter()
            .map(|p| p.r)
            .fold(f64::INFINITY, f64::min),
        mine.points
            .iter()
            .map(|p| p.r)
            .fold(f64::NEG_INFINITY, f64::max),
    );
    let inside: Vec<&(Label, f64)> = located.iter().filter(|(_, r)| lo < *r && *r < hi).collect();
    assert!(
        !inside.is_empty(),
        "no bifurcation of one unit's branch to compare"
    );
    for (label, r) in inside {
        let bracketed = b
            .points
            .windows(2)
            .any(|w| w[1].label == *label && w[0].r.min(w[1].r) <= *r && *r <= w[0].r.max(w[1].r));
        assert!(
            bracketed,
            "one unit's {label:?} at r = {r} is not bracketed by the units' {label:?}"
        );
    }
}

/// The continuation of two different units (clearances 8 and 12 mm) from the census's period-1
/// orbit: every point a fixed point of the map of several units to `1e-9 L`, and at a point a
/// quarter along it the independent reference's own shooting converges to the same fixed point to `1e-9`
/// of the orbit's scale, with the same multipliers to `1e-5`.
#[test]
fn the_branch_of_two_units_holds_the_reference_orbits() {
    let f = two_units();
    let o = &period_one_orbit(&f);
    let b = units::continuation::follow_units(&f, o, &units_cont((0.9, 1.3)));
    eprintln!(
        "two units: {} points over r = {:.4} … {:.4}, ends {:?}, {} periods",
        b.points.len(),
        r_span(&b).0,
        r_span(&b).1,
        b.ends,
        b.periods
    );
    assert!(b.points.len() > 5);
    let l = f.half_gap();
    for p in &b.points {
        let g = f.at_ratio(p.r);
        let e = units::eval(&g, &p.orbit.s, u64::from(p.orbit.period));
        let off = umap::distance(&g, &e.end, &p.orbit.s);
        assert!(
            off <= 1e-9 * l,
            "r = {}: {off:e} m off its fixed point",
            p.r
        );
    }
    // A point the walk stepped to (a located bifurcation is a fold or the like, where `J - I`
    // is singular and shooting is ill-posed).
    let stepped: Vec<_> = b.points.iter().filter(|p| !p.located).collect();
    let mid = stepped[stepped.len() / 4];
    let g = f.at_ratio(mid.r);
    let scale = umap::scale(&g, &mid.orbit.s);
    let s0: Vec<f64> = mid
        .orbit
        .s
        .iter()
        .enumerate()
        .map(|(k, q)| q + 1e-4 * scale * if k % 2 == 1 { g.sys.omega() } else { 1.0 })
        .collect();
    let (s_ref, _, _, mult_ref) = oracle_shoot(&g, &s0);
    let diff = worst(&g, &mid.orbit.s, &s_ref);
    let mult_diff = multipliers_apart(&mid.orbit.multipliers, &mult_ref);
    eprintln!(
        "at r = {}: {diff:e} m from the reference, multipliers {mult_diff:e}",
        mid.r
    );
    assert!(
        diff <= 1e-9 * scale,
        "{diff:e} m from the reference's fixed point"
    );
    assert!(mult_diff < 1e-5, "multipliers {mult_diff:e} apart");
}
