//! The I/O of the `smith_micro_*_differential` kernels: one case of inputs per invocation,
//! results encoded as bits (`smith_micro::encode`: `None` as `SMITH_NONE_BITS`, every other
//! value, ±∞ included, as its own bits).

use glam::{UVec4, Vec4};
use gpu_layout::{StructDecl, gpu_struct};

gpu_struct! {
    /// The inputs of one case of the differential kernel `smith_values`: every function
    /// of the crate reads the fields it needs (see the CPU reference in `tests/smith_micro_gpu.rs`).
    pub struct SmithCase {
        /// `xyz`: the view direction in the mean-normal frame; `w`: a `ν` for
        /// `smith_lambda_from_nu`.
        pub view: Vec4,
        /// `xyz`: the light direction; `w`: an `x` for `erf`, `erfc`, `erfcx`.
        pub light: Vec4,
        /// `(σ_nx, σ_ny, σ_npx, σ_npy)`: surface and BRDF slope deviations.
        pub slopes: Vec4,
        /// `(μ, σ, h, σ_h)`: the isotropic Λ's inputs, a height and the height deviation.
        pub scalars: Vec4,
        /// `(ā, a_s, Ē, Λ)`: the attribute, the light radiance, and a Λ for `g^Λ` and
        /// `1/(1+Λ)`.
        pub material: Vec4,
    }
}

gpu_struct! {
    /// The encoded results of one [`SmithCase`] (see the CPU reference in `tests/smith_micro_gpu.rs`).
    pub struct SmithResults {
        /// Four groups of four results.
        pub values: [UVec4; 4],
    }
}

gpu_struct! {
    /// The inputs of one case of the differential kernel `smith_corrected_values`. The
    /// knots are the `GpuLambdaCorrection` of a validated `smith_micro::LambdaCorrection`
    /// (`LambdaCorrection::to_gpu`), which the WGSL twin takes without re-checking it.
    pub struct CorrectionCase {
        /// `GpuLambdaCorrection::low`: the factors at knots 0 … 3.
        pub knots_low: Vec4,
        /// `GpuLambdaCorrection::high`: the factors at knots 4 … 7.
        pub knots_high: Vec4,
        /// `(ā, a_s, Λ(v), Λ(l))`.
        pub inputs: Vec4,
    }
}

gpu_struct! {
    /// The encoded results of one [`CorrectionCase`] (see the CPU reference in `tests/smith_micro_gpu.rs`).
    pub struct CorrectionResults {
        /// Four results.
        pub values: UVec4,
    }
}

gpu_struct! {
    /// The inputs of one case of the differential kernel `smith_cubic_corrected_values`.
    pub struct CubicCase {
        /// `GpuCubicLambdaCorrection::coefficients` of a validated
        /// `smith_micro::CubicLambdaCorrection` (`CubicLambdaCorrection::to_gpu`), which the
        /// WGSL twin takes without re-checking it.
        pub coefficients: Vec4,
        /// `(ā, a_s, Λ(v), Λ(l))`.
        pub inputs: Vec4,
    }
}

gpu_struct! {
    /// The encoded results of one [`CubicCase`] (see the CPU reference in `tests/smith_micro_gpu.rs`).
    pub struct CubicResults {
        /// Four results.
        pub values: UVec4,
    }
}

gpu_struct! {
    /// The inputs of one case of the differential kernel `smith_correlated_values`. The
    /// first five fields are the `GpuVisibilityCorrection` of a validated
    /// `smith_micro::VisibilityCorrection` (`VisibilityCorrection::to_gpu`), in its order,
    /// which the WGSL twin takes without re-checking it.
    pub struct CorrelatedCase {
        /// `GpuVisibilityCorrection::view_low` of the model under test.
        pub view_low: Vec4,
        /// `GpuVisibilityCorrection::view_high`.
        pub view_high: Vec4,
        /// `GpuVisibilityCorrection::light_low`.
        pub light_low: Vec4,
        /// `GpuVisibilityCorrection::light_high`.
        pub light_high: Vec4,
        /// `GpuVisibilityCorrection::correlation`: `(ρ₀, ρ₁, ρ₂, 0)`.
        pub correlation: Vec4,
        /// `(ā, a_s, Λ(v), Λ(l))`.
        pub inputs: Vec4,
        /// The view direction in `xyz`, `cos Δφ` for the Λ-based functions in `w`.
        pub view: Vec4,
        /// The light direction in `xyz`, the isotropic slope deviation `σ_n` in `w`.
        pub light: Vec4,
    }
}

gpu_struct! {
    /// The encoded results of one [`CorrelatedCase`] (see the CPU reference in `tests/smith_micro_gpu.rs`).
    pub struct CorrelatedResults {
        /// Four results.
        pub values: UVec4,
    }
}

/// The structs of every `smith_micro` kernel.
pub const STRUCTS: &[StructDecl] = &[
    StructDecl::of::<SmithCase>(),
    StructDecl::of::<SmithResults>(),
    StructDecl::of::<CorrectionCase>(),
    StructDecl::of::<CorrectionResults>(),
    StructDecl::of::<CubicCase>(),
    StructDecl::of::<CubicResults>(),
    StructDecl::of::<CorrelatedCase>(),
    StructDecl::of::<CorrelatedResults>(),
];
