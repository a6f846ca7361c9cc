//! WGSL types of Rust field types, and their host-shareable layout (WGSL §14.4).

/// A WGSL scalar type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scalar {
    /// `f32`
    F32,
    /// `u32`
    U32,
    /// `i32`
    I32,
}

impl Scalar {
    /// The WGSL spelling of the scalar.
    pub const fn wgsl_name(self) -> &'static str {
        match self {
            Scalar::F32 => "f32",
            Scalar::U32 => "u32",
            Scalar::I32 => "i32",
        }
    }
}

/// A WGSL type that may appear in a host-shareable struct.
#[derive(Clone, Copy, Debug)]
pub enum WgslType {
    /// A scalar.
    Scalar(Scalar),
    /// `vecN<scalar>` with N = 2 or 4 (never 3, see the crate docs).
    Vector(u8, Scalar),
    /// `array<element, count>`.
    Array {
        /// The element type.
        element: fn() -> WgslType,
        /// The element count.
        count: u32,
    },
}

impl PartialEq for WgslType {
    fn eq(&self, other: &Self) -> bool {
        match (*self, *other) {
            (WgslType::Scalar(a), WgslType::Scalar(b)) => a == b,
            (WgslType::Vector(n, a), WgslType::Vector(m, b)) => n == m && a == b,
            (WgslType::Array { element: a, count: n }, WgslType::Array { element: b, count: m }) => {
                n == m && a() == b()
            }
            _ => false,
        }
    }
}

impl Eq for WgslType {}

impl WgslType {
    /// Alignment in bytes in the storage address space (WGSL §14.4.1).
    pub fn align(&self) -> u32 {
        match *self {
            WgslType::Scalar(_) => 4,
            WgslType::Vector(2, _) => 8,
            WgslType::Vector(_, _) => 16,
            WgslType::Array { element, .. } => element().align(),
        }
    }

    /// Size in bytes in the storage address space (WGSL §14.4.1).
    pub fn size(&self) -> u32 {
        match *self {
            WgslType::Scalar(_) => 4,
            WgslType::Vector(n, _) => 4 * u32::from(n),
            WgslType::Array { element, count } => {
                let element = element();
                count * element.size().next_multiple_of(element.align())
            }
        }
    }
}

/// A Rust type with a WGSL twin of the same size (checked by the `wgsl-gen` layout test).
pub trait WgslTyped {
    /// The WGSL type of `Self`.
    fn wgsl_type() -> WgslType;
}

macro_rules! impl_wgsl_typed {
    ($($rust:ty => $wgsl:expr),* $(,)?) => {
        $(impl WgslTyped for $rust {
            fn wgsl_type() -> WgslType {
                $wgsl
            }
        })*
    };
}

impl_wgsl_typed! {
    f32 => WgslType::Scalar(Scalar::F32),
    u32 => WgslType::Scalar(Scalar::U32),
    i32 => WgslType::Scalar(Scalar::I32),
    glam::Vec2 => WgslType::Vector(2, Scalar::F32),
    glam::Vec4 => WgslType::Vector(4, Scalar::F32),
    glam::UVec2 => WgslType::Vector(2, Scalar::U32),
    glam::UVec4 => WgslType::Vector(4, Scalar::U32),
    glam::IVec2 => WgslType::Vector(2, Scalar::I32),
    glam::IVec4 => WgslType::Vector(4, Scalar::I32),
}

impl<T: WgslTyped, const N: usize> WgslTyped for [T; N] {
    fn wgsl_type() -> WgslType {
        // A `[T; N]` with N > u32::MAX cannot be a GPU array; saturate so that the layout
        // check reports the mismatch instead of wrapping around.
        let count = u32::try_from(N).unwrap_or(u32::MAX);
        WgslType::Array { element: T::wgsl_type, count }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_and_alignments_follow_the_wgsl_rules() {
        assert_eq!(glam::Vec2::wgsl_type().align(), 8);
        assert_eq!(glam::UVec4::wgsl_type().align(), 16);
        assert_eq!(<[u32; 3]>::wgsl_type().size(), 12);
        assert_eq!(<[glam::Vec2; 3]>::wgsl_type().size(), 24);
        assert_eq!(<[glam::Vec4; 2]>::wgsl_type().align(), 16);
    }
}
