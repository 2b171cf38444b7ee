//! DIKU: spheres rolling down an inclined plane with "DIKU" engraved in it (paper §7,
//! Fig. 12; DESIGN §5).
//!
//! `N` spheres (default 120, radius 0.5) fall from a grid onto a plane inclined 20°,
//! roll down across the letters D I K U engraved as grooves, and come to rest either in
//! a groove or in a pile against the rim at the lower edge. The runner steps it for
//! 10 simulated seconds at `dt = 0.01`.
//!
//! # Geometry
//! Everything is described in the *plane frame*: `x` runs up the slope (0 at the
//! inner face of the lower rim, [`PLANE_LENGTH`] at the inner face of the upper rim),
//! `y` is the plane's normal (the flat surface is `y = 0`), `z` runs across the slope
//! (`-w/2..w/2`, `w` = [`plane_width`]). The fixed body `"plane"` sits at the world
//! origin, rotated by the incline about the world `z` axis, so that `+x` goes uphill
//! and the slope descends towards world `-x` ([`plane_pose`]).
//!
//! Along the slope, from the bottom:
//! - `x = 0..3`: the run-out, flat, where the pile collects against the lower rim;
//! - `x = 3..11.4`: the letter band, 7 rows of [`CELL`] = 1.2 m; a cell that belongs to
//!   a letter stroke is a groove [`GROOVE_DEPTH`] = 0.2 m deep (0.4 radii) and 1.2 m
//!   (1.2 diameters) wide, so a sphere drops into it, touches its bottom and follows it;
//! - `x = 11.4..14`: a flat top strip. The drop grid (4 rows, 2 staggered layers)
//!   hangs over `x = 9..13.2`, over the top of the letters.
//!
//! Across the slope the letters are a 5 × 7 cell font, one blank cell between letters,
//! so one "DIKU" is 24 cells (28.8 m), plus one blank cell at the far side. The plane
//! holds one "DIKU" per 120 spheres ([`blocks`]): `N` scales the width only, so at
//! 1,200 or 12,000 spheres every sphere falls and rolls as far as at 120, and the pile
//! at the rim is as deep. Seen from above with uphill at the top, the text reads along
//! `+z`.
//!
//! Why these numbers:
//! - The slope is short (14 m, at most ~13 m of rolling): a rolling sphere accelerates
//!   at `5/7 · g · sin 20° ≈ 2.4 m/s²` and reaches only ~8 m/s at the rim, instead of
//!   the 15+ m/s a longer slope gives. Everything reaches the rim within ~3.5 s, which
//!   leaves several seconds to settle.
//! - The rim (lower edge, both sides and the upper edge) stands [`RIM_HEIGHT`] = 2.5 m
//!   (2.5 diameters) above the surface. Spheres arriving at the rim pile up
//!   about two layers deep and are thrown up by the ones behind; the highest centre
//!   measured over 10 s (N = 120 and 1,200) stays about 1.2 m below the top of the
//!   rim, so no sphere leaves the plane (the tests check it).
//! - Grooves 0.4 radii deep hold a sphere at rest on a 20° slope: its lower groove wall
//!   touches it about 45° away from the normal, well beyond the 20° tilt of gravity.
//!   Fast spheres hop over grooves across the slope; slow ones are caught.
//! - The surface is few colliders on the one fixed body, not one per cell: a flat slab
//!   below the band, one above it, one groove-bottom slab under the band and, on it,
//!   the flat "land" between the strokes merged greedily into rectangles ([`surface`];
//!   28 per "DIKU", ~2,800 at 12,000 spheres), plus the four rim walls. All of them
//!   reach down to `y = -1`, so none is thinner than 0.8 m.
//! - Spheres start at least 0.2 m apart (surface to surface) and off the walls, with a
//!   ±0.05 m jitter per axis from a seeded splitmix/xorshift generator (no `rand`),
//!   inserted layer by layer, row by row, across; a given `(N, seed)` always builds the
//!   same world. Rapier's defaults otherwise (friction 0.5, restitution 0, auto-sleep
//!   on, no hooks or event flags).

use rapier3d::math::{Pose, Real, Rotation, Vector};
use rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder};

use super::{new_world, Scene};

