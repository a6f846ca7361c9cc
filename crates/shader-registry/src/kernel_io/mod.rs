//! The input and output structs of the test kernels, per module: test scaffolding, so they
//! live here rather than in the algorithm crates' APIs. Their WGSL declarations are
//! generated when a kernel is composed ([`TestKernel::shader`](crate::TestKernel::shader)).

pub mod ddm_tracer;
pub mod octahedral_map;
pub mod quadric_fit;
pub mod smith_micro;
