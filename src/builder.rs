//! The builder style of the options structs: `with_<field>(self, value) -> Self` for each of
//! their fields, so that a caller outside the crate (the CLI, the Python binding, a CAD
//! pipeline) writes `DesignOptions::default().with_tol_mm(0.1).with_module_mm(Some(2.0))`
//! although the structs are `#[non_exhaustive]`.

/// Implements `with_<field>` for the listed `field: Type` pairs of an options struct; each sets
/// the field and returns the struct (its doc points to the field's, which gives unit and default).
macro_rules! with_fields {
    ($ty:ty { $($with:ident => $field:ident: $t:ty),* $(,)? }) => {
        impl $ty {
            $(
                #[doc = concat!("Sets [`Self::", stringify!($field), "`].")]
                #[must_use]
                pub fn $with(mut self, value: $t) -> Self {
                    self.$field = value;
                    self
                }
            )*
        }
    };
}
pub(crate) use with_fields;
