//! Allocation-free dense kernels on fixed-size matrices: checked Cholesky
//! factorisations, checked rank-one updates and downdates, Householder
//! triangularisation of a factor plus extra columns, triangular solves and
//! the symmetric products the update forms need.
//!
//! Every factor here is **lower triangular** with a non-negative diagonal:
//! `P = S Sᵀ`.

mod cholesky;
mod factored;
mod ldl;
mod product;
mod rank_one;
mod symmetric;
mod triangular;
mod triangularize;

pub use cholesky::{cholesky, cholesky_semidefinite, NotPositiveDefinite};
pub use factored::FactoredCovariance;
pub use product::mul_vector;
pub use rank_one::{rank_one_downdate, rank_one_update, weighted_rank_one};
pub use symmetric::{
    add_weighted_outer_lower, joseph_expanded, joseph_factored_noise, mirror_lower, sandwich,
    sandwich_transposed,
};
pub use triangular::{solve_lower, solve_lower_transpose};
pub use triangularize::add_columns;

pub(crate) use cholesky::cholesky_semidefinite_in_place;
pub(crate) use ldl::Ldl;
pub(crate) use product::{add_products, add_scaled, mul_lower};
pub(crate) use rank_one::{
    downdate_columns_in_place, downdate_in_place, update_in_place, weighted_rank_one_in_place,
};
pub(crate) use symmetric::{joseph_factored_noise_negated, lower_times_transpose, sandwich_into};
pub(crate) use triangular::solve_right_cholesky;
pub(crate) use triangularize::add_columns_by_rows;
