//! Conservative occlusion of quasi-spherical grains by one occluder grain, after Michel &
//! Boubekeur, *Real Time Multiscale Rendering of Dense Dynamic Stackings* (CGF 2020), §8,
//! Fig. 8 and Listing 2 (`IsOccluded`) — derived again, proven exact, and made
//! conservative under `f32` rounding.
//!
//! Every grain lies between an inner ball of radius `r` and an outer ball of radius `R`
//! about its centre. If the inner ball of a grain nearer the eye (the *occluder*, found in
//! the occluder map) hides the outer ball of another grain, the other grain is invisible
//! whatever its shape, and need not be drawn.
//!
//! ```
//! use glam::Vec3;
//! use occlusion_cone::{Exact, Projection, Sphere, hidden_exact, is_occluded};
//!
//! // Camera space, eye at the origin, looking down −z.
//! let occluder = Sphere { centre: Vec3::new(0.1, 0.0, -10.0), radius: 0.8 }; // inner ball
//! let grain = Sphere { centre: Vec3::new(0.2, 0.05, -16.0), radius: 1.0 }; // outer ball
//! assert!(is_occluded(Projection::Perspective, Some(occluder), grain));
//!
//! // The exact answer (f64) agrees: every ray from the eye through the grain's ball meets
//! // the occluder's ball first.
//! let exact = hidden_exact(occluder.centre.as_dvec3(), 0.8, grain.centre.as_dvec3(), 1.0);
//! assert_eq!(exact, Exact::Hidden);
//! ```
//!
//! # The derivation (Fig. 8, again)
//!
//! Eye at the origin `O`, occluder ball `B₀ = B(g₀, r)` with `|g₀| > r`, grain ball
//! `B₁ = B(g₁, R)`. The rays that meet `B₀` form the cone `C` of axis `u = g₀/|g₀|` and
//! half-angle `α`, `sin α = r/|g₀|`.
//!
//! 1. **What `B₀` hides is `B₀ + C`.** A point behind `B₀` on its ray is `p + λ p̂` with
//!    `p ∈ B₀`, so it is in the Minkowski sum `B₀ + C`. Conversely let `y = p + v`,
//!    `p ∈ B₀`, `v ∈ C`, and suppose the segment `[O, y]` missed `B₀`. The point `q` of `B₀`
//!    nearest to the segment gives a plane, normal `n = ` (nearest segment point − `q`)
//!    normalised, with the whole segment strictly on its far side: `(x − q)·n > 0` on
//!    `[O, y]`. At `x = O` this gives `q·n < 0`, and since `q = g₀ + r n`,
//!    `u·n < −r/|g₀| = −sin α`: `n` makes an angle above `π/2 + α` with the axis, hence
//!    above `π/2` with every `v ∈ C`, so `v·n ≤ 0`. Then
//!    `(y − q)·n = (p − q)·n + v·n ≤ 0`, a contradiction. So `B₀ + C` is exactly the set
//!    of points hidden by (or inside) `B₀`.
//! 2. **Listing 2's cone is sufficient.** Let `k = R/r ≥ 1` and `a = k g₀` (Listing 2's
//!    `g0 * R / r`). The homothety of ratio `k` about `O` maps `B₀` to `B(a, R)`; a point
//!    `a + e` of it is `k p = p + (k − 1) p` with `p ∈ B₀`, and `(k − 1) p ∈ C`. If
//!    `g₁ = a + s w` with `w ∈ C` (the cone of apex `a`), every point of `B₁` is
//!    `p + ((k − 1) p + s w)`, in `B₀ + C`: hidden.
//! 3. **And exact.** `B₀ + C` is convex, so `B₁ ⊂ B₀ + C` iff their support functions
//!    compare in every direction; `C`'s is `+∞` outside its polar cone
//!    `{n : n·u ≤ −sin α}` and `0` inside, so `B₁` is hidden iff `(g₁ − g₀)·n ≤ r − R` for
//!    every unit `n` of the polar cone. Maximising over that spherical cap gives, for
//!    `R ≥ r`, exactly "`g₁` in the cone of apex `g₀` eroded by `R − r`", whose apex is
//!    `g₀ + u (R − r)/sin α = a`. The cone test culls every hidden grain and no other
//!    (the [`exact`] module evaluates this form in `f64`).
//!
//! The test [`is_occluded_by`] evaluates "`g₁ − a` within `α` of `u`" as
//! `g₀·(g₁ − a) > 0` and `|g₀ × g₁|² < r² |g₁ − a|²` (no square root, no normalisation),
//! with a rounding margin that keeps it conservative in `f32`; the [`cone`] module lists
//! every special case (no occluder, `g₁` at the apex, `R < r`, orthographic cameras,
//! per-grain scale, values outside the domain) and the margin's derivation.
//!
//! # Checked
//!
//! - [`check_conservative`] decides random configurations concentrated at the cone's boundary with the
//!   `f32` test and the exact `f64` answer: `cargo xtask occlusion-check [--cases N]`
//!   (10⁷ by default) prints how many visible grains were culled (must be 0) and the
//!   fraction of hidden ones found; `cargo test` runs 10⁵ of them and proptests.
//! - [`exact::sampled_points_hidden`] checks the exact answer by brute force (segments from
//!   the eye to points of the grain's sphere).
//! - The WGSL twin is compared with the Rust on the GPU (`tests/occlusion_cone_gpu.rs`).
//!
//! # Modules
//!
//! - [`cone`]: the `f32` test, its domain and its rounding margin.
//! - [`exact`]: the exact answer in `f64`, and the brute-force check of it.
//! - [`check`]: the random conservativeness check.
//!
//! # Using the WGSL twin
//!
//! With the `wgsl` feature, [`WGSL`] holds `occlusion_is_occluded(occluder, grain)` on
//! `vec4(centre, radius)` spheres, the layout of an occluder-map texel, and its helpers:
//!
//! ```
//! # #[cfg(feature = "wgsl")] {
//! let mut source = String::new();
//! occlusion_cone::WGSL.write_source(&mut source).unwrap(); // no dependencies to compose first
//! source.push_str(
//!     "@group(0) @binding(0) var<storage, read> occluders: array<vec4<f32>>; // per grain, from the occluder map
//!      @group(0) @binding(1) var<storage, read> grains: array<vec4<f32>>; // centre, scaled outer radius
//!      @group(0) @binding(2) var<storage, read_write> visible: array<u32>;
//!      @compute @workgroup_size(64)
//!      fn main(@builtin(global_invocation_id) id: vec3<u32>) {
//!          visible[id.x] = select(1u, 0u, occlusion_is_occluded(occluders[id.x], grains[id.x]));
//!      }",
//! );
//! # let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
//! # naga::valid::Validator::new(naga::valid::ValidationFlags::all(), Default::default()).validate(&module).unwrap();
//! assert!(source.contains("fn occlusion_is_occluded"));
//! # }
//! ```
//!
//! Or register `WGSL.naga_oil_source` with a `naga_oil` composer under the name
//! `occlusion_cone` and `#import occlusion_cone::occlusion_is_occluded`.
//!
//! # Features
//!
//! - `std` (default): enables `std` in the dependencies. The crate is `#![no_std]` and
//!   needs no allocator; `cargo check -p occlusion-cone --no-default-features` builds it.
//! - `wgsl`: [`WGSL`], the WGSL twin (its sources are embedded; no extra dependency).
#![no_std]

pub mod check;
pub mod cone;
pub mod exact;
#[cfg(feature = "wgsl")]
mod wgsl;

pub use check::{CheckReport, check_conservative};
pub use cone::{MAX_COORDINATE, MAX_RADIUS, MIN_RADIUS, Projection, Sphere, in_domain, is_occluded, is_occluded_by};
pub use exact::{Exact, hidden_exact};
#[cfg(feature = "wgsl")]
pub use wgsl::WGSL;
