//! The accuracy measure on real DIKU runs (`docs/accuracy.md`): a configuration identical
//! to the reference is judged equivalent, bit for bit, at accuracy 0; the reference's
//! refinements give finite tolerances; fewer than two seeds is a usage error.
//!
//! A small scene (30 spheres, 5 s) so that the test takes seconds at the test
//! profile's optimisation: long enough for every sphere to reach the rim or a groove,
//! so that every observable is finite.

use rcg_lab::accuracy::ensemble::{
    outcomes, reference_double_iterations, run_reference, run_seed, ReferenceRun, SeedRun, Setup,
    Variant,
};
use rcg_lab::accuracy::observables::{COUNT, OBSERVABLES, W1};
use rcg_lab::accuracy::stats::StatsError;
use rcg_lab::accuracy::{judge, tolerances};
use rcg_lab::measure::RunSpec;

const SETUP: Setup = Setup {
    spheres: 30,
    steps: 500,
};

fn run_all(spec: &RunSpec, refs: &[ReferenceRun], variant: Variant) -> Vec<SeedRun> {
    refs.iter()
        .map(|r| {
            run_seed(SETUP, spec, r.run.seed, variant, Some(r))
                .unwrap()
                .0
        })
        .collect()
}

#[test]
fn a_configuration_identical_to_the_reference_is_judged_equivalent() {
    let refs: Vec<ReferenceRun> = [0, 1, 2]
        .into_iter()
        .map(|seed| run_reference(SETUP, seed).unwrap())
        .collect();
    let reference: Vec<_> = refs.iter().map(|r| r.run.outcome).collect();
    for o in &reference {
        assert!(o.iter().all(|x| x.is_finite()), "{o:?}");
        assert_eq!(o[W1], 0.0);
    }
    // The reference's settings under another name: the same runs, bit for bit.
    let again = RunSpec {
        name: "reference again".into(),
        ..RunSpec::reference()
    };
    let same = run_all(&again, &refs, Variant::AsBuilt);
    for (a, r) in same.iter().zip(&refs) {
        assert_eq!(a.outcome.map(f64::to_bits), r.run.outcome.map(f64::to_bits));
        assert_eq!(a.result.deviation, 0.0);
        assert_eq!(a.plausibility, r.run.plausibility);
    }
    // Tolerances from both refinements.
    let double = run_all(&reference_double_iterations(), &refs, Variant::AsBuilt);
    let half = run_all(&RunSpec::reference(), &refs, Variant::HalfStep);
    assert_eq!(half[0].result.dt, refs[0].run.result.dt / 2.0);
    assert_eq!(
        half[0].result.ms_speed_series.len(),
        2 * refs[0].run.result.ms_speed_series.len()
    );
    let tol = tolerances(&[&outcomes(&double), &outcomes(&half)], &reference).unwrap();
    for (t, o) in tol.iter().zip(OBSERVABLES.iter()) {
        assert!(t.is_finite() && *t >= o.resolution, "{}: {t}", o.key);
    }
    let j = judge(&outcomes(&same), &reference, &tol).unwrap();
    assert!(j.equivalent(), "{}", j.differs());
    assert_eq!(j.accuracy(), 0.0);
    assert_eq!((j.k, j.differs().as_str()), (3, ""));
    assert!(j.reasons().is_empty());
    // Each refinement is inside the tolerance it helped set.
    for r in [&double, &half] {
        let j = judge(&outcomes(r), &reference, &tol).unwrap();
        assert!(j.equivalent() && j.accuracy() <= 1.0, "{}", j.differs());
    }
    // One seed cannot be judged: a usage error, not a panic.
    assert_eq!(
        judge(&outcomes(&same[..1]), &reference[..1], &tol).unwrap_err(),
        StatsError::TooFewSamples { k: 1 }
    );
    assert_eq!(tol.len(), COUNT);
}

#[test]
fn one_ulp_changes_the_trajectory_but_not_the_verdict_machinery() {
    let r = run_reference(SETUP, 7).unwrap();
    let (nudged, _) =
        run_seed(SETUP, &RunSpec::reference(), 7, Variant::UlpNudge, Some(&r)).unwrap();
    // Chaos: one ulp at the start gives a measurable trajectory deviation.
    assert!(nudged.result.deviation.is_finite());
    assert!(nudged.outcome.iter().all(|x| x.is_finite()));
}

#[test]
fn a_configurations_own_floor_is_its_run_against_itself_nudged_by_one_ulp() {
    // What `rcg-lab diku` prints as `floor (r)`: the configuration's
    // own solver against itself, one ulp apart at the start.
    let radius = SETUP.params(7).radius;
    for spec in [RunSpec::brute_force(), RunSpec::contact_graph()] {
        let (_, own) = run_seed(SETUP, &spec, 7, Variant::AsBuilt, None).unwrap();
        let (_, again) = run_seed(SETUP, &spec, 7, Variant::AsBuilt, None).unwrap();
        let (_, nudged) = run_seed(SETUP, &spec, 7, Variant::UlpNudge, None).unwrap();
        // Deterministic: the run again is the run, so the floor is the ulp's alone.
        assert_eq!(
            rcg_lab::measure::deviation(&again, &own, radius),
            0.0,
            "{}",
            spec.name
        );
        let floor = rcg_lab::measure::deviation(&nudged, &own, radius);
        assert!(floor.is_finite() && floor > 0.0, "{}: {floor}", spec.name);
    }
}
