//! Chain mail: closed, consistently oriented ring meshes; rings that never touch one
//! another, also across the tile's borders (the tile repeats without seams); every flat ring
//! linked by four standing rings. The torus base mesh: orthonormal frames consistent with
//! the uv parametrisation, periodic seams, a closed surface.

use std::collections::HashMap;

use glam::{IVec3, UVec2, UVec3, Vec3};
use mesostructure::{Ring, chain_mail, chain_mail_rings, torus_base_mesh};

const TILES: [UVec3; 3] = [UVec3::new(64, 64, 16), UVec3::new(16, 16, 8), UVec3::new(24, 16, 8)];

/// Every undirected edge (vertices welded on a 1e-3 grid) is used by exactly two
/// triangles, once in each direction: a closed, consistently oriented surface.
fn assert_closed(triangles: &[[Vec3; 3]], label: &str) {
    let key = |v: Vec3| (v * 1000.0).round().as_ivec3();
    let mut directed: HashMap<(IVec3, IVec3), u32> = HashMap::new();
    for t in triangles {
        for k in 0..3 {
            *directed.entry((key(t[k]), key(t[(k + 1) % 3]))).or_default() += 1;
        }
    }
    for (&(a, b), &count) in &directed {
        assert_eq!(count, 1, "{label}: edge {a} {b} used {count} times in one direction");
        assert_eq!(directed.get(&(b, a)), Some(&1), "{label}: edge {a} {b} has no opposite");
    }
}

/// Smallest distance between the centre circles of two rings (dense sampling).
fn centerline_distance(p: &Ring, q: &Ring) -> f32 {
    let n = 256;
    let qs: Vec<Vec3> = (0..n).map(|k| q.centerline(std::f32::consts::TAU * k as f32 / n as f32)).collect();
    (0..n)
        .map(|k| p.centerline(std::f32::consts::TAU * k as f32 / n as f32))
        .map(|a| qs.iter().map(|&b| a.distance(b)).fold(f32::INFINITY, f32::min))
        .fold(f32::INFINITY, f32::min)
}

/// How many times the centre circle of `q` crosses the hole disc of `p` (the disc inside
/// `p`'s tube): odd when the rings are linked.
fn hole_crossings(p: &Ring, q: &Ring) -> usize {
    let n = 2048;
    let signed = |x: Vec3| (x - p.center).dot(p.axis);
    let mut crossings = 0;
    for k in 0..n {
        let (a, b) = (
            q.centerline(std::f32::consts::TAU * k as f32 / n as f32),
            q.centerline(std::f32::consts::TAU * (k + 1) as f32 / n as f32),
        );
        let (sa, sb) = (signed(a), signed(b));
        if (sa < 0.0) != (sb < 0.0) {
            let x = a + (b - a) * (sa / (sa - sb));
            if x.distance(p.center) < p.major_radius - p.minor_radius {
                crossings += 1;
            }
        }
    }
    crossings
}

#[test]
fn ring_meshes_are_closed_and_outward() {
    let ring = Ring {
        center: Vec3::new(3.0, 2.0, 1.0),
        axis: Vec3::new(0.3, 0.4, 0.8).normalize(),
        major_radius: 2.0,
        minor_radius: 0.5,
    };
    let triangles: Vec<[Vec3; 3]> = ring.triangles(24, 8).iter().map(|t| t.0).collect();
    assert_closed(&triangles, "ring");
    // Outward: the normal points away from the centre circle.
    for t in &triangles {
        let centroid = (t[0] + t[1] + t[2]) / 3.0;
        let normal = (t[1] - t[0]).cross(t[2] - t[0]);
        let radial = (centroid - ring.center) - ring.axis * (centroid - ring.center).dot(ring.axis);
        let nearest = ring.center + radial.normalize() * ring.major_radius;
        assert!(normal.dot(centroid - nearest) > 0.0);
    }
}

