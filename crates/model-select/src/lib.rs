//! *Model no more than a scene needs*: given measured tables of what each representation
//! of an object costs and how far its image is from the truth, the cheapest one that meets
//! an error budget.
//!
//! A [`Table`] holds [`Measurement`]s: per object (a mesostructure, a grain type, a
//! material), per representation (a method and its parameters, named), per condition (the
//! camera's effect on the object, e.g. pixels per voxel), the image error under each
//! [`Metric`] and a cost (its unit named by the table). Tables are produced by named
//! commands and carry a [`Stamp`]: the command, the commit, the adapter and a
//! [`fingerprint`] of the sources that produced them, so that a test can tell a stale
//! table from a fresh one ([`Table::is_fresh`]).
//!
//! [`Table::select`] answers *which representation for this object, seen at this
//! condition, within this [`Budget`]*: among the rows measured at the least condition at
//! or above the one asked (error grows with the condition by the table's own convention,
//! so this side is the conservative one), the cheapest whose error is within budget. No
//! constant decides: only the table. [`pareto_front`] gives the candidates that no other is
//! both cheaper and more accurate than; a [`Choice`] says whether it lies on it (a cheapest
//! candidate within budget always does).
//!
//! ```
//! use model_select::{Budget, Measurement, Metric, Stamp, Table};
//!
//! let row = |representation: &str, flip: f64, cost: f64| Measurement {
//!     object: "ball".into(),
//!     representation: representation.into(),
//!     condition: 1.0,
//!     flip,
//!     ssim_loss: flip / 2.0,
//!     cost,
//! };
//! let stamp = Stamp {
//!     command: "cargo xtask example".into(),
//!     commit: "0123abc".into(),
//!     adapter: "CPU".into(),
//!     sources: "0000000000000000".into(),
//! };
//! let table = Table::new(
//!     "example",
//!     stamp,
//!     "pixels per voxel",
//!     "ns per ray",
//!     vec![row("coarse", 0.20, 1.0), row("medium", 0.05, 3.0), row("exact", 0.01, 9.0)],
//! )?;
//! let choice = table.select("ball", 0.5, Budget::new(Metric::Flip, 0.1)?)?;
//! assert_eq!(choice.measurement.representation, "medium");
//! assert!(choice.on_front);
//! // Nothing meets 0.001: an error that says how close the table comes.
//! let error = table.select("ball", 0.5, Budget::new(Metric::Flip, 0.001)?).unwrap_err();
//! assert!(error.to_string().contains("least ꟻLIP measured is 0.01"), "{error}");
//! # Ok::<(), model_select::SelectError>(())
//! ```
//!
//! # API
//!
//! - [`Metric`], [`Budget`] (validated): the error measure and its bound.
//! - [`Measurement`], [`Stamp`], [`Table`] (validated, CSV in and out: [`Table::to_csv`],
//!   [`Table::from_csv`]), [`fingerprint`] of source files.
//! - [`Table::select`] → [`Choice`]; [`pareto_front`].
//! - [`Table::check_held_out`] → [`HeldOutCheck`]: a choice measured where the table was
//!   not (another camera, another realization).
//! - [`prediction_bound`]: the margin a row needs for a camera it was not measured from.
//! - [`SelectError`]: every failure, naming the field, file, line or object.

mod budget;
mod error;
mod fingerprint;
mod held_out;
mod pareto;
mod prediction;
mod select;
mod table;

pub use budget::{Budget, Metric};
pub use error::SelectError;
pub use fingerprint::fingerprint;
pub use held_out::HeldOutCheck;
pub use pareto::pareto_front;
pub use prediction::prediction_bound;
pub use select::Choice;
pub use table::{Measurement, Stamp, Table};
