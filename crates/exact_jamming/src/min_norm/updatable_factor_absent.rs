//! [`UpdatableFactor`] in a build without the `cholmod` feature: a type with no values, so
//! every use of it type-checks and none can run. [`UpdatableFactor::from_ldl`] always declines,
//! and the preconditioner stays bordered; `Params::validate` refuses `factor_updates` first,
//! with a sentence that names the feature.

/// Never constructed: factor updates need SuiteSparse's CHOLMOD (the `cholmod` feature).
pub(crate) enum UpdatableFactor {}

impl UpdatableFactor {
    pub fn from_ldl(_: &[usize], _: &[usize], _: &[usize], _: &[f64]) -> Result<Self, String> {
        Err("packbench was built without the `cholmod` feature".into())
    }

    pub fn len(&self) -> usize {
        match *self {}
    }

    pub fn add_row(&mut self, _: usize, _: &[(usize, f64)]) -> Result<(), String> {
        match *self {}
    }

    pub fn delete_row(&mut self, _: usize) -> Result<(), String> {
        match *self {}
    }

    pub fn solve_in_place(&mut self, _: &mut [f64]) {
        match *self {}
    }

    pub fn inverse_diagonal(&self, _: usize, _: f64, _: &mut [f64]) -> f64 {
        match *self {}
    }
}
