//! A registry line: a model's self-description and its plan builder. Model files define their
//! `ENTRY` constants with this type; only `registry.rs` lists them (so no model file imports
//! the registry).

use crate::error::Result;
use crate::model::ModelInfo;
use crate::params::Params;
use crate::plan::{Models, Plan, PlanFn};

/// One registry line: the description and the builder of the model's plan.
#[derive(Clone, Copy)]
pub struct Entry {
    pub info: ModelInfo,
    pub plan: PlanFn,
}

impl Entry {
    /// A registry line.
    pub const fn new(info: ModelInfo, plan: PlanFn) -> Self {
        Self { info, plan }
    }

    /// The plan from already resolved parameters.
    pub fn build_plan(&self, p: &Params, models: &dyn Models) -> Result<Plan> {
        (self.plan)(p, models)
    }
}
