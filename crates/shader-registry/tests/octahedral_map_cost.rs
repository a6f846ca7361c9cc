//! The GPU cost of `octahedral_view_sample`, the WGSL twin of `octahedral-map`'s Listing 1
//! with a defined result for every input, beside a direct WGSL transcription of the
//! paper's Listing 1 (`paper_view_sample` below, test-only: it has no defined result for
//! zero, NaN or infinite inputs), counted on naga's IR.
//!
//! Two counts of each function, both with callees inlined and both sides of every branch
//! counted:
//! - `wgsl_gen::operation_count`: arithmetic per component, dynamic indexing, branches
//!   (see its documentation); the assertions use its total;
//! - the emitted expressions by kind (`Binary`, `Math`, `Select`, `As`, …), one per
//!   expression whatever its width, beside the size of the function's own expression
//!   arena (constants, arguments and loads included, callees not), for the record.
//!
//! The crate's function classifies its input once (`octahedral_is_plain_direction`) and
//! takes the canonical form (`octahedral_canonical_direction`) only when the input is not
//! plain; the common path is everything but that branch's body. The bound asserted:
//!
//! ```text
//! common path ≤ paper + classification
//! ```
//!
//! where the classification is `octahedral_is_plain_direction` plus the `!` and the `if`
//! that branch on it: every other robustness fix (the clamp of `n`, of `u` and `v`, the
//! cancellation-free sums) is paid for inside the paper's own budget.
//!
//! Measured: the paper 44 operations (43 arithmetic, its one `if`). The crate's function
//! 134 in all, 66 on the common path: the classification 21 (branch-free bit tests), its
//! `!` and `if` 2, the clamp of `n` 1, the kernel `octahedral_view_sample_of_plain` 42:
//! the listing's 44, plus the clamps of `u` and `v` (2; the non-negative sums cost what
//! the listing's normalisation does), less 2 products (two rows times `n` where the
//! listing multiplies both floors and both ceilings by `(n, 1)`), less 2 additions (`n²`
//! added to the two rows instead of the four indices). The canonical form's 68 count only
//! for directions that are not plain. Before the classification, every direction
//! paid 120: the canonical form 68, the clamp of `n` 1, a kernel of 51.

use std::collections::BTreeMap;

use naga::{Block, Expression, Function, Handle, Statement};
use wgsl_gen::{OperationCount, ValidatedModule, operation_count};

/// Listing 1 (`DirectionToViewIndices`) transcribed line by line from GLSL; `ViewSample`
/// stands for the `out` parameters.
const PAPER_LISTING_1: &str = "
fn paper_view_sample(direction: vec3<f32>, n: u32) -> ViewSample {
    let d = direction / dot(vec3<f32>(1.0), abs(direction));
    let uv = (vec2<f32>(1.0, -1.0) * d.y + d.x + 1.0) * f32(n - 1u) / 2.0;
    let fuv = vec2<u32>(floor(uv)) * vec2<u32>(n, 1u);
    let cuv = vec2<u32>(ceil(uv)) * vec2<u32>(n, 1u);
    var i = vec4<u32>(fuv.x + fuv.y, cuv.x + fuv.y, fuv.x + cuv.y, cuv.x + cuv.y);
    if d.z > 0.0 {
        i += n * n;
    }
    var sample: ViewSample;
    sample.indices = i;
    sample.alpha = fract(uv);
    sample.padding = vec2<f32>(0.0);
    return sample;
}
";

fn module() -> ValidatedModule {
    let module = shader_registry::module("octahedral_map").expect("octahedral_map is registered");
    let shader = module.shader().with_part("paper_listing_1.wgsl (test)", PAPER_LISTING_1);
    shader.validate().unwrap_or_else(|e| panic!("{e}"))
}

fn function(validated: &ValidatedModule, name: &str) -> Handle<Function> {
    let found = validated.module.functions.iter().find(|(_, f)| f.name.as_deref() == Some(name));
    found.unwrap_or_else(|| panic!("no function {name}")).0
}

fn count(validated: &ValidatedModule, name: &str) -> OperationCount {
    operation_count(validated, name).unwrap_or_else(|| panic!("no function {name}"))
}

