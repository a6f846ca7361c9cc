//! The crate's WGSL twin (feature `wgsl`): the generated declarations of the structs and
//! constants below (the GPU forms of the validated corrections, approximation
//! coefficients, thresholds, float bit masks) and the
//! functions of `wgsl/smith_micro.wgsl`, each the twin of the Rust function named in its
//! comment, with the same formulas in the same order.

use gpu_layout::f32_bits::{ABS_MASK, INFINITY_BITS, SIGN_MASK};
use gpu_layout::{StructDecl, WgslModule, gpu_const};

use crate::attribute::MAX_ATTRIBUTE_MAGNITUDE;
use crate::correction::{
    CORRECTION_KNOTS, GpuLambdaCorrection, MAX_CORRECTED_LAMBDA, MAX_CORRECTION_FACTOR, MIN_CORRECTION_FACTOR,
};
use crate::correlated::{GpuVisibilityCorrection, MAX_CORRELATION, MAX_CORRELATION_COEFFICIENT, MIN_CORRELATION};
use crate::cubic_correction::GpuCubicLambdaCorrection;
use crate::encoding::NONE_BITS;
use crate::erf::{ERF_SERIES_LIMIT, ERFC_COEFFICIENTS, ERFC_ZERO_FROM, EXP_ZERO_FROM};
use crate::height::{LOG_ONE_MINUS_SERIES_LIMIT, MAX_HEIGHT_DEVIATION, STANDARDIZED_HEIGHT_LIMIT};
use crate::masking::{
    CONTINUED_FRACTION_FROM_NU, CONTINUED_FRACTION_TERMS, FRAC_1_SQRT_PI, LAMBDA_ZERO_FROM_NU, MAX_SLOPE_DEVIATION,
    MIN_SLOPE_DEVIATION,
};
use crate::shading::MAX_LIGHT_RADIANCE;

