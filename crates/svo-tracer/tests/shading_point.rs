//! Where a magnified element is shaded (`trace` module documentation, "Where an element is
//! shaded"): at the point of its plane that the cone's axis sees.
//!
//! A plane `z = 0` whose colour is linear in `x` and `y`, seen at 60° through pixels far
//! smaller than a voxel: at the finest level, trilinear interpolation reproduces a linear
//! distance, normal and colour exactly, so the octree's sample at the axis's true hit is the
//! radiance the pixel should show. An element's centre lies up to `l_d + 2 r_d` off the
//! plane, which moves a sample taken at its centre, or at the foot of its centre, by up to
//! `l_d tan φ` along the plane; the axis's point of the plane moves only where a partially
//! covering element's axis crosses the plane outside it, by at most `2 r_d` along the axis,
//! `2 r_d / cos φ` along the plane. The test bounds every pixel's error by the radiance's
//! gradient along the plane times that distance, and checks that the bound is well below
//! what the centre's offset would cost.

use abuffer_mask::MaskTable;
use glam::Vec3;
use svo_brick::{BrickSize, BrickTree, BuildOptions, Domain, PackedTree, SdfSurface, VoxelLayout};
use svo_tracer::{Camera, Filtering, TraceSettings, element_radiance, trace_cone};

fn colour(p: Vec3) -> [f32; 3] {
    [0.2 + 0.3 * (p.x + 1.0), 0.5, 0.3 + 0.2 * (p.y + 1.0)]
}

#[test]
fn a_magnified_element_is_shaded_where_its_axis_meets_its_plane() {
    let plane = SdfSurface::new(|p: Vec3| p.z, colour, 1e-4).unwrap();
    let options = BuildOptions { brick_size: BrickSize::Eight, levels: 3, ..BuildOptions::default() };
    let tree = BrickTree::build(&plane, Domain { origin: Vec3::splat(-1.0), size: 2.0 }, options).unwrap();
    let packed = PackedTree::new(&tree, VoxelLayout::Paper20);
    let voxel = packed.uniforms().voxel_size.x;
    let table = MaskTable::<4>::paper().unwrap();
    let settings = TraceSettings::default();
    let phi = 60f32.to_radians();
    let eye = Vec3::new(0.1 + 1.5 * phi.sin(), 0.05, 1.5 * phi.cos());
    let (w, h) = (24, 24);
    let camera = Camera::look_at(eye, Vec3::new(0.1, 0.05, 0.0), Vec3::Z, 0.05, w, h).unwrap();
    // The radiance of the octree's sample at a point of the plane, seen along `direction`.
    let shade = |x: Vec3, direction: Vec3, lod: f32| {
        let sample = packed.sample(x, lod).unwrap();
        let light = (settings.light.position - x).normalize();
        element_radiance(
            &sample,
            -direction,
            light,
            &settings.material,
            Filtering::Correlated,
            settings.light.radiance,
            1.0,
        )
    };
    let (mut compared, mut worst, mut worst_bound, mut centre_cost) = (0, 0.0f32, 0.0f32, f32::MAX);
    for y in 0..h {
        for x in 0..w {
            let cone = camera.pixel_cone(x, y);
            let result = trace_cone(&packed, &table, &cone, &settings);
            assert_eq!(result.coverage, 1.0, "pixel ({x}, {y}) sees the plane");
            let t = -cone.origin.z / cone.direction.z;
            let hit = cone.origin + cone.direction * t;
            let r = 0.5 * cone.width(t);
            let l = r.max(settings.min_half_length * voxel);
            assert!(r < 0.1 * l, "the view must be magnified: r {r}, l {l}");
            let lod = (2.0 * r / voxel).log2();
            let expected = shade(hit, cone.direction, lod);
            // The radiance's gradient along the plane, by central differences over a tenth of
            // a voxel (the radiance is smooth there: linear colour, a distant light).
            let step = 0.1 * voxel;
            let gradient = [Vec3::X, Vec3::Y]
                .map(|u| {
                    let (a, b) =
                        (shade(hit + u * step, cone.direction, lod), shade(hit - u * step, cone.direction, lod));
                    (a - b).abs().max_element() / (2.0 * step)
                })
                .into_iter()
                .fold(0.0, f32::max);
            let bound = gradient * 2.0 * r / phi.cos() + 1e-5;
            let error = (result.radiance - expected).abs().max_element();
            assert!(error <= bound, "pixel ({x}, {y}): error {error} above the bound {bound}");
            worst = worst.max(error);
            worst_bound = worst_bound.max(bound);
            centre_cost = centre_cost.min(gradient * l * phi.tan());
            compared += 1;
        }
    }
    assert_eq!(compared, w * h);
    println!(
        "{compared} pixels: worst error {worst:.2e}, worst bound {worst_bound:.2e}; \
         a shading point l tan φ off would cost up to {centre_cost:.2e} at every pixel"
    );
    assert!(worst_bound < 0.25 * centre_cost, "the bound must tell the shading points apart");
}