/// Side of one letter cell, both along and across the slope: the width of a groove.
pub const CELL: Real = 1.2;
/// Depth of the grooves below the flat surface `y = 0` (plane frame).
pub const GROOVE_DEPTH: Real = 0.2;
/// Length of the flat run-out between the lower rim (`x = 0`) and the letter band.
pub const RUNOUT: Real = 3.0;
/// Length of the plane along the slope, between the inner faces of the lower and the
/// upper rim.
pub const PLANE_LENGTH: Real = 14.0;
/// Height of the rim walls above the flat surface.
pub const RIM_HEIGHT: Real = 2.5;
/// Number of spheres per repetition of "DIKU" across the slope.
pub const SPHERES_PER_BLOCK: usize = 120;
/// Number of cells across one "DIKU" (four 5-cell letters, each followed by a blank).
pub const BLOCK_CELLS: usize = 24;

/// Rows of the letter font (along the slope).
const LETTER_ROWS: usize = 7;
/// Columns of the letter font (across the slope).
const LETTER_COLS: usize = 5;
/// All surface pieces reach down to `y = -SLAB_BOTTOM`.
const SLAB_BOTTOM: Real = 1.0;
/// Thickness of the rim walls.
const WALL_THICKNESS: Real = 1.0;
/// Rows of the drop grid along the slope (per layer).
const DROP_ROWS: usize = 4;
/// `x` of the uppermost drop row (layer 0); the rows go down the slope from there.
const DROP_TOP_X: Real = PLANE_LENGTH - 0.8;
/// Height above the surface of the lowest drop layer's centres.
const DROP_FIRST_Y: Real = 1.5;
/// Largest jitter applied to each coordinate of a drop position.
const JITTER: Real = 0.05;

/// Row 0 is the top of the letter (uphill); column 0 is at the lowest `z`.
const FONT: [[&[u8; LETTER_COLS]; LETTER_ROWS]; 4] = [
    [
        b"####.", b"#...#", b"#...#", b"#...#", b"#...#", b"#...#", b"####.",
    ],
    [
        b".###.", b"..#..", b"..#..", b"..#..", b"..#..", b"..#..", b".###.",
    ],
    [
        b"#...#", b"#..#.", b"#.#..", b"##...", b"#.#..", b"#..#.", b"#...#",
    ],
    [
        b"#...#", b"#...#", b"#...#", b"#...#", b"#...#", b"#...#", b".###.",
    ],
];

/// Parameters of the DIKU scene.
#[derive(Clone, Debug)]
pub struct DikuParams {
    /// Number of spheres (default 120). The plane gets one "DIKU" per 120 spheres.
    pub spheres: usize,
    /// Sphere radius (default 0.5). The plane's geometry is fixed in metres and tuned
    /// for this default (grooves 1.2 m wide); other radii only change the spheres and
    /// the drop spacing.
    pub radius: Real,
    /// Incline of the plane in degrees (default 20).
    pub incline_deg: Real,
    /// Seed of the drop-position jitter (default 0).
    pub seed: u64,
}

impl Default for DikuParams {
    fn default() -> Self {
        DikuParams {
            spheres: 120,
            radius: 0.5,
            incline_deg: 20.0,
            seed: 0,
        }
    }
}

/// Number of "DIKU" repetitions across the slope for `spheres` spheres:
/// `ceil(spheres / 120)`, at least 1.
pub fn blocks(spheres: usize) -> usize {
    spheres.div_ceil(SPHERES_PER_BLOCK).max(1)
}

/// Width of the plane across the slope (between the inner faces of the side rims) for
/// `spheres` spheres: `(24 · blocks + 1) · 1.2` m, e.g. 30 m for 120 spheres.
pub fn plane_width(spheres: usize) -> Real {
    (BLOCK_CELLS * blocks(spheres) + 1) as Real * CELL
}

/// Pose of the fixed `"plane"` body: at the world origin, rotated by the incline about
/// the world `z` axis so that the plane frame's `+x` points up the slope.
pub fn plane_pose(params: &DikuParams) -> Pose {
    Pose::from_parts(
        Vector::ZERO,
        Rotation::from_rotation_z(params.incline_deg.to_radians()),
    )
}

/// A world-space point expressed in the plane frame (`x` up the slope from the lower
/// rim, `y` above the flat surface, `z` across the slope).
pub fn to_plane_frame(params: &DikuParams, pos: Vector) -> Vector {
    plane_pose(params).inverse_transform_point(pos)
}

