//! Smith masking of Gaussian microsurfaces and the view- and light-dependent mean
//! attribute, after Heitz & Neyret, *Representing Appearance and Pre-filtering Subpixel
//! Data in Sparse Voxel Octrees* (HPG 2012), eqs. 4–6, 13, 17 and §5.5.
//!
//! A pre-filtered voxel stores a Gaussian microsurface: heights `N(0, σ_h²)`, slopes
//! `N(0, σ_nx²)` and `N(0, σ_ny²)`, and attributes correlated with height,
//! `a(h) = ā + a_s (2g(h) − 1)`. Smith's masking function Λ (eq. 6) gives the probability
//! `g(h)^Λ(v)` that a point at height `h` is seen from `v` (eq. 4); integrating the
//! attribute against the visibility from the eye and the light gives the closed form
//! `ā(v, l) = ā + a_s Λ/(Λ + 2)`, `Λ = Λ(v) + Λ(l)` (eq. 17), used in the shading of
//! eq. 13.
//!
//! ```
//! use glam::Vec3;
//! use smith_micro::{HeightCorrelatedAttribute, SlopeDeviation};
//!
//! // Grooves along x: flat along x, rough along y (Fig. 5 of the paper).
//! let slopes = SlopeDeviation::new(0.0, 0.5).unwrap();
//! let green = HeightCorrelatedAttribute::new(0.5, 0.4).unwrap();
//!
//! // Normal incidence sees the mean; grazing light across the grooves only lights the
//! // bumps, so the visible attribute tends to ā + a_s.
//! let at_normal = smith_micro::visible_mean_attribute_for_directions(green, Vec3::Z, Vec3::Z, slopes);
//! assert_eq!(at_normal, Some(0.5));
//! let across = Vec3::new(0.0, 1.0, 0.01);
//! let grazing = smith_micro::visible_mean_attribute_for_directions(green, Vec3::Z, across, slopes).unwrap();
//! assert!(grazing > 0.85 && grazing < 0.9);
//! // Along the grooves nothing changes.
//! let along = Vec3::new(1.0, 0.0, 0.01);
//! assert_eq!(smith_micro::visible_mean_attribute_for_directions(green, Vec3::Z, along, slopes), Some(0.5));
//!
//! // Below the horizon a direction sees nothing of the surface: no Λ.
//! assert_eq!(smith_micro::smith_lambda_direction(Vec3::new(0.0, 1.0, -0.1), slopes), None);
//! ```
//!
//! # Modules
//!
//! - [`erf`](mod@erf): `erf`, `erfc`, `erfcx` in one approximation (Numerical Recipes' Chebyshev
//!   fit), written so that a WGSL twin can evaluate the same formulas.
//! - [`masking`]: Λ (eq. 6) from `ν`, from `(μ, σ)` and from a direction over
//!   anisotropic slopes; Smith's mean visibility `1/(1+Λ)`.
//! - [`height`]: the height CDF `g(h)` (eq. 5), the visibility `g(h)^Λ` (eq. 4) and the
//!   attribute `a(h)` of H5bis.
//! - [`attribute`]: the mean visible attribute `ā(v, l)` (eq. 17).
//! - [`correction`]: a per-material correction of Λ fitted to ray-traced ground truth,
//!   and eq. 17 with it (`ā + a_s Λ'/(Λ' + 2)`), kept beside eq. 17.
//! - [`cubic_correction`]: the same correction as a cubic in `Λ/(1 + Λ)`, the least-squares
//!   cubic through a fitted table: as accurate, and three multiply–adds on the GPU.
//! - [`correlated`]: the corrected visibility model with separate view and light tables
//!   and a light–view correlation term in the azimuth difference (its derivation).
//! - [`shading`]: the NDF ⊗ BRDF convolution of §5.5 and the shading of eq. 13.
//!
//! Every function documents its result for every input in a table: normal incidence,
//! grazing, below the horizon, `σ = 0`, extreme anisotropy, NaN and ±∞. No function
//! panics, and none returns NaN; geometrically meaningless input gives `None`. Inputs
//! are bounded (slope deviations ≤ 2³², height deviations, attributes and radiances
//! ≤ 2⁶⁴) so that no intermediate overflows f32: WGSL cannot represent the overflow, and
//! the WGSL twin must compute the same result.
//!
//! # Validated types
//!
//! What a function relies on and a caller builds once is a type with private fields and
//! validating constructors, which say why they reject an input (an error enum): the slope
//! deviations ([`SlopeDeviation`], [`SlopeDeviationError`]), the attribute
//! ([`HeightCorrelatedAttribute`], [`AttributeError`]) and the per-material corrections
//! ([`LambdaCorrection`], [`VisibilityCorrection`], [`CubicLambdaCorrection`] with
//! [`LambdaCorrectionError`], [`VisibilityCorrectionError`], [`CubicCorrectionError`],
//! [`CubicFitError`]). No function re-checks them. Each correction has a separate `Pod`
//! GPU form ([`GpuLambdaCorrection`], [`GpuVisibilityCorrection`],
//! [`GpuCubicLambdaCorrection`], made by `to_gpu`) whose WGSL declaration is generated;
//! the WGSL twins take it and do not re-check it either. The slopes and the attribute
//! reach the WGSL twins as raw voxel data and are checked there.
//!
//! # Using the WGSL twin
//!
//! With the `wgsl` feature, [`WGSL`] is the crate's WGSL twin: the generated GPU forms of
//! the corrections and every constant (the `erfc` coefficients, thresholds, bit masks),
//! and the functions, each named after the Rust function it mirrors
//! (`smith_visible_mean_attribute_for_directions` is
//! [`visible_mean_attribute_for_directions`], `smith_shade` is [`shade`], …). A result
//! is a `SmithValue` (a value and a kind: finite, none, ±∞ — WGSL has no `Option` and may
//! assume no NaN or infinity reaches float operations); `smith_encode` writes it as the
//! bits [`encode`] gives on the CPU. A voxel's slopes and attribute reach the twin as raw
//! data (`vec3(σ_nx, σ_ny, 0)`, `vec2(ā, a_s)`) and are checked there:
//!
//! ```
//! # #[cfg(feature = "wgsl")] {
//! let mut source = String::new();
//! smith_micro::WGSL.write_source(&mut source).unwrap(); // no dependencies to compose first
//! source.push_str(
//!     "@group(0) @binding(0) var<storage, read> voxels: array<vec4<f32>>; // (σ_nx, σ_ny, ā, a_s)
//!      @group(0) @binding(1) var<storage, read_write> colours: array<f32>;
//!      @compute @workgroup_size(64)
//!      fn main(@builtin(global_invocation_id) id: vec3<u32>) {
//!          let voxel = voxels[id.x];
//!          let seen = smith_visible_mean_attribute_for_directions(
//!              voxel.zw, vec3<f32>(0.0, 0.0, 1.0), normalize(vec3<f32>(0.3, 0.0, 1.0)), vec3<f32>(voxel.xy, 0.0));
//!          colours[id.x] = select(0.0, seen.value, seen.kind == SMITH_FINITE);
//!      }",
//! );
//! # let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
//! # naga::valid::Validator::new(naga::valid::ValidationFlags::all(), Default::default()).validate(&module).unwrap();
//! assert!(source.contains("fn smith_visible_mean_attribute_for_directions"));
//! # }
//! ```
//!
//! A per-material correction is uploaded as its GPU form, e.g.
//! `bytemuck::bytes_of(&cubic.to_gpu())` for a [`CubicLambdaCorrection`], and evaluated by
//! `smith_cubic_corrected_visible_mean_attribute`. Or register `WGSL.naga_oil_source` with
//! a `naga_oil` composer under the name `smith_micro` and `#import smith_micro::{...}`.
//!
//! # Features
//!
//! - `std` (default): enables `std` in the dependencies. The crate is `#![no_std]` and
//!   needs no allocator; `cargo check -p smith-micro --no-default-features` builds it
//!   without `std`.
//! - `wgsl`: [`WGSL`], the WGSL twin (its sources are embedded; no extra dependency).
#![no_std]

