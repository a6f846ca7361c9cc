//! Deterministic dense stackings of quasi-spherical grains from a seed, after Michel &
//! Boubekeur, *Real Time Multiscale Rendering of Dense Dynamic Stackings* (CGF 2020): the
//! scenes of its experiments (20 k to 20 M grains, Fig. 9–11, 14–17) with the properties
//! its method relies on — grains whose surface lies between the spheres of radii `r` and
//! `R` about their centre (§1), inner balls that never overlap, so they can serve as
//! occluders (§8), per-grain procedural colours (Fig. 16), and motion of positions *and*
//! orientations every frame.
//!
//! ```
//! use grain_scenes::{GrainRadii, Region, Shake, Stacking, StackingSpec};
//! use glam::Vec4;
//!
//! // A coffee bean's r and R (take them from grain_mesh::GrainBounds).
//! let radii = GrainRadii::new(0.55, 1.0)?;
//! let mut spec = StackingSpec::new(1_000, radii);
//! spec.seed = 42;
//! spec.region = Region::Pile { slope: 0.6 };
//! spec.scale_jitter = 0.1;
//! spec.jitter = 0.1;
//! spec.spacing = 0.9; // denser than touching outer balls: 0.9·(1 − 2·0.1) ≥ r/R
//! let stacking = Stacking::generate(&spec)?;
//! assert_eq!(stacking.len(), 1_000);
//! assert!(stacking.min_inner_gap() >= 0.0); // inner balls disjoint, by construction
//! assert!(stacking.min_outer_gap() < 0.0); // outer balls overlap: a dense pile
//!
//! // A frame of animation, written into the caller's buffers.
//! let shake = Shake::new(0.05, 2.0, 1.5)?;
//! let mut centre_scale = vec![Vec4::ZERO; stacking.len()];
//! let mut rotation = vec![Vec4::ZERO; stacking.len()];
//! shake.pose_at(&stacking, 0.25, &mut centre_scale, &mut rotation)?;
//! assert!(grain_scenes::min_gap(&centre_scale, radii.inner()) >= 0.0);
//! # Ok::<(), grain_scenes::SceneError>(())
//! ```
//!
//! # Modules
//!
//! - [`spec`]: [`GrainRadii`], [`Region`] (box or conical pile), [`StackingSpec`] and the
//!   paper's sizes [`StackingSize`] (`"20k"`, `"200k"`, `"1.6M"`, `"20M"`).
//! - [`stacking`]: [`Stacking::generate`], the structure-of-arrays result
//!   (`centre_scale`, `rotation`, `colour`), its [`Aabb`] and gaps.
//! - [`shake`]: [`Shake`], per-frame positions and orientations.
//! - [`gap`]: [`min_gap`], the smallest gap between balls, `O(n)` with a hashed grid.
//! - [`colour`]: [`SAND_RAMP`], Fig. 16's hashed colour ramp, RGBA8 packing.
//! - [`rng`]: the counter-based `SplitMix64` hash and the uniform samplers.
//! - [`memory`]: [`MemoryLimit`], the guard against stackings larger than memory.
//! - [`error`]: [`SceneError`], naming the field or the limit at fault.
//!
//! # Determinism
//!
//! Every random value of grain `i` is a pure function of `(seed, i, attribute)`
//! ([`rng`]): grains are generated independently, a grain's orientation, scale and colour
//! do not depend on `count`, and its site depends only on the region, the count and `i`.
//! Generation uses only integer arithmetic and correctly rounded `f64` operations
//! (`+ − × ÷ √`, `floor`, `round`; no `sin`, `cbrt` or `powf`), so a seed gives
//! bit-identical stackings on every platform and version of this crate (a change of the
//! generator is a breaking change). Poses of [`Shake`] use `sin`/`cos` and may differ by an
//! ulp between platforms.
//!
//! # Guarantees
//!
//! - Exactly `count` grains on distinct FCC sites, lowest layers first: the
//!   stacking fills like a pour, and the last layer grows from its centre.
//! - **Inner balls never overlap**: with `d` the lattice distance, centres lie within
//!   `jitter·d` of distinct FCC sites `d` apart, so specs must satisfy
//!   `spacing·(1 − 2·jitter) ≥ r/R` (plus a rounding margin for the `f32` storage); the
//!   stored data then has [`Stacking::min_inner_gap`] `≥ 0`. The same holds at every time
//!   of a [`Shake`], whose amplitude is added to the jitter in the inequality.
//! - **Outer balls never overlap** (meshes cannot interpenetrate) when
//!   `spacing·(1 − 2·jitter) ≥ 1` with the margin ([`Stacking::outer_balls_disjoint`]).
//! - Every grain's outer ball lies above the ground plane `y = 0`; orientations are
//!   uniform unit quaternions; scales lie in `[1 − scale_jitter, 1 + scale_jitter]`.
//! - Bad input is an error naming the field, never a panic; a stacking larger than the
//!   memory available is refused before anything is allocated.

mod lattice;

pub mod colour;
pub mod error;
pub mod gap;
pub mod memory;
pub mod rng;
pub mod shake;
pub mod spec;
pub mod stacking;

pub use colour::{SAND_RAMP, pack_rgba8, sand_ramp, unpack_rgba8};
pub use error::SceneError;
pub use gap::min_gap;
pub use memory::{BYTES_PER_GRAIN, MemoryLimit, available_memory};
pub use rng::{GrainRng, Stream};
pub use shake::Shake;
pub use spec::{GrainRadii, MAX_ASPECT_RATIO, Region, SLOPE_RANGE, StackingSize, StackingSpec};
pub use stacking::{Aabb, Stacking};