#[test]
fn chain_mail_rings_never_touch_across_tiles_and_interlock() {
    for size in TILES {
        let rings = chain_mail_rings(size);
        assert_eq!(chain_mail(size).len(), rings.len() * 2 * 24 * 8);
        let tube = rings[0].minor_radius;
        // The tile and its 8 neighbours.
        let mut all = Vec::new();
        for dy in -1..=1 {
            for dx in -1..=1 {
                let shift = Vec3::new((dx * size.x as i32) as f32, (dy * size.y as i32) as f32, 0.0);
                all.extend(rings.iter().map(|r| Ring { center: r.center + shift, ..*r }));
            }
        }
        let mut closest = f32::INFINITY;
        for (i, p) in rings.iter().enumerate() {
            // Inside the tile in z, within a ring of it in x and y.
            let reach = p.major_radius + p.minor_radius;
            assert!(
                p.center.z - reach >= 0.05 * size.z as f32 - 1e-4 && p.center.z + reach <= 0.95 * size.z as f32 + 1e-4
            );
            for q in &all {
                if q == p || q.center.distance(p.center) > p.major_radius + q.major_radius + 2.0 * tube {
                    continue;
                }
                closest = closest.min(centerline_distance(p, q));
            }
            if p.axis == Vec3::Z {
                // A flat ring: linked once by each of its four standing rings, by no other ring.
                let linked: Vec<&Ring> =
                    all.iter().filter(|q| q.axis != Vec3::Z && hole_crossings(p, q) % 2 == 1).collect();
                assert_eq!(linked.len(), 4, "{size}: flat ring {i} linked by {}", linked.len());
            }
        }
        // Tubes touch when their centre circles come within 2 tube radii; the faceted
        // tubes lie inside the exact ones (their vertices are on them), so more than 2
        // radii keeps the meshes apart (measured: 2.5 on every tile, 0.0375 s).
        println!("{size}: centre circles at least {:.3} tube radii apart", closest / tube);
        assert!(closest > 2.0 * tube, "{size}: centre circles {closest} apart, tubes {tube}");
        // Periodic: every ring shifted by a tile size is a ring of the pattern, taken modulo the tile.
        for p in &rings {
            let wrapped = |c: Vec3| Vec3::new(c.x.rem_euclid(size.x as f32), c.y.rem_euclid(size.y as f32), c.z);
            for shift in [Vec3::new(size.x as f32, 0.0, 0.0), Vec3::new(0.0, size.y as f32, 0.0)] {
                let moved = wrapped(p.center + shift);
                assert!(rings.iter().any(|q| wrapped(q.center).distance(moved) < 1e-4 && q.axis == p.axis));
            }
        }
    }
}

#[test]
fn torus_base_mesh_has_orthonormal_frames_periodic_seams_and_is_closed() {
    let (major, minor, segments, sides) = (3.0, 1.0, 32, 12);
    let mesh = torus_base_mesh(major, minor, segments, sides, UVec2::new(4, 2)).unwrap();
    let n = mesh.positions.len();
    assert_eq!(n, ((segments + 1) * (sides + 1)) as usize);
    for k in 0..n {
        let (t, b, nrm) = (mesh.tangents[k], mesh.bitangents[k], mesh.normals[k]);
        for v in [t, b, nrm] {
            assert!((v.length() - 1.0).abs() < 1e-5);
        }
        assert!(t.dot(b).abs() < 1e-5 && t.dot(nrm).abs() < 1e-5 && b.dot(nrm).abs() < 1e-5);
        assert!(t.cross(b).distance(nrm) < 1e-5);
        // Outward: away from the centre circle.
        let p = mesh.positions[k];
        let nearest = Vec3::new(p.x, p.y, 0.0).normalize() * major;
        assert!(nrm.dot(p - nearest) > 0.99 * minor);
    }
    let index = |i: u32, j: u32| (i * (sides + 1) + j) as usize;
    // Consistent with uv: along a triangle's edges, Δposition ≈ tangent Δu |∂P/∂u| + bitangent Δv |∂P/∂v|.
    for i in 0..segments {
        for j in 0..sides {
            let (a, b) = (index(i, j), index(i + 1, j));
            let (c, d) = (index(i, j), index(i, j + 1));
            assert!(
                (mesh.positions[b] - mesh.positions[a])
                    .normalize()
                    .dot((mesh.tangents[a] + mesh.tangents[b]).normalize())
                    > 0.9999
            );
            assert!(
                (mesh.positions[d] - mesh.positions[c])
                    .normalize()
                    .dot((mesh.bitangents[c] + mesh.bitangents[d]).normalize())
                    > 0.9999
            );
            assert!(mesh.uvs[b].x > mesh.uvs[a].x && mesh.uvs[d].y > mesh.uvs[c].y);
        }
    }
    // Seams: same position and frame, uv larger by the repeat count.
    for j in 0..=sides {
        let (first, last) = (index(0, j), index(segments, j));
        assert_eq!(mesh.positions[first], mesh.positions[last]);
        assert_eq!(mesh.normals[first], mesh.normals[last]);
        assert_eq!(mesh.uvs[last].x - mesh.uvs[first].x, 4.0);
    }
    for i in 0..=segments {
        let (first, last) = (index(i, 0), index(i, sides));
        assert_eq!(mesh.positions[first], mesh.positions[last]);
        assert_eq!(mesh.tangents[first], mesh.tangents[last]);
        assert_eq!(mesh.uvs[last].y - mesh.uvs[first].y, 2.0);
    }
    let triangles: Vec<[Vec3; 3]> = mesh.indices.iter().map(|t| t.map(|k| mesh.positions[k as usize])).collect();
    assert_closed(&triangles, "torus base mesh");
    assert!(torus_base_mesh(1.0, 1.0, 8, 8, UVec2::ONE).is_none());
    assert!(torus_base_mesh(2.0, 1.0, 2, 8, UVec2::ONE).is_none());
    assert!(torus_base_mesh(2.0, 1.0, 8, 8, UVec2::new(0, 1)).is_none());
}