/// The emitted expressions of `block` (callees inlined) by kind, added to `kinds`.
fn expression_kinds(
    validated: &ValidatedModule,
    function: Handle<Function>,
    block: &Block,
    kinds: &mut BTreeMap<&'static str, usize>,
) {
    let module = &validated.module;
    for statement in block.iter() {
        match statement {
            Statement::Emit(range) => {
                for expression in range.clone() {
                    let kind = match module.functions[function].expressions[expression] {
                        Expression::Binary { .. } => "Binary",
                        Expression::Unary { .. } => "Unary",
                        Expression::Select { .. } => "Select",
                        Expression::Relational { .. } => "Relational",
                        Expression::Math { .. } => "Math",
                        Expression::As { .. } => "As",
                        _ => "other (moves, loads, accesses)",
                    };
                    *kinds.entry(kind).or_default() += 1;
                }
            }
            Statement::Block(inner) => expression_kinds(validated, function, inner, kinds),
            Statement::If { accept, reject, .. } => {
                *kinds.entry("If").or_default() += 1;
                expression_kinds(validated, function, accept, kinds);
                expression_kinds(validated, function, reject, kinds);
            }
            Statement::Call { function: callee, .. } => {
                let body = &module.functions[*callee].body;
                expression_kinds(validated, *callee, body, kinds);
            }
            Statement::Switch { .. } | Statement::Loop { .. } => panic!("no switch or loop expected"),
            _ => {}
        }
    }
}

/// Prints both counts of `name`; returns the operation count.
fn report(validated: &ValidatedModule, name: &str) -> OperationCount {
    let handle = function(validated, name);
    let mut kinds = BTreeMap::new();
    expression_kinds(validated, handle, &validated.module.functions[handle].body, &mut kinds);
    let operations = count(validated, name);
    let arena = validated.module.functions[handle].expressions.len();
    println!("{name}: {operations:?} total {}", operations.total());
    println!("    {arena} expressions in its own arena; emitted, callees inlined: {kinds:?}");
    operations
}

/// The functions called from the top-level statements of `name`'s body, and those called
/// inside the accepted branch of one of its `if`s.
fn calls(validated: &ValidatedModule, name: &str) -> (Vec<String>, Vec<String>) {
    let module = &validated.module;
    let name_of = |callee: &Handle<Function>| module.functions[*callee].name.clone().unwrap_or_default();
    let (mut direct, mut branched) = (Vec::new(), Vec::new());
    for statement in module.functions[function(validated, name)].body.iter() {
        match statement {
            Statement::Call { function: callee, .. } => direct.push(name_of(callee)),
            Statement::If { accept, reject, .. } => {
                assert!(reject.is_empty(), "{name}: an else branch");
                for inner in accept.iter() {
                    if let Statement::Call { function: callee, .. } = inner {
                        branched.push(name_of(callee));
                    }
                }
            }
            _ => {}
        }
    }
    (direct, branched)
}

#[test]
fn view_sample_costs_at_most_the_paper_plus_the_classification() {
    let validated = module();
    let paper = report(&validated, "paper_view_sample");
    let ours = report(&validated, "octahedral_view_sample");
    let classification = report(&validated, "octahedral_is_plain_direction");
    let canonical = report(&validated, "octahedral_canonical_direction");
    let kernel = report(&validated, "octahedral_view_sample_of_plain");
    for c in [paper, ours, classification, canonical, kernel] {
        assert_eq!((c.loops, c.indexing), (0, 0), "{c:?}");
    }
    // The structure the bound relies on: the classification and the kernel on every
    // path, the canonical form only in the branch taken by directions that are not plain.
    let (direct, branched) = calls(&validated, "octahedral_view_sample");
    assert_eq!(direct, ["octahedral_is_plain_direction", "octahedral_view_sample_of_plain"]);
    assert_eq!(branched, ["octahedral_canonical_direction"]);
    // Besides its callees, the function has the clamp of n, the `!` and the `if`.
    let own = 3;
    assert_eq!(ours.total(), own + classification.total() + canonical.total() + kernel.total(), "{ours:?}");
    let common = ours.total() - canonical.total();
    let bound = paper.total() + classification.total() + 2;
    println!(
        "common path {common} (static {}, the canonical form {} of it) against the paper's {}: bound {bound} \
         (the classification {} + its `!` and `if`)",
        ours.total(),
        canonical.total(),
        paper.total(),
        classification.total()
    );
    // Equivalently: the kernel and the clamp of n cost no more than the listing.
    assert!(common <= bound, "the common path costs {common} > {bound}");
    assert_eq!(classification.branches, 0, "{classification:?}");
}