/// Whether a world-space point (a sphere centre) is inside the rimmed volume: between
/// the rims' inner faces, no lower than a groove bottom and no higher than the rim's
/// top. A sphere whose centre is not on the plane has left it.
pub fn is_on_plane(params: &DikuParams, pos: Vector) -> bool {
    let p = to_plane_frame(params, pos);
    let half_w = plane_width(params.spheres) / 2.0;
    (0.0..=PLANE_LENGTH).contains(&p.x)
        && (-half_w..=half_w).contains(&p.z)
        && (-GROOVE_DEPTH..=RIM_HEIGHT).contains(&p.y)
}

/// Whether a sphere of the scene's radius centred at world-space `pos` lies in a groove:
/// its centre is lower than half a groove depth below where it would rest on the flat
/// surface.
pub fn is_in_groove(params: &DikuParams, pos: Vector) -> bool {
    to_plane_frame(params, pos).y < params.radius - GROOVE_DEPTH / 2.0
}

/// Whether cell (`row`, `col`) of the letter band is a groove. Row 0 is the top row
/// (uphill); column 0 is the blank column at `z = -w/2`.
fn is_groove(row: usize, col: usize) -> bool {
    if col == 0 {
        return false;
    }
    let c = (col - 1) % BLOCK_CELLS;
    let (letter, lc) = (c / (LETTER_COLS + 1), c % (LETTER_COLS + 1));
    lc < LETTER_COLS && FONT[letter][row][lc] == b'#'
}

/// A rectangle of cells: first row, first column, number of rows, number of columns.
type CellRect = (usize, usize, usize, usize);

/// The flat land of the letter band (every cell that is not a groove) as rectangles of
/// cells, merged greedily: each rectangle grows as far as it can across the slope, then
/// down the rows while the whole span stays land. Deterministic, row by row.
fn land_rects(cols: usize) -> Vec<CellRect> {
    let mut used = vec![false; LETTER_ROWS * cols];
    let free = |used: &[bool], r: usize, c: usize| !used[r * cols + c] && !is_groove(r, c);
    let mut rects = Vec::new();
    for r in 0..LETTER_ROWS {
        let mut c = 0;
        while c < cols {
            if !free(&used, r, c) {
                c += 1;
                continue;
            }
            let mut w = 1;
            while c + w < cols && free(&used, r, c + w) {
                w += 1;
            }
            let mut h = 1;
            while r + h < LETTER_ROWS && (c..c + w).all(|cc| free(&used, r + h, cc)) {
                h += 1;
            }
            for rr in r..r + h {
                for cc in c..c + w {
                    used[rr * cols + cc] = true;
                }
            }
            rects.push((r, c, h, w));
            c += w;
        }
    }
    rects
}

/// The plane's surface pieces, in the plane frame, as (centre, half extents) of
/// cuboids: the slab below the letter band, the slab above it, the groove-bottom slab
/// under the band, then the land rectangles of the band. Not the rim walls.
pub fn surface(spheres: usize) -> Vec<(Vector, Vector)> {
    let w = plane_width(spheres);
    let band_lo = RUNOUT;
    let band_hi = RUNOUT + LETTER_ROWS as Real * CELL;
    let slab = |x0: Real, x1: Real, z0: Real, z1: Real, top: Real| {
        (
            Vector::new((x0 + x1) / 2.0, (top - SLAB_BOTTOM) / 2.0, (z0 + z1) / 2.0),
            Vector::new((x1 - x0) / 2.0, (top + SLAB_BOTTOM) / 2.0, (z1 - z0) / 2.0),
        )
    };
    let (z0, z1) = (-w / 2.0, w / 2.0);
    let mut parts = vec![
        slab(0.0, band_lo, z0, z1, 0.0),
        slab(band_hi, PLANE_LENGTH, z0, z1, 0.0),
        slab(band_lo, band_hi, z0, z1, -GROOVE_DEPTH),
    ];
    let cols = BLOCK_CELLS * blocks(spheres) + 1;
    for (r, c, h, n) in land_rects(cols) {
        // Row r spans x = band_hi - (r + 1)·CELL .. band_hi - r·CELL.
        let x1 = band_hi - r as Real * CELL;
        let x0 = x1 - h as Real * CELL;
        let zc0 = z0 + c as Real * CELL;
        parts.push(slab(x0, x1, zc0, zc0 + n as Real * CELL, 0.0));
    }
    parts
}

