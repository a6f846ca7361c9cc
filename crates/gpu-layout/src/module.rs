//! A crate's WGSL twin as data: its generated declarations, its hand-written library, the
//! modules it must be composed after, and the Rust items its declarations come from.

use crate::{GpuConst, GpuField, GpuStruct};

/// A struct to declare in WGSL: its name, fields and Rust size. Built at compile time by
/// [`StructDecl::of`], so that a crate can list the structs of its WGSL twin in a `const`.
#[derive(Clone, Copy, Debug)]
pub struct StructDecl {
    /// WGSL (and Rust) name.
    pub name: &'static str,
    /// Fields with their Rust offsets and WGSL types.
    pub fields: &'static [GpuField],
    /// `size_of` of the Rust struct.
    pub rust_size: usize,
}

impl StructDecl {
    /// The declaration of `T`.
    pub const fn of<T: GpuStruct>() -> Self {
        Self { name: T::WGSL_NAME, fields: T::FIELDS, rust_size: size_of::<T>() }
    }
}

/// The WGSL twin of an algorithm crate, as the crate exports it (feature `wgsl`).
///
/// WGSL has one global namespace and no imports, so a module is used by pasting, in
/// order, the [`declarations`](Self::declarations) and [`library`](Self::library) of each
/// of its [`dependencies`](Self::dependencies), then its own
/// ([`write_source`](Self::write_source) does exactly that). For `naga_oil` composers
/// (Bevy), [`naga_oil_source`](Self::naga_oil_source) is the same text as one composable
/// module with `#define_import_path` [`name`](Self::name) and `#import` lines for what it
/// uses of its dependencies.
///
/// ```
/// use gpu_layout::WgslModule;
///
/// const BASE: WgslModule = WgslModule {
///     name: "base",
///     declarations: "const BASE_SCALE: f32 = 2.0;\n",
///     library: "fn base_scaled(x: f32) -> f32 { return x * BASE_SCALE; }\n",
///     naga_oil_source: "#define_import_path base\nconst BASE_SCALE: f32 = 2.0;\nfn base_scaled(x: f32) -> f32 { return x * BASE_SCALE; }\n",
///     dependencies: &[],
///     structs: &[],
///     constants: &[],
/// };
/// const USER: WgslModule = WgslModule {
///     name: "user",
///     declarations: "",
///     library: "fn user_twice(x: f32) -> f32 { return base_scaled(x); }\n",
///     naga_oil_source: "#define_import_path user\n#import base::base_scaled\nfn user_twice(x: f32) -> f32 { return base_scaled(x); }\n",
///     dependencies: &[&BASE],
///     structs: &[],
///     constants: &[],
/// };
///
/// let mut source = String::new();
/// USER.write_source(&mut source).unwrap();
/// assert!(source.find("fn base_scaled").unwrap() < source.find("fn user_twice").unwrap());
/// assert_eq!(USER.parts().map(|(name, _, _)| name).collect::<Vec<_>>(), ["base", "user"]);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct WgslModule {
    /// The module's name: the crate's name with underscores (`octahedral_map`); also its
    /// `naga_oil` import path and the prefix-free stem of its files.
    pub name: &'static str,
    /// The generated WGSL declarations of [`structs`](Self::structs) and
    /// [`constants`](Self::constants) (`cargo xtask codegen` writes them; a test checks
    /// that they are fresh).
    pub declarations: &'static str,
    /// The hand-written WGSL functions, the twins of the crate's Rust functions.
    pub library: &'static str,
    /// [`declarations`](Self::declarations) and [`library`](Self::library) as one
    /// `naga_oil` composable module: `#define_import_path` [`name`](Self::name) and one
    /// `#import` per dependency naming the items this module uses (generated too).
    pub naga_oil_source: &'static str,
    /// Every module this one calls into, directly or not, in the order they must be
    /// composed (each after those it uses).
    pub dependencies: &'static [&'static WgslModule],
    /// The Rust structs the declarations are generated from.
    pub structs: &'static [StructDecl],
    /// The Rust constants the declarations are generated from.
    pub constants: &'static [GpuConst],
}

impl WgslModule {
    /// The names of the modules this one must be composed after, in order.
    pub fn dependency_names(&self) -> impl Iterator<Item = &'static str> {
        self.dependencies.iter().map(|module| module.name)
    }

    /// `(module name, declarations, library)` of every dependency, then of this module: the
    /// parts to paste, in order, into one WGSL source.
    pub fn parts(&self) -> impl Iterator<Item = (&'static str, &'static str, &'static str)> {
        let this: &WgslModule = self;
        let own = (this.name, this.declarations, this.library);
        self.dependencies.iter().map(|m| (m.name, m.declarations, m.library)).chain(core::iter::once(own))
    }

    /// Writes the complete WGSL source of the module, dependencies first, each part headed
    /// by a comment naming it; paste it before the caller's own WGSL.
    pub fn write_source<W: core::fmt::Write>(&self, out: &mut W) -> core::fmt::Result {
        for (name, declarations, library) in self.parts() {
            writeln!(out, "// ---- {name}: declarations ----")?;
            out.write_str(declarations)?;
            if !declarations.is_empty() && !declarations.ends_with('\n') {
                out.write_char('\n')?;
            }
            writeln!(out, "// ---- {name}: library ----")?;
            out.write_str(library)?;
            if !library.is_empty() && !library.ends_with('\n') {
                out.write_char('\n')?;
            }
        }
        Ok(())
    }

    /// [`write_source`](Self::write_source) into a new string.
    #[cfg(feature = "alloc")]
    pub fn source(&self) -> alloc::string::String {
        let mut out = alloc::string::String::new();
        // Writing into a String cannot fail.
        let _ = self.write_source(&mut out);
        out
    }
}
