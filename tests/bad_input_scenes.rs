//! Bad-input audit (see `tests/common/audit.rs`): the `rcg-scenes` constructors and
//! helpers the tests and the laboratory build on, fed empty, NaN, huge and degenerate
//! parameters. (The laboratory's own rows, `measure`, `report` and `frames`, are in
//! `lab/tests/bad_input_lab.rs`.)

mod common;

use rapier3d::prelude::*;
use rcg_scenes as scenes;

use common::audit::*;

#[test]
fn scenes_with_degenerate_parameters() {
    no_panic("degenerate scenes", || {
        let mut s = scenes::sphere_stack(0);
        s.run_plain(0, 2);
        let _ = scenes::sphere_pile(0, u64::MAX);
        for (spheres, radius, incline) in [
            (0, 0.5, 20.0),
            (10, Real::NAN, Real::NAN),
            (10, 0.0, 90.0),
            (10, -1.0, -720.0),
            (10, 1e30, Real::INFINITY),
        ] {
            let p = scenes::DikuParams {
                spheres,
                radius,
                incline_deg: incline,
                seed: 0,
            };
            let _ = scenes::diku(&p);
            let _ = scenes::diku::is_on_plane(&p, Vector::splat(Real::NAN));
        }
        let _ = scenes::diku::plane_width(usize::MAX);
        let _ = scenes::pile::wall_height(usize::MAX);
        let _ = scenes::diku::surface(0);
    });
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_scenes_step_index_overflow_panics() {
    no_panic("platform_x_after(u64::MAX)", || {
        scenes::kinematic_platform::platform_x_after(u64::MAX, DT)
    });
    no_panic("before_step(u64::MAX)", || {
        scenes::kinematic_platform().before_step(u64::MAX)
    });
    no_panic("run_plain(u64::MAX, 1)", || {
        scenes::ball_on_box().run_plain(u64::MAX, 1)
    });
}
