//! The methods of the tables: the patch constructions and the tracing methods, each a map,
//! its patches and a stepping.

use ddm_tracer::{PatchSurface, Stepping, TraceSettings};

use super::TraceTablesSettings;

/// A patch construction of the tables.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PatchKind {
    /// The paper's C⁰ patches (§3.1 steps b–c).
    C0,
    /// Each voxel's fitted quadric (step a).
    Fitted,
    /// The mesh's own triangles per voxel (exact).
    Triangles,
    /// The fitted quadric or the triangles under the error budget.
    Adaptive,
    /// The watertight C⁰ patches from decisions shared by neighbours (beyond the paper).
    Watertight,
}

impl PatchKind {
    /// The five, in table order.
    pub const ALL: [PatchKind; 5] = [Self::C0, Self::Fitted, Self::Triangles, Self::Adaptive, Self::Watertight];

    /// The construction of `ddm_tracer` it is (`adaptive_budget`: the adaptive patches'
    /// error budget, voxels).
    pub fn surface(self, adaptive_budget: f32) -> PatchSurface {
        match self {
            Self::C0 => PatchSurface::C0,
            Self::Fitted => PatchSurface::FittedQuadric,
            Self::Triangles => PatchSurface::Triangles,
            Self::Adaptive => PatchSurface::Adaptive { max_error: adaptive_budget },
            Self::Watertight => PatchSurface::Watertight,
        }
    }

    /// The name in `ddm_trace_patches.csv`.
    pub fn name(self) -> &'static str {
        match self {
            Self::C0 => "C0",
            Self::Fitted => "fitted",
            Self::Triangles => "triangles",
            Self::Adaptive => "adaptive",
            Self::Watertight => "watertight",
        }
    }
}

/// A method of Tables 1–3.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TraceMethod {
    /// Sphere tracing with the plain distance map.
    Dm,
    /// Sphere tracing with the DDM 2×1.
    Ddm2x1,
    /// Sphere tracing with the DDM 4×1.
    Ddm4x1,
    /// Sphere tracing with the DDM 8×1.
    Ddm8x1,
    /// Sphere tracing with the DDM 4×2.
    Ddm4x2,
    /// DDM 4×1 + the C⁰ quadric patches (Algorithm 3.1).
    Ddm4x1Quadric,
    /// DDM 4×1 + each voxel's fitted quadric.
    Ddm4x1Fitted,
    /// DDM 4×1 + the mesh's triangles (exact).
    Ddm4x1Triangles,
    /// DDM 4×1 + the adaptive patches.
    Ddm4x1Adaptive,
    /// DDM 4×1 + the watertight C⁰ patches.
    Ddm4x1Watertight,
    /// The plain distance map with voxel-exit stepping.
    DmExit,
    /// The DDM 4×1 with voxel-exit stepping.
    Ddm4x1Exit,
    /// DDM 4×1 + the adaptive patches with voxel-exit stepping.
    Ddm4x1AdaptiveExit,
    /// Relief mapping (height fields only).
    Relief,
}

/// How a map-based method traces: its map, patches and settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MethodCase {
    /// The map's name in [`crate::maps::TRACE_MAPS`].
    pub map: &'static str,
    /// The patches, for [`ddm_tracer::Method::Quadric`].
    pub patches: Option<PatchKind>,
    /// Method and stepping (`max_steps` from the settings).
    pub settings: TraceSettings,
}

impl TraceMethod {
    /// All methods, in table order.
    pub const ALL: [TraceMethod; 14] = [
        Self::Dm,
        Self::Ddm2x1,
        Self::Ddm4x1,
        Self::Ddm8x1,
        Self::Ddm4x2,
        Self::Ddm4x1Quadric,
        Self::Ddm4x1Fitted,
        Self::Ddm4x1Triangles,
        Self::Ddm4x1Adaptive,
        Self::Ddm4x1Watertight,
        Self::DmExit,
        Self::Ddm4x1Exit,
        Self::Ddm4x1AdaptiveExit,
        Self::Relief,
    ];

    /// The name in the tables.
    pub fn name(self) -> &'static str {
        match self {
            Self::Dm => "DM",
            Self::Ddm2x1 => "DDM 2x1",
            Self::Ddm4x1 => "DDM 4x1",
            Self::Ddm8x1 => "DDM 8x1",
            Self::Ddm4x2 => "DDM 4x2",
            Self::Ddm4x1Quadric => "DDM 4x1 + quadric",
            Self::Ddm4x1Fitted => "DDM 4x1 + fitted Q",
            Self::Ddm4x1Triangles => "DDM 4x1 + triangles",
            Self::Ddm4x1Adaptive => "DDM 4x1 + adaptive",
            Self::Ddm4x1Watertight => "DDM 4x1 + watertight",
            Self::DmExit => "DM exit",
            Self::Ddm4x1Exit => "DDM 4x1 exit",
            Self::Ddm4x1AdaptiveExit => "DDM 4x1 + adaptive exit",
            Self::Relief => "relief 32+8",
        }
    }

    /// The map, patches and settings of a map-based method (`None` for relief mapping).
    pub fn case(self, settings: &TraceTablesSettings) -> Option<MethodCase> {
        let (sphere, quadric) = (settings.sphere(), settings.quadric());
        let exit = |s: TraceSettings| TraceSettings { stepping: Stepping::VoxelExit, ..s };
        let case = |map, patches, settings| Some(MethodCase { map, patches, settings });
        match self {
            Self::Dm | Self::Ddm2x1 | Self::Ddm4x1 | Self::Ddm8x1 | Self::Ddm4x2 => case(self.name(), None, sphere),
            Self::Ddm4x1Quadric => case("DDM 4x1", Some(PatchKind::C0), quadric),
            Self::Ddm4x1Fitted => case("DDM 4x1", Some(PatchKind::Fitted), quadric),
            Self::Ddm4x1Triangles => case("DDM 4x1", Some(PatchKind::Triangles), quadric),
            Self::Ddm4x1Adaptive => case("DDM 4x1", Some(PatchKind::Adaptive), quadric),
            Self::Ddm4x1Watertight => case("DDM 4x1", Some(PatchKind::Watertight), quadric),
            Self::DmExit => case("DM", None, exit(sphere)),
            Self::Ddm4x1Exit => case("DDM 4x1", None, exit(sphere)),
            Self::Ddm4x1AdaptiveExit => case("DDM 4x1", Some(PatchKind::Adaptive), exit(quadric)),
            Self::Relief => None,
        }
    }
}