#[cfg(all(test, feature = "std"))]
extern crate std;

pub mod attribute;
pub mod correction;
pub mod correlated;
pub mod cubic_correction;
pub mod encoding;
pub mod erf;
pub mod height;
pub mod masking;
pub mod shading;
#[cfg(feature = "wgsl")]
mod wgsl;

pub use attribute::{
    AttributeComponent, AttributeError, HeightCorrelatedAttribute, visible_mean_attribute,
    visible_mean_attribute_for_directions,
};
pub use correction::{
    GpuLambdaCorrection, LambdaCorrection, LambdaCorrectionError, corrected_lambda, corrected_visible_mean_attribute,
};
pub use correlated::{
    GpuVisibilityCorrection, VisibilityCorrection, VisibilityCorrectionError, correlated_lambda,
    correlated_visible_mean_attribute, correlated_visible_mean_attribute_for_directions, cos_azimuth_difference,
};
pub use cubic_correction::{
    CUBIC_DEVIATION_BUDGET, CubicCorrectionError, CubicFitError, CubicLambdaCorrection, GpuCubicLambdaCorrection,
    cubic_corrected_visible_mean_attribute,
};
pub use encoding::{NONE_BITS, encode};
pub use erf::{erf, erfc, erfcx};
pub use height::{attribute_at_height, height_cdf, height_visibility, log_height_cdf};
pub use masking::{
    SlopeAxis, SlopeDeviation, SlopeDeviationError, mean_visibility, nu_of_direction, projected_slope_deviation,
    smith_lambda, smith_lambda_direction, smith_lambda_from_nu,
};
pub use shading::{FilteredSurface, convolved_slope_deviation, gaussian_slope_ndf, shade};
#[cfg(feature = "wgsl")]
pub use wgsl::WGSL;
