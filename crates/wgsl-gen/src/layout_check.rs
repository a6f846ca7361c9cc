//! Proof that the WGSL layout of each generated struct equals the Rust layout.

use std::fmt;

use crate::StructDecl;

/// One difference between a Rust struct and its WGSL twin.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LayoutMismatch {
    /// The struct is not declared in the WGSL module.
    Missing {
        /// Struct name.
        name: &'static str,
    },
    /// The structs have different member counts.
    MemberCount {
        /// Struct name.
        name: &'static str,
        /// Members in Rust.
        rust: usize,
        /// Members in WGSL.
        wgsl: usize,
    },
    /// A member differs in name, offset or size.
    Member {
        /// Struct name.
        name: &'static str,
        /// Rust field name.
        field: &'static str,
        /// Rust `(offset, size)`.
        rust: (usize, usize),
        /// WGSL `(name, offset, size)`.
        wgsl: (String, usize, usize),
    },
    /// The structs have different sizes.
    Size {
        /// Struct name.
        name: &'static str,
        /// `size_of` in Rust.
        rust: usize,
        /// naga's size in WGSL.
        wgsl: usize,
    },
}

impl fmt::Display for LayoutMismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LayoutMismatch::Missing { name } => write!(f, "struct {name} is not declared in WGSL"),
            LayoutMismatch::MemberCount { name, rust, wgsl } => {
                write!(f, "struct {name}: {rust} fields in Rust, {wgsl} members in WGSL")
            }
            LayoutMismatch::Member { name, field, rust, wgsl } => write!(
                f,
                "struct {name}: Rust field `{field}` at offset {} size {}, WGSL member `{}` at offset {} size {}",
                rust.0, rust.1, wgsl.0, wgsl.1, wgsl.2
            ),
            LayoutMismatch::Size { name, rust, wgsl } => {
                write!(f, "struct {name}: {rust} bytes in Rust, {wgsl} bytes in WGSL (add explicit padding)")
            }
        }
    }
}

/// Compares naga's layout of each struct of `structs` in `module` with the Rust layout:
/// same member names, offsets and sizes, and the same total size.
pub fn check_layout(module: &naga::Module, structs: &[StructDecl]) -> Result<(), Vec<LayoutMismatch>> {
    let mut layouter = naga::proc::Layouter::default();
    let mut mismatches = Vec::new();
    if layouter.update(module.to_ctx()).is_err() {
        // A module that naga cannot lay out has no valid struct at all.
        mismatches.extend(structs.iter().map(|s| LayoutMismatch::Missing { name: s.name }));
        return Err(mismatches);
    }
    for decl in structs {
        let found = module.types.iter().find_map(|(_, ty)| match &ty.inner {
            naga::TypeInner::Struct { members, span } if ty.name.as_deref() == Some(decl.name) => {
                Some((members, *span as usize))
            }
            _ => None,
        });
        let Some((members, span)) = found else {
            mismatches.push(LayoutMismatch::Missing { name: decl.name });
            continue;
        };
        if members.len() != decl.fields.len() {
            mismatches.push(LayoutMismatch::MemberCount {
                name: decl.name,
                rust: decl.fields.len(),
                wgsl: members.len(),
            });
        }
        for (field, member) in decl.fields.iter().zip(members) {
            let wgsl_size = layouter[member.ty].size as usize;
            let wgsl_name = member.name.clone().unwrap_or_default();
            if wgsl_name != field.name || member.offset as usize != field.offset || wgsl_size != field.size {
                mismatches.push(LayoutMismatch::Member {
                    name: decl.name,
                    field: field.name,
                    rust: (field.offset, field.size),
                    wgsl: (wgsl_name, member.offset as usize, wgsl_size),
                });
            }
        }
        if span != decl.rust_size {
            mismatches.push(LayoutMismatch::Size { name: decl.name, rust: decl.rust_size, wgsl: span });
        }
    }
    if mismatches.is_empty() { Ok(()) } else { Err(mismatches) }
}

#[cfg(test)]
mod tests {
    use glam::{UVec4, Vec2};
    use gpu_layout::gpu_struct;

    use super::*;
    use crate::{ComposedShader, generate_declarations};

    gpu_struct! {
        /// Without the explicit tail padding its WGSL twin is 8 bytes larger.
        pub struct Unpadded {
            /// Indices.
            pub indices: UVec4,
            /// Weights.
            pub weights: Vec2,
        }
    }

    gpu_struct! {
        /// A `u32` before a `vec4` moves the vector to offset 16 in WGSL.
        pub struct Misaligned {
            /// Count.
            pub count: u32,
            /// Value.
            pub value: UVec4,
        }
    }

    #[test]
    fn the_classic_alignment_traps_are_caught() {
        let structs = [StructDecl::of::<Unpadded>(), StructDecl::of::<Misaligned>()];
        let wgsl = generate_declarations("traps", &structs, &[]).unwrap();
        let module = ComposedShader::new("traps").with_part("traps.wgsl", &wgsl).validate().unwrap();
        let errors = check_layout(&module.module, &structs).unwrap_err();
        assert!(errors.contains(&LayoutMismatch::Size { name: "Unpadded", rust: 24, wgsl: 32 }), "{errors:?}");
        assert!(
            errors.iter().any(|e| matches!(e, LayoutMismatch::Member { field: "value", rust: (4, 16), .. })),
            "{errors:?}"
        );
    }

    #[test]
    fn a_hand_edited_declaration_is_caught() {
        let structs = [StructDecl::of::<Unpadded>()];
        let module = ComposedShader::new("edited")
            .with_part("edited.wgsl", "struct Unpadded { indices: vec4<u32>, weights: vec2<f32>, extra: vec2<f32> }")
            .validate()
            .unwrap();
        let errors = check_layout(&module.module, &structs).unwrap_err();
        assert!(errors.iter().any(|e| matches!(e, LayoutMismatch::MemberCount { rust: 2, wgsl: 3, .. })));
        let missing = check_layout(&module.module, &[StructDecl::of::<Misaligned>()]).unwrap_err();
        assert_eq!(missing, vec![LayoutMismatch::Missing { name: "Misaligned" }]);
    }
}
