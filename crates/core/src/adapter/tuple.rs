//! Tuples of adapters are adapters: members run in order, each seeing the
//! effect of the ones before it; the report is the tuple of the members'
//! reports.

use super::{GainStep, NoiseAdapter, Posterior, PriorAdapter, PriorStep};
use crate::Real;

macro_rules! tuple_adapter {
    ($($name:ident $idx:tt),+) => {
        impl<T: Real, $($name: PriorAdapter<T>),+> PriorAdapter<T> for ($($name,)+) {
            const NEEDS_SPLIT: bool = false $(|| $name::NEEDS_SPLIT)+;
            #[inline(always)]
            fn after_predict(&mut self, prior: &mut PriorStep<T>) {
                $(self.$idx.after_predict(prior);)+
            }
        }

        impl<T: Real, const M: usize, $($name: NoiseAdapter<T, M>),+> NoiseAdapter<T, M>
            for ($($name,)+)
        {
            type Report = ($($name::Report,)+);
            const IS_IDENTITY: bool = true $(&& $name::IS_IDENTITY)+;

            #[inline(always)]
            fn before_gain(&mut self, step: &mut GainStep<T, M>, report: &mut Self::Report) {
                $(self.$idx.before_gain(step, &mut report.$idx);)+
            }

            #[inline(always)]
            fn after_update(&mut self, posterior: &Posterior<'_, T, M>, report: &mut Self::Report) {
                $(self.$idx.after_update(posterior, &mut report.$idx);)+
            }
        }
    };
}

tuple_adapter!(A 0);
tuple_adapter!(A 0, B 1);
tuple_adapter!(A 0, B 1, C 2);
tuple_adapter!(A 0, B 1, C 2, D 3);
tuple_adapter!(A 0, B 1, C 2, D 3, E 4);
tuple_adapter!(A 0, B 1, C 2, D 3, E 4, F 5);