/// The WGSL twin of this crate: `erf`/`erfc`/`erfcx`, Smith's Λ (eq. 6), g(h) and V = g^Λ
/// (eqs. 4–5), the visible mean attribute (eq. 17) and its corrected models, the §5.5
/// convolution and eq. 13's shading; no dependencies.
pub const WGSL: WgslModule = WgslModule {
    name: "smith_micro",
    declarations: include_str!("../wgsl/generated/smith_micro.wgsl"),
    library: include_str!("../wgsl/smith_micro.wgsl"),
    naga_oil_source: concat!(
        include_str!("../wgsl/generated/smith_micro.naga_oil_header.wgsl"),
        include_str!("../wgsl/generated/smith_micro.wgsl"),
        include_str!("../wgsl/smith_micro.wgsl"),
    ),
    dependencies: &[],
    structs: &[
        StructDecl::of::<GpuLambdaCorrection>(),
        StructDecl::of::<GpuVisibilityCorrection>(),
        StructDecl::of::<GpuCubicLambdaCorrection>(),
    ],
    constants: &[
        gpu_const!(ABS_MASK: u32 as "SMITH_ABS_MASK"),
        gpu_const!(SIGN_MASK: u32 as "SMITH_SIGN_MASK"),
        gpu_const!(INFINITY_BITS: u32 as "SMITH_EXPONENT_MASK"),
        gpu_const!("SMITH_F32_MAX": f32 = f32::MAX),
        gpu_const!("SMITH_SQRT_2": f32 = core::f32::consts::SQRT_2),
        gpu_const!("SMITH_TAU": f32 = core::f32::consts::TAU),
        gpu_const!(EXP_ZERO_FROM: f32 as "SMITH_EXP_ZERO_FROM"),
        gpu_const!(NONE_BITS: u32 as "SMITH_NONE_BITS"),
        gpu_const!("SMITH_ERFC_C0": f32 = ERFC_COEFFICIENTS[0]),
        gpu_const!("SMITH_ERFC_C1": f32 = ERFC_COEFFICIENTS[1]),
        gpu_const!("SMITH_ERFC_C2": f32 = ERFC_COEFFICIENTS[2]),
        gpu_const!("SMITH_ERFC_C3": f32 = ERFC_COEFFICIENTS[3]),
        gpu_const!("SMITH_ERFC_C4": f32 = ERFC_COEFFICIENTS[4]),
        gpu_const!("SMITH_ERFC_C5": f32 = ERFC_COEFFICIENTS[5]),
        gpu_const!("SMITH_ERFC_C6": f32 = ERFC_COEFFICIENTS[6]),
        gpu_const!("SMITH_ERFC_C7": f32 = ERFC_COEFFICIENTS[7]),
        gpu_const!("SMITH_ERFC_C8": f32 = ERFC_COEFFICIENTS[8]),
        gpu_const!("SMITH_ERFC_C9": f32 = ERFC_COEFFICIENTS[9]),
        gpu_const!(ERF_SERIES_LIMIT: f32 as "SMITH_ERF_SERIES_LIMIT"),
        gpu_const!(ERFC_ZERO_FROM: f32 as "SMITH_ERFC_ZERO_FROM"),
        gpu_const!(FRAC_1_SQRT_PI: f32 as "SMITH_FRAC_1_SQRT_PI"),
        gpu_const!(CONTINUED_FRACTION_FROM_NU: f32 as "SMITH_CONTINUED_FRACTION_FROM_NU"),
        gpu_const!(CONTINUED_FRACTION_TERMS: u32 as "SMITH_CONTINUED_FRACTION_TERMS"),
        gpu_const!(LAMBDA_ZERO_FROM_NU: f32 as "SMITH_LAMBDA_ZERO_FROM_NU"),
        gpu_const!(MAX_SLOPE_DEVIATION: f32 as "SMITH_MAX_SLOPE_DEVIATION"),
        gpu_const!(MIN_SLOPE_DEVIATION: f32 as "SMITH_MIN_SLOPE_DEVIATION"),
        gpu_const!(LOG_ONE_MINUS_SERIES_LIMIT: f32 as "SMITH_LOG_ONE_MINUS_SERIES_LIMIT"),
        gpu_const!(MAX_HEIGHT_DEVIATION: f32 as "SMITH_MAX_HEIGHT_DEVIATION"),
        gpu_const!(STANDARDIZED_HEIGHT_LIMIT: f32 as "SMITH_STANDARDIZED_HEIGHT_LIMIT"),
        gpu_const!(MAX_ATTRIBUTE_MAGNITUDE: f32 as "SMITH_MAX_ATTRIBUTE_MAGNITUDE"),
        gpu_const!(MAX_LIGHT_RADIANCE: f32 as "SMITH_MAX_LIGHT_RADIANCE"),
        gpu_const!("SMITH_CORRECTION_SEGMENTS": u32 = CORRECTION_KNOTS as u32 - 1),
        gpu_const!(MIN_CORRECTION_FACTOR: f32 as "SMITH_MIN_CORRECTION_FACTOR"),
        gpu_const!(MAX_CORRECTION_FACTOR: f32 as "SMITH_MAX_CORRECTION_FACTOR"),
        gpu_const!(MAX_CORRECTED_LAMBDA: f32 as "SMITH_MAX_CORRECTED_LAMBDA"),
        gpu_const!(MIN_CORRELATION: f32 as "SMITH_MIN_CORRELATION"),
        gpu_const!(MAX_CORRELATION: f32 as "SMITH_MAX_CORRELATION"),
        gpu_const!(MAX_CORRELATION_COEFFICIENT: f32 as "SMITH_MAX_CORRELATION_COEFFICIENT"),
    ],
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn structs_have_the_expected_sizes() {
        assert_eq!(size_of::<GpuLambdaCorrection>(), 32);
        assert_eq!(size_of::<GpuVisibilityCorrection>(), 80);
        assert_eq!(size_of::<GpuCubicLambdaCorrection>(), 16);
    }
}
