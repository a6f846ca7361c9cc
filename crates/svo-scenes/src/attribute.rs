//! The colour of a surface: a constant, or a function of the position (or, for height maps
//! and displaced surfaces, of the height).

use std::fmt;
use std::sync::Arc;

use glam::Vec3;
use svo_brick::ATTRIBUTE_CHANNELS;

use crate::error::{SceneError, check};

/// An RGB attribute in `[0, 1]`: a constant, or a function of `X` (the surface point for
/// shapes and meshes, the height for height maps).
///
/// A function's values are clamped to `[0, 1]` when evaluated (NaN becomes 0), so the
/// [`SurfaceSource`](svo_brick::SurfaceSource) contract holds whatever the closure returns.
/// Cloning shares the closure.
pub struct Attribute<X = Vec3> {
    repr: Repr<X>,
}

/// A closure from `X` to RGB, shared between threads.
type Function<X> = Arc<dyn Fn(X) -> [f32; ATTRIBUTE_CHANNELS] + Send + Sync>;

enum Repr<X> {
    Constant([f32; ATTRIBUTE_CHANNELS]),
    Function(Function<X>),
}

impl<X> Attribute<X> {
    /// A constant colour; each channel must lie in `[0, 1]`.
    pub fn constant(rgb: [f32; ATTRIBUTE_CHANNELS]) -> Result<Self, SceneError> {
        let rgb = check("Attribute", "constant", rgb, rgb.iter().all(|c| (0.0..=1.0).contains(c)), "in [0, 1]")?;
        Ok(Attribute { repr: Repr::Constant(rgb) })
    }

    /// A mid grey, `[0.5; 3]`.
    pub fn grey() -> Self {
        Attribute { repr: Repr::Constant([0.5; ATTRIBUTE_CHANNELS]) }
    }

    /// A colour computed from `X` (clamped to `[0, 1]` when evaluated).
    pub fn function(f: impl Fn(X) -> [f32; ATTRIBUTE_CHANNELS] + Send + Sync + 'static) -> Self {
        Attribute { repr: Repr::Function(Arc::new(f)) }
    }

    /// The colour at `x`, each channel in `[0, 1]`.
    pub fn eval(&self, x: X) -> [f32; ATTRIBUTE_CHANNELS] {
        match &self.repr {
            Repr::Constant(rgb) => *rgb,
            // `NaN >= 0.0` is false, so NaN becomes 0.
            Repr::Function(f) => f(x).map(|c| if c >= 0.0 { c.min(1.0) } else { 0.0 }),
        }
    }
}

impl<X> Clone for Attribute<X> {
    fn clone(&self) -> Self {
        let repr = match &self.repr {
            Repr::Constant(rgb) => Repr::Constant(*rgb),
            Repr::Function(f) => Repr::Function(Arc::clone(f)),
        };
        Attribute { repr }
    }
}

impl<X> fmt::Debug for Attribute<X> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.repr {
            Repr::Constant(rgb) => f.debug_tuple("Attribute::Constant").field(rgb).finish(),
            Repr::Function(_) => f.write_str("Attribute::Function(..)"),
        }
    }
}

impl<X> Default for Attribute<X> {
    /// [`Attribute::grey`].
    fn default() -> Self {
        Attribute::grey()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constants_are_checked_and_functions_clamped() {
        assert!(Attribute::<Vec3>::constant([0.0, 1.0, 0.5]).is_ok());
        let error = Attribute::<Vec3>::constant([0.0, 1.5, 0.5]).unwrap_err();
        assert!(error.to_string().contains("Attribute.constant"), "{error}");
        let f = Attribute::function(|h: f32| [h, -h, f32::NAN]);
        assert_eq!(f.eval(2.0), [1.0, 0.0, 0.0]);
        assert_eq!(f.clone().eval(0.25), [0.25, 0.0, 0.0]);
        assert_eq!(format!("{f:?}"), "Attribute::Function(..)");
    }
}
