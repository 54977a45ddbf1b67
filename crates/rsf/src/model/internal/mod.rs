//! Faults inside the body: the mesh split along them and the mean–jump change of variables
//! the model's matrices are expressed in (docs/faults-inside.md, docs/math.md §15–16) —
//! one fault, or a network of several (disjoint; in 2-D also a branch or a crossing,
//! docs/fault-networks.md).

pub(crate) mod cuts;
mod fault;
mod hierarchy;

pub(crate) use cuts::{FaultCut, NetworkSplit};
pub use fault::{FaultSide, InternalFault, SlipNode};
