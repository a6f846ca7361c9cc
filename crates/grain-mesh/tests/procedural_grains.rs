//! Every procedural grain is a closed, outward-wound solid whose measured `r` and `R` bound
//! its surface; the ball, bean and rock contain their centre, the nut does not.

use std::f64::consts::PI;

use glam::{DVec3, Vec3};
use grain_mesh::{Ball, CentreKind, CoffeeBean, GrainMesh, HexNut, MeshError, SandGrain};

/// The four default procedural grains, named.
fn grains() -> Vec<(&'static str, GrainMesh)> {
    vec![
        ("ball", Ball::default().mesh().unwrap()),
        ("coffee bean", CoffeeBean::default().mesh().unwrap()),
        ("sand grain", SandGrain::default().mesh().unwrap()),
        ("hex nut", HexNut::default().mesh().unwrap()),
    ]
}

/// Signed volume by the divergence theorem, computed here independently of the crate.
fn signed_volume(mesh: &GrainMesh) -> f64 {
    (0..mesh.triangles().len())
        .map(|t| {
            let [a, b, c] = mesh.triangle_corners(t).unwrap().map(Vec3::as_dvec3);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

#[test]
fn every_grain_is_closed_and_consistently_oriented() {
    for (name, mesh) in grains() {
        let report = mesh.edge_report();
        assert!(report.is_closed_and_oriented(), "{name}: {report:?}");
        // Euler characteristic V − E + F: 2 for a sphere, 0 for a torus (the nut).
        let vertices = grain_mesh::topology::weld_by_position(mesh.positions())
            .iter()
            .enumerate()
            .filter(|&(i, &first)| i == first as usize)
            .count() as i64;
        let euler = vertices - report.edges as i64 + mesh.triangles().len() as i64;
        assert_eq!(euler, if name == "hex nut" { 0 } else { 2 }, "{name}");
    }
}

#[test]
fn every_grain_has_positive_volume_about_its_volume_centroid() {
    for (name, mesh) in grains() {
        let volume = signed_volume(&mesh);
        assert!(volume > 0.0, "{name}: signed volume {volume}");
        let bounds = mesh.bounds();
        assert_eq!(bounds.centre_kind, CentreKind::VolumeCentroid, "{name}");
        let measured = f64::from(bounds.volume.unwrap());
        assert!((measured - volume).abs() <= 1e-5 * volume, "{name}: {measured} vs {volume}");
    }
}

#[test]
fn volumes_match_closed_forms() {
    let ball = Ball::default().mesh().unwrap();
    let sphere = 4.0 / 3.0 * PI;
    // An inscribed polyhedron of 5 120 triangles falls short of the sphere by about 0.3 %.
    let ball_volume = signed_volume(&ball);
    assert!(ball_volume < sphere && ball_volume > 0.99 * sphere, "{ball_volume}");

    let nut = HexNut::default();
    let (apothem, height, hole, segments) = (0.8_f64, 0.8_f64, 0.5_f64, 48.0_f64);
    let hexagon_area = 2.0 * 3.0_f64.sqrt() * apothem * apothem;
    let hole_area = segments / 2.0 * hole * hole * (2.0 * PI / segments).sin();
    let expected = (hexagon_area - hole_area) * height;
    let volume = signed_volume(&nut.mesh().unwrap());
    assert!((volume - expected).abs() < 1e-5, "{volume} vs {expected}");
}

#[test]
fn surface_lies_between_the_inner_and_outer_spheres() {
    for (name, mesh) in grains() {
        let bounds = mesh.bounds();
        let (r, big_r) = (f64::from(bounds.inner_radius), f64::from(bounds.outer_radius));
        assert!(0.0 < r && r <= big_r, "{name}: r = {r}, R = {big_r}");
        let centre = bounds.centre.as_dvec3();
        let mut nearest = f64::INFINITY;
        let mut farthest: f64 = 0.0;
        for t in 0..mesh.triangles().len() {
            let [a, b, c] = mesh.triangle_corners(t).unwrap().map(Vec3::as_dvec3);
            // Corners, edge midpoints and a grid of interior points.
            for (u, v) in (0..=8).flat_map(|i| (0..=8 - i).map(move |j| (f64::from(i) / 8.0, f64::from(j) / 8.0))) {
                let distance = (a + (b - a) * u + (c - a) * v).distance(centre);
                nearest = nearest.min(distance);
                farthest = farthest.max(distance);
            }
        }
        assert!(nearest >= r * (1.0 - 1e-6), "{name}: a surface point at {nearest} inside r = {r}");
        assert!(farthest <= big_r * (1.0 + 1e-6), "{name}: a surface point at {farthest} outside R = {big_r}");
        // The bounds are tight: sampled points come close to both spheres.
        assert!(nearest <= r + 0.02 * big_r, "{name}: nearest sample {nearest}, r = {r}");
        assert!(farthest >= big_r * (1.0 - 1e-6), "{name}: farthest sample {farthest}, R = {big_r}");
    }
}

/// The measured `r/R` per grain (printed with `--nocapture`): the ball is nearly a sphere,
/// the rock is a rounded ellipsoid, the bean is elongated and creased (its `r` is set by
/// its half-thickness and crease), and the nut's `r` is its hole, where no material is.
#[test]
fn radius_ratios_per_grain() {
    for (name, mesh) in grains() {
        let b = mesh.bounds();
        println!(
            "{name:12} triangles {:6}  r {:.4}  R {:.4}  r/R {:.3}  winding number {:+.3}  occluder r/R {:.3}",
            mesh.triangles().len(),
            b.inner_radius,
            b.outer_radius,
            b.radius_ratio(),
            b.winding_number,
            b.occluder_radius() / b.outer_radius,
        );
        let (ratio, inside) = (b.radius_ratio(), b.centre_inside_solid());
        match name {
            "ball" => assert!(ratio > 0.99 && inside, "{name}: {ratio}"),
            "sand grain" => assert!((0.6..0.85).contains(&ratio) && inside, "{name}: {ratio}"),
            "coffee bean" => assert!((0.15..0.35).contains(&ratio) && inside, "{name}: {ratio}"),
            _ => {
                // Centre in the hole: r is the hole polygon's apothem, and the inner ball
                // holds no material.
                let apothem = 0.5 * (PI / 48.0).cos();
                assert!((f64::from(b.inner_radius) - apothem).abs() < 1e-6, "{}", b.inner_radius);
                let corner = 0.8 / (PI / 6.0).cos();
                let expected_outer = (corner * corner + 0.4 * 0.4).sqrt();
                assert!((f64::from(b.outer_radius) - expected_outer).abs() < 1e-6, "{}", b.outer_radius);
                assert!(b.winding_number.abs() < 1e-3 && !inside, "{}", b.winding_number);
                assert_eq!(b.occluder_radius(), 0.0);
            }
        }
        if inside {
            assert!((b.winding_number - 1.0).abs() < 1e-3, "{name}: {}", b.winding_number);
            assert_eq!(b.occluder_radius(), b.inner_radius);
        }
    }
}

#[test]
fn normals_are_unit_and_face_outward() {
    for (name, mesh) in grains() {
        for (i, n) in mesh.normals().iter().enumerate() {
            assert!((n.length() - 1.0).abs() < 1e-5, "{name}: normal {i} = {n}");
        }
        // Every normal agrees with the triangles around its vertex.
        let mut face_sums = vec![DVec3::ZERO; mesh.positions().len()];
        for (t, corners) in mesh.triangles().iter().enumerate() {
            let [a, b, c] = mesh.triangle_corners(t).unwrap().map(Vec3::as_dvec3);
            for &i in corners {
                face_sums[i as usize] += (b - a).cross(c - a).normalize();
            }
        }
        for (i, (n, sum)) in mesh.normals().iter().zip(&face_sums).enumerate() {
            assert!(n.as_dvec3().dot(*sum) > 0.0, "{name}: normal {i} = {n} faces inward");
        }
    }
    let ball = Ball::default().mesh().unwrap();
    for (p, n) in ball.positions().iter().zip(ball.normals()) {
        assert!(p.normalize().dot(*n) > 0.999, "{p}: {n}");
    }
    // Sharp edges stay sharp: the nut's end faces are flat-shaded.
    let nut = HexNut::default().mesh().unwrap();
    for (p, n) in nut.positions().iter().zip(nut.normals()) {
        if p.z == 0.4 && n.z > 0.5 {
            assert!(n.abs_diff_eq(Vec3::Z, 1e-6), "{p}: {n}");
        }
    }
}

#[test]
fn every_grain_has_a_material_per_vertex() {
    for (name, mesh) in grains() {
        let materials = mesh.materials().unwrap_or_else(|| panic!("{name} has no material"));
        assert_eq!(materials.len(), mesh.positions().len(), "{name}");
    }
    // The bean's crease is paler than its skin.
    let bean = CoffeeBean::default();
    let mesh = bean.mesh().unwrap();
    let materials = mesh.materials().unwrap();
    let crease_floor = (0..materials.len())
        .filter(|&i| mesh.positions()[i].y.abs() < 0.02 && mesh.positions()[i].x.abs() < 0.3)
        .map(|i| materials[i].albedo)
        .fold(Vec3::ZERO, Vec3::max);
    assert!(crease_floor.x > bean.skin.albedo.x + 0.1, "{crease_floor}");
}

#[test]
fn sand_grain_depends_on_its_seed_only() {
    let grain = SandGrain { seed: 42, ..SandGrain::default() };
    assert_eq!(grain.mesh().unwrap(), grain.mesh().unwrap());
    let other = SandGrain { seed: 43, ..grain }.mesh().unwrap();
    assert_ne!(grain.mesh().unwrap().positions(), other.positions());
    // Same triangles (the icosphere), displaced differently.
    assert_eq!(grain.mesh().unwrap().triangles(), other.triangles());
}

#[test]
fn out_of_range_parameters_are_errors() {
    let cases: Vec<(Result<GrainMesh, MeshError>, &str)> = vec![
        (Ball { radius: 0.0, ..Ball::default() }.mesh(), "radius"),
        (Ball { radius: f32::NAN, ..Ball::default() }.mesh(), "radius"),
        (Ball { subdivisions: 8, ..Ball::default() }.mesh(), "subdivisions"),
        (CoffeeBean { crease_depth: 1.0, ..CoffeeBean::default() }.mesh(), "crease_depth"),
        (CoffeeBean { half_width: -1.0, ..CoffeeBean::default() }.mesh(), "half_width"),
        (SandGrain { displacement: 1.0, ..SandGrain::default() }.mesh(), "displacement"),
        (SandGrain { octaves: 0, ..SandGrain::default() }.mesh(), "octaves"),
        (HexNut { hole_radius: 0.78, ..HexNut::default() }.mesh(), "hole_radius"),
        (HexNut { hole_segments: 50, ..HexNut::default() }.mesh(), "hole_segments"),
    ];
    for (result, parameter) in cases {
        match result {
            Err(MeshError::InvalidParameter { name, .. }) => assert_eq!(name, parameter),
            other => panic!("{parameter}: expected an invalid-parameter error, got {:?}", other.map(|m| *m.bounds())),
        }
    }
}

#[test]
fn nut_with_fewest_segments_is_still_closed() {
    let mesh = HexNut { hole_segments: 6, ..HexNut::default() }.mesh().unwrap();
    assert!(mesh.edge_report().is_closed_and_oriented());
    assert!(signed_volume(&mesh) > 0.0);
}
