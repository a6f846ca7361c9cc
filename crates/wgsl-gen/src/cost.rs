//! A static operation count of a WGSL function, from naga's IR: how much work a call
//! costs, with every callee inlined (as GPU compilers do), to compare two functions'
//! costs in a test (for example a corrected model against the formula it extends).
//!
//! What counts, per expression that the function evaluates (naga `Emit`s it):
//! - **arithmetic**: `Binary`, `Unary`, `Select`, `Relational`, `Math`, `As` (conversions
//!   and bitcasts), one per component of the result (GPUs execute vector operations one
//!   scalar lane instruction per component);
//! - **indexing**: `Access` with a dynamic index (a register-indexed or scratch-memory
//!   load), one each;
//! - **branches**: one per `if`, `switch` and loop statement.
//!
//! Free: literals, constants, arguments, local variables and their loads and stores
//! (registers), constant-index accesses, swizzles, splats and composes (register moves).
//! Both branches of an `if` count, so the total is the static size of the inlined code —
//! an upper bound of what one call executes — and a loop's body counts once: a function
//! with a loop reports it in [`OperationCount::loops`], so that a caller knows the count is
//! per iteration there.

use std::collections::HashMap;

use naga::{Block, Expression, Handle, Statement, TypeInner};

use crate::ValidatedModule;

/// The operations of a function (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OperationCount {
    /// Arithmetic, comparison, selection and conversion operations, per component.
    pub arithmetic: usize,
    /// Dynamically indexed loads.
    pub indexing: usize,
    /// `if`, `switch` and loop statements.
    pub branches: usize,
    /// Loop statements (their bodies are counted once).
    pub loops: usize,
}

impl OperationCount {
    /// `arithmetic + indexing + branches`.
    pub fn total(&self) -> usize {
        self.arithmetic + self.indexing + self.branches
    }

    fn add(&mut self, other: Self) {
        self.arithmetic += other.arithmetic;
        self.indexing += other.indexing;
        self.branches += other.branches;
        self.loops += other.loops;
    }
}

/// The operations of the function called `name` in `validated`, callees inlined; `None`
/// when no function has that name.
pub fn operation_count(validated: &ValidatedModule, name: &str) -> Option<OperationCount> {
    let (handle, _) = validated.module.functions.iter().find(|(_, f)| f.name.as_deref() == Some(name))?;
    let mut memo = HashMap::new();
    Some(count_function(validated, handle, &mut memo))
}

fn count_function(
    validated: &ValidatedModule,
    handle: Handle<naga::Function>,
    memo: &mut HashMap<Handle<naga::Function>, OperationCount>,
) -> OperationCount {
    if let Some(&count) = memo.get(&handle) {
        return count;
    }
    let function = &validated.module.functions[handle];
    // WGSL forbids recursion, so the call graph is acyclic and this terminates.
    let count = count_block(validated, handle, &function.body, memo);
    memo.insert(handle, count);
    count
}

fn count_block(
    validated: &ValidatedModule,
    function: Handle<naga::Function>,
    block: &Block,
    memo: &mut HashMap<Handle<naga::Function>, OperationCount>,
) -> OperationCount {
    let mut count = OperationCount::default();
    for statement in block.iter() {
        match statement {
            Statement::Emit(range) => {
                for expression in range.clone() {
                    count.add(count_expression(validated, function, expression));
                }
            }
            Statement::Block(inner) => count.add(count_block(validated, function, inner, memo)),
            Statement::If { accept, reject, .. } => {
                count.branches += 1;
                count.add(count_block(validated, function, accept, memo));
                count.add(count_block(validated, function, reject, memo));
            }
            Statement::Switch { cases, .. } => {
                count.branches += 1;
                for case in cases {
                    count.add(count_block(validated, function, &case.body, memo));
                }
            }
            Statement::Loop { body, continuing, .. } => {
                count.branches += 1;
                count.loops += 1;
                count.add(count_block(validated, function, body, memo));
                count.add(count_block(validated, function, continuing, memo));
            }
            Statement::Call { function: callee, .. } => count.add(count_function(validated, *callee, memo)),
            _ => {}
        }
    }
    count
}

fn count_expression(
    validated: &ValidatedModule,
    function: Handle<naga::Function>,
    expression: Handle<Expression>,
) -> OperationCount {
    let module = &validated.module;
    let components = || match validated.info[function][expression].ty.inner_with(&module.types) {
        TypeInner::Vector { size, .. } => *size as usize,
        _ => 1,
    };
    match module.functions[function].expressions[expression] {
        Expression::Binary { .. }
        | Expression::Unary { .. }
        | Expression::Select { .. }
        | Expression::Relational { .. }
        | Expression::Math { .. }
        | Expression::As { .. } => OperationCount { arithmetic: components(), ..OperationCount::default() },
        Expression::Access { .. } => OperationCount { indexing: 1, ..OperationCount::default() },
        _ => OperationCount::default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ComposedShader;

    fn count(source: &str, name: &str) -> OperationCount {
        let module = ComposedShader::new("cost").with_part("cost.wgsl", source).validate().unwrap();
        operation_count(&module, name).unwrap()
    }

    #[test]
    fn counts_operations_per_component_and_inlines_callees() {
        let source = "
            fn axpy(a: f32, x: vec3<f32>, y: vec3<f32>) -> vec3<f32> { return a * x + y; }
            fn twice(x: vec3<f32>) -> f32 {
                let v = axpy(2.0, x, x);
                if v.x > 0.0 { return v.y; }
                return sqrt(v.z);
            }
            fn pick(values: array<f32, 4>, i: u32) -> f32 { var copy = values; return copy[i]; }
            fn total(n: u32) -> f32 {
                var sum = 0.0;
                for (var i = 0u; i < n; i++) { sum += f32(i); }
                return sum;
            }
        ";
        // a * x (3) + y (3).
        assert_eq!(count(source, "axpy"), OperationCount { arithmetic: 6, ..OperationCount::default() });
        // axpy (6), `>` (1), sqrt (1), one branch.
        assert_eq!(count(source, "twice"), OperationCount { arithmetic: 8, branches: 1, ..OperationCount::default() });
        assert_eq!(count(source, "pick"), OperationCount { indexing: 1, ..OperationCount::default() });
        let looped = count(source, "total");
        assert_eq!((looped.loops, looped.branches >= 2), (1, true), "{looped:?}");
        let module = ComposedShader::new("cost").with_part("cost.wgsl", source).validate().unwrap();
        assert_eq!(operation_count(&module, "missing"), None);
    }
}