/// The rim walls, in the plane frame, as (centre, half extents) of cuboids: lower edge,
/// upper edge, then the two sides. Their inner faces are `x = 0`, `x = PLANE_LENGTH`,
/// `z = ±w/2`; they reach from `y = -1` to `y = RIM_HEIGHT`.
fn rim(spheres: usize) -> [(Vector, Vector); 4] {
    let w = plane_width(spheres);
    let t = WALL_THICKNESS;
    let hy = (RIM_HEIGHT + SLAB_BOTTOM) / 2.0;
    let cy = (RIM_HEIGHT - SLAB_BOTTOM) / 2.0;
    // End walls span the full width; side walls cover the end walls' ends too.
    let end_half = Vector::new(t / 2.0, hy, w / 2.0);
    let side_half = Vector::new(PLANE_LENGTH / 2.0 + t, hy, t / 2.0);
    [
        (Vector::new(-t / 2.0, cy, 0.0), end_half),
        (Vector::new(PLANE_LENGTH + t / 2.0, cy, 0.0), end_half),
        (
            Vector::new(PLANE_LENGTH / 2.0, cy, -(w + t) / 2.0),
            side_half,
        ),
        (
            Vector::new(PLANE_LENGTH / 2.0, cy, (w + t) / 2.0),
            side_half,
        ),
    ]
}

/// splitmix64-seeded xorshift64*: deterministic, tiny, seed 0 is fine.
struct Jitter(u64);

impl Jitter {
    fn new(seed: u64) -> Self {
        let mut z = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        Jitter(if z == 0 { 0x2545_F491_4F6C_DD1D } else { z })
    }

    /// Uniform in `[-JITTER, JITTER]`.
    fn next(&mut self) -> Real {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        let unit = (x.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64;
        ((unit * 2.0 - 1.0) * JITTER as f64) as Real
    }
}

/// Drop positions of the spheres in the plane frame, in insertion order (layer by
/// layer from the bottom, each layer row by row from the top of the slope, each row
/// across in `+z`). Full layers first; the last, partial layer is spread evenly over
/// its slots. Layer `l` is `l · spacing` higher than layer 0, and odd layers are offset
/// by half a spacing down the slope and across so that they do not land in columns.
fn drop_positions(params: &DikuParams) -> Vec<Vector> {
    let n = params.spheres;
    let w = plane_width(n);
    let spacing = (2.0 * params.radius + 0.2).max(CELL);
    let cols = ((w / spacing).floor() as usize).saturating_sub(2).max(1);
    let col_step = w / (cols + 1) as Real;
    let per_layer = cols * DROP_ROWS;
    let layers = n.div_ceil(per_layer).max(1);
    let mut rng = Jitter::new(params.seed);
    let mut out = Vec::with_capacity(n);
    for layer in 0..layers {
        let first = layer * per_layer;
        let count = (n - first).min(per_layer);
        let odd = (layer % 2) as Real * 0.5;
        for k in 0..count {
            // Spread `count` spheres over the `per_layer` slots of this layer.
            let slot = k * per_layer / count;
            let (row, col) = (slot / cols, slot % cols);
            let x = DROP_TOP_X - (row as Real + odd) * spacing + rng.next();
            let y = DROP_FIRST_Y + layer as Real * spacing + rng.next();
            let z = -w / 2.0 + (col as Real + 1.0 + odd) * col_step + rng.next();
            out.push(Vector::new(x, y, z));
        }
    }
    out
}

/// Builds the DIKU scene. `scene.bodies` holds only `"plane"`, the fixed body carrying
/// the surface ([`surface`]) and the rim walls as cuboid colliders; the spheres are all
/// the other bodies of `scene.world.bodies` (dynamic, inserted after the plane, in the
/// order of the drop grid: layer by layer from the bottom, row by row from the top of
/// the slope, across in `+z`).
pub fn diku(params: &DikuParams) -> Scene {
    let mut world = new_world();
    let pose = plane_pose(params);
    let plane = world.insert_body(RigidBodyBuilder::fixed().pose(pose));
    for (centre, half) in surface(params.spheres)
        .into_iter()
        .chain(rim(params.spheres))
    {
        world.insert_collider(
            ColliderBuilder::cuboid(half.x, half.y, half.z).translation(centre),
            Some(plane),
        );
    }
    for p in drop_positions(params) {
        world.insert(
            RigidBodyBuilder::dynamic().translation(pose.transform_point(p)),
            ColliderBuilder::ball(params.radius),
        );
    }
    Scene {
        name: "diku",
        world,
        bodies: vec![("plane", plane)],
        script: None,
    }
}
